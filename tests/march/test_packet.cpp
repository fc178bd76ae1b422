// Packets through the batched tape take the one-point path's decisions: for the camera rays of a strided
// subset of every built-in scene's pixels, the same outcome, steps, evaluations and t (bit for bit: both
// evaluate the same floats, see sdf/test_batch.cpp), the same central normals at the hits and the same hard
// shadow rays toward every light; a tape one rounding apart is caught.
#include "marchcheck/march/camera.hpp"
#include "marchcheck/march/effects.hpp"
#include "marchcheck/march/packet.hpp"
#include "marchcheck/march/render.hpp"
#include "marchcheck/sdf/builtin_scenes.hpp"

#include "builtin_param.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace marchcheck::march {
namespace {

constexpr int kStride = 7;  // every 7th pixel of every 7th row of a 256 x 144 image: 777 rays per scene

struct Mismatches {
  int march = 0, normals = 0, shadows = 0, hits = 0;
};

template <class T>
bool same(const RayRecord<T>& a, const RayRecord<T>& b) {
  return a.outcome == b.outcome && a.steps == b.steps && a.evals == b.evals && a.t == b.t &&
         a.min_abs_f == b.min_abs_f && a.t_at_min == b.t_at_min;
}

// Marches the scene's rays through packet_tape and one at a time through point_tape and counts disagreements.
template <class T>
Mismatches compare(const sdf::Scene& scene, const sdf::Tape& packet_tape, const sdf::Tape& point_tape) {
  using V = glm::vec<3, T>;
  const int w = 256, h = 144;
  const Camera camera(scene.camera, w, h);
  const MarchContext c = march_context(camera, scene);
  const auto& s = scene.march;
  const TapeField field{&point_tape};
  std::vector<PacketRay<T>> rays;
  for (int y = 0; y < h; y += kStride)
    for (int x = 0; x < w; x += kStride) {
      const Ray ray = camera.ray(x + 0.5, y + 0.5);
      rays.push_back({V(ray.origin), V(ray.direction), s.max_dist});
    }
  std::vector<RayRecord<T>> records(rays.size());
  march_packet(packet_tape, rays.data(), records.data(), static_cast<int>(rays.size()), s, c);

  Mismatches m;
  std::vector<V> points;
  std::vector<T> eps;
  for (size_t i = 0; i < rays.size(); ++i) {
    m.march += !same(records[i], march<T>(field, rays[i].origin, rays[i].direction, s, c));
    if (records[i].outcome != Outcome::hit) continue;
    points.push_back(rays[i].origin + rays[i].direction * records[i].t);
    eps.push_back(T(s.normal_eps));
  }
  m.hits = static_cast<int>(points.size());
  std::vector<NormalResult<T>> normals(points.size());
  central_normals_packet(packet_tape, points.data(), eps.data(), normals.data(), m.hits);
  for (size_t i = 0; i < points.size(); ++i) {
    const auto one = estimate_normal(field, points[i], NormalMethod::central, eps[i]);
    m.normals += one.n != normals[i].n || one.evals != normals[i].evals;
  }
  for (const auto& light : scene.lights) {
    if (light.shadow == sdf::ShadowMode::none) continue;
    sdf::Light hard = light;
    hard.shadow = sdf::ShadowMode::hard;
    std::vector<PacketRay<T>> shadow_rays;
    for (size_t i = 0; i < points.size(); ++i) {
      const V to_light = light.type == sdf::LightType::point
                             ? glm::normalize(V(light.position_at(scene.time)) - points[i])
                             : -glm::normalize(V(light.direction));
      const T dist = light.type == sdf::LightType::point ? glm::length(V(light.position_at(scene.time)) - points[i])
                                                         : std::numeric_limits<T>::infinity();
      const auto start = shadow_start(points[i], normals[i].n, dist, T(1), hard, s, c);
      shadow_rays.push_back({start.origin, to_light, start.max_dist});
    }
    std::vector<RayRecord<T>> shadow(shadow_rays.size());
    march_packet(packet_tape, shadow_rays.data(), shadow.data(), static_cast<int>(shadow.size()), s, c);
    for (size_t i = 0; i < shadow_rays.size(); ++i) {
      MarchSettings own = s;
      own.max_dist = shadow_rays[i].max_dist;
      m.shadows += !same(shadow[i], march<T>(field, shadow_rays[i].origin, shadow_rays[i].direction, own, c));
    }
  }
  return m;
}

template <class T>
Mismatches compare(const sdf::Scene& scene) {
  const sdf::Tape tape = sdf::compile(scene);
  return compare<T>(scene, tape, tape);
}

class EveryBuiltinPacket : public ::testing::TestWithParam<std::string> {};

// In the scene's own marcher, over-relaxed (its packets keep each lane's factor and step back where the unbounding
// spheres part, as SphereTrace does), in fixed steps with bisection (lanes stepping by FixedTrace's rule) and with
// its hits refined by a secant step (one batch more at the roots once the lanes ended), own and relaxed, and
// clipped to the field's bounds (lanes start and end where the ray crosses the box). Broken
// variants: a relaxed lane that never steps back (march-packet-relaxed-no-step-back), one whose fallback forgets
// the last forward step (march-packet-relaxed-stale), a bisection that keeps the wrong half
// (march-fixed-bisects-wrong-half), a secant root kept unchecked (march-packet-secant-unchecked), compaction that
// leaves a lane's last forward f behind (march-packet-compaction-drops-prev-f), lanes marching the whole ray
// whatever the clip (march-packet-clip-ignored), relaxed lanes whose unbounding spheres ignore L on the L > 1
// built-ins (march-packet-relaxed-radius-unscaled), relaxed lanes whose unbounding spheres ignore a declared
// perturbation (march-packet-perturbed-radii-plain; on the fields that declare one, stepped by it), lanes that take
// only the plain step where a perturbation is declared (march-packet-perturbation-never-seen), compaction that leaves
// a vector of running lanes behind where lanes before it ended (march-packet-compaction-vector-left-behind), lanes
// whose end is stored only where the first lane of their vector ends (march-packet-ended-lanes-unrecorded), running
// lanes counted in only the low half of a vector (march-packet-lanes-set-half, on AVX2
// march-packet-lanes-set-half-avx2), AVX2's compaction reading its table's lane numbers wrongly
// (march-packet-compress-word-order), and, in double (float64: own and relaxed), keeping half of each lane's words
// (march-packet-compress-double-half) or a lane's low word twice (march-packet-compress-low-word-twice).
TEST_P(EveryBuiltinPacket, SameOutcomesStepsEvaluationsNormalsAndShadowsAsOneRayAtATime) {
  for (const std::string marcher : {"own", "relaxed", "fixed", "secant", "relaxed+secant", "clip", "relaxed+perturbed",
                                    "float64", "relaxed+float64"}) {
    sdf::Scene scene = sdf::builtin_scene(GetParam());
    if (marcher.ends_with("float64")) scene.march.precision = sdf::Precision::float64;
    if (marcher.ends_with("perturbed")) {
      if (!sdf::derive_info(scene.root, scene.time).perturbation) continue;
      sdf::apply_setting(scene, "step_bound", "perturbed");
    }
    if (marcher.ends_with("secant")) sdf::apply_setting(scene, "refine", "secant");
    if (marcher == "clip") sdf::apply_setting(scene, "clip", "bounds");
    if (marcher.starts_with("relaxed") || marcher == "fixed")
      sdf::apply_setting(scene, "marcher", marcher.substr(0, marcher.find('+')));
    const Mismatches m = scene.march.precision == sdf::Precision::float64 ? compare<double>(scene) : compare<float>(scene);
    EXPECT_EQ(m.march, 0) << marcher;
    EXPECT_EQ(m.normals, 0) << marcher;
    EXPECT_EQ(m.shadows, 0) << marcher;
  }
}

INSTANTIATE_TEST_SUITE_P(All, EveryBuiltinPacket, ::testing::ValuesIn(sdf::builtin_scene_names()),
                         testing::builtin_param_name);

// The comparison can fail: packets through lee-flat's sphere moved up by one float rounding at 1 (2^-23, the
// gap above 1.0f) end some rays elsewhere and tilt some normals.
TEST(Packet, ATapeOneRoundingApartIsCaught) {
  sdf::Scene scene = sdf::builtin_scene("lee-flat");
  const sdf::Tape point_tape = sdf::compile(scene.root);
  scene.root.children[0] = sdf::translate({0, 0x1p-23, 0}, scene.root.children[0]);
  const sdf::Tape packet_tape = sdf::compile(scene.root);
  const Mismatches m = compare<float>(scene, packet_tape, point_tape);
  EXPECT_GT(m.hits, 100);
  EXPECT_GT(m.march, 0);
  EXPECT_GT(m.normals, 0);
}

// Each ray's packet record beside its one-point march (march() with the ray's own max_dist), in ray order.
std::vector<std::pair<RayRecord<float>, RayRecord<float>>> packet_and_alone(const sdf::Tape& tape,
                                                                         const std::vector<PacketRay<float>>& rays,
                                                                         const MarchSettings& s, const MarchContext& c) {
  const auto one_point = [&tape](glm::vec3 p) { return sdf::evaluate(tape, p); };
  std::vector<RayRecord<float>> records(rays.size());
  march_packet(tape, rays.data(), records.data(), static_cast<int>(rays.size()), s, c);
  std::vector<std::pair<RayRecord<float>, RayRecord<float>>> both;
  for (size_t i = 0; i < rays.size(); ++i) {
    MarchSettings own = s;
    own.max_dist = rays[i].max_dist;
    both.emplace_back(records[i], march<float>(one_point, rays[i].origin, rays[i].direction, own, c));
  }
  return both;
}

// Rays march_packet hands to march() (settings that make no sense, a non-positive max_dist, a degenerate ray: no
// direction, or a NaN or infinity in any one of the six components) end as march() ends them: invalid, after no
// evaluation. A direction along one axis is not degenerate. Rays marched in the same packet after the degenerate
// ones (which leave its lanes) end as they would alone. Broken variants: a ray whose direction's z is not tested
// finite, one at a time and in the lanes (march-ray-degenerate-skips-dz); a ray along one axis taken for no
// direction (march-ray-degenerate-direction-any-zero); a degenerate ray marched in the lanes as well
// (march-packet-degenerate-kept); the lanes after it keeping their neighbour's max_dist
// (march-packet-degenerate-shift-forgets-max-dist); a packet with a ray of no length filled whole, so that ray is
// marched a step (march-packet-whole-ignores-reach).
TEST(Packet, InvalidSettingsAndRaysEndInvalidAsOneRayAtATime) {
  const sdf::Scene scene = sdf::builtin_scene("lee-flat");
  const sdf::Tape tape = sdf::compile(scene.root);
  const MarchContext c;
  std::vector<PacketRay<float>> rays = {{glm::vec3(0, 1, 0), glm::vec3(0, 0, 1), 100},
                                        {glm::vec3(0, 1, 0), glm::vec3(0, 0, 1), 0},
                                        {glm::vec3(0, 1, 0), glm::vec3(0), 100}};
  for (int k = 0; k < 6; ++k) {
    PacketRay<float> ray{glm::vec3(0, 1, 0), glm::vec3(0, 0, 1), 100};
    (k < 3 ? ray.origin : ray.direction)[k % 3] = k % 2 ? INFINITY : NAN;
    rays.push_back(ray);
  }
  const size_t degenerate_end = rays.size();
  for (int k = 0; k < 5; ++k) rays.push_back({glm::vec3(0, 2, -3), glm::vec3(0.2f * static_cast<float>(k), -0.5f, 1), 1.0 + 2.0 * k});
  for (const double step_scale : {1.0, double(NAN)}) {
    MarchSettings s = scene.march;
    s.step_scale = step_scale;
    const auto both = packet_and_alone(tape, rays, s, c);
    for (size_t i = 0; i < rays.size(); ++i) {
      const auto& [packet, alone] = both[i];
      EXPECT_TRUE(same(packet, alone) || (std::isnan(packet.t) && std::isnan(alone.t))) << i;
      EXPECT_EQ(packet.outcome == Outcome::invalid, std::isnan(step_scale) || (i > 0 && i < degenerate_end)) << i;
      if (packet.outcome == Outcome::invalid) {
        EXPECT_EQ(packet.evals, 0) << i;
      }
    }
  }
}

// Lanes at their rules' edges, against march() on the plane y = 0 (f = y exactly): fixed
// steps, one landing exactly on the surface with a zero threshold (not a hit: the next step crosses and the bracket
// starts there), bisections cut short by max_steps (the ray ends at the bracket's outer end); sphere traced and
// relaxed hits refined by a secant step, some on their last allowed step (no extra evaluation then); starts
// inside, one 1.5 thresholds deep; a ray away from the ground; one whose first relaxed step passes max_dist (13)
// where a plain step does not (RelaxedTracing in test_marchers.cpp). Broken variants: an inside test at twice the
// depth (march-packet-inside-threshold), a relaxed lane's miss decided on its over-relaxed step
// (march-packet-relaxed-miss-on-relaxed-step), a fixed lane whose bracket forgets a step of f = 0
// (march-packet-fixed-zero-step-forgotten), one cut short at the midpoint it would evaluate next
// (march-packet-fixed-cut-short-at-mid), a secant step one past max_steps (march-packet-secant-past-last-step),
// compaction leaving the lanes' next points behind (march-packet-compaction-leaves-points), compaction taking the
// padding past the packet's last ray for ended rays (march-packet-compaction-ended-past-count), the first padding
// lane counted as one of the packet's rays (march-packet-in-packet-one-past).
TEST(Packet, LanesEndAsOneRayAtATimeAtTheRulesEdges) {
  const sdf::Tape tape = sdf::compile(sdf::plane({0, 1, 0}, 0));
  const MarchContext c;
  const std::vector<PacketRay<float>> rays = {{glm::vec3(5, 1, 0), glm::vec3(0, -1, 0), 100},
                                              {glm::vec3(5, 1, 3), glm::vec3(0.6f, -0.8f, 0), 100},
                                              {glm::vec3(5, -1, 0), glm::vec3(0, -1, 0), 100},
                                              {glm::vec3(5, -0.015f, 0), glm::vec3(0, -1, 0), 100},
                                              {glm::vec3(5, 1, -3), glm::vec3(0, 1, 0), 3},
                                              {glm::vec3(5, 10, 0), glm::vec3(0.6f, -0.8f, 0), 13}};
  int cut_short = 0, zero_steps = 0, hits_on_last_step = 0, shallow_inside = 0;
  for (const Marcher marcher : {Marcher::fixed, Marcher::sphere, Marcher::relaxed})
    for (const double eps : {0.0, 0.01})
      for (const double step : {0.5, 0.3})
        for (const int max_steps : {3, 4, 5, 8, 200}) {
          MarchSettings s;
          s.marcher = marcher;
          s.refine = marcher == Marcher::fixed ? sdf::HitRefine::none : sdf::HitRefine::secant;
          s.hit_eps = eps;
          s.fixed_step = step;
          s.max_steps = max_steps;
          const auto both = packet_and_alone(tape, rays, s, c);
          for (size_t i = 0; i < rays.size(); ++i) {
            const auto& [packet, alone] = both[i];
            EXPECT_TRUE(same(packet, alone)) << "ray " << i << " marcher " << static_cast<int>(marcher) << " eps "
                                             << eps << " step " << step << " max_steps " << max_steps << ": t "
                                             << packet.t << " against " << alone.t;
            const bool fixed = marcher == Marcher::fixed;
            cut_short += fixed && alone.outcome == Outcome::miss_steps && i < 2 && alone.t < 2;
            shallow_inside += i == 3 && eps > 0 && alone.outcome == Outcome::inside;
            zero_steps += fixed && eps == 0 && step == 0.5 && i == 0 && alone.outcome == Outcome::hit;
            hits_on_last_step += !fixed && alone.outcome == Outcome::hit && alone.steps == max_steps;
          }
        }
  // Each edge was reached (else the case tests nothing).
  EXPECT_GT(cut_short, 0);
  EXPECT_GT(zero_steps, 0);
  EXPECT_GT(hits_on_last_step, 0);
  EXPECT_GT(shallow_inside, 0);
}

}  // namespace
}  // namespace marchcheck::march
