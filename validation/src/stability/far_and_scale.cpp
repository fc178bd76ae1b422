// Far coordinates (float, double and the camera-relative fix) and scales from 1e-8 to 1e8.
#include "battery.hpp"

#include "marchcheck/march/camera.hpp"
#include "marchcheck/march/camera_relative.hpp"
#include "marchcheck/march/normals.hpp"
#include "marchcheck/sdf/builtin_scenes.hpp"
#include "marchcheck/sdf/noise.hpp"
#include "marchcheck/validation/reference.hpp"
#include "marchcheck/validation/validate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <span>
#include <string>
#include <utility>

namespace marchcheck::validation::stability {

namespace {

// ---- far coordinates: float, double and the camera-relative fix ----

struct FarErrors {
  double t_err = 0, normal_deg = 0;
  int missed = 0, t_off = 0, normal_off = 0;  // rays that did not hit; hits beyond the t bound; beyond 1 degree
  int wrong = 0;                              // rays with any of the three
};

// The broken variants of one precision's march: no budget, the hit lifted off the surface, a facing normal.
enum class FarBreak { none, one_step, hit_lifted, normal_facing };

FarBreak far_break(const Run& r, const std::string& precision) {
  for (const auto& [name, kind] : {std::pair{".one_step", FarBreak::one_step}, std::pair{".hit_lifted", FarBreak::hit_lifted},
                                   std::pair{".normal_facing", FarBreak::normal_facing}})
    if (r.as(precision + name)) return kind;
  return FarBreak::none;
}

constexpr double kFarEps = 1e-4;

// A unit sphere at offset seen from 4 units away: rays marched in T, in world coordinates or camera-relative.
template <class T>
FarErrors far_errors(dvec3 offset, bool relative, FarBreak broken = FarBreak::none) {
  using V = glm::vec<3, T>;
  const sdf::Node world = sdf::translate(offset, sdf::sphere(1));
  const dvec3 eye = offset + dvec3(0, 0, 4);
  const sdf::Tape tape = sdf::compile(relative ? march::camera_relative(world, eye) : world);
  const TapeField field{&tape};
  const Reference ref(world, 0);
  MarchSettings ms;
  ms.hit_eps = kFarEps;
  ms.max_steps = broken == FarBreak::one_step ? 1 : 1000;
  FarErrors out;
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 6; ++i) {
      const dvec3 d = glm::normalize(offset + dvec3((i - 2.5) / 4, (j - 2.5) / 4, 0) - eye);
      const ReferenceHit exact = ref.first_hit(eye, d, 100);
      const V origin = relative ? V(0) : V(eye);
      auto rec = march::march<T>(field, origin, V(d), ms, {});
      if (rec.outcome != Outcome::hit) {
        ++out.missed;
        ++out.wrong;
        continue;
      }
      if (broken == FarBreak::hit_lifted) rec.t -= T(10 * kFarEps);  // backed off 10 hit_eps along the ray
      const double t_err = std::abs(double(rec.t) - exact.t);
      const double cos_i = -glm::dot(d, exact.normal);
      const dvec3 n = broken == FarBreak::normal_facing
                          ? -d  // the shortcut "the surface faces the eye"
                          : dvec3(march::estimate_normal(field, origin + V(d) * rec.t, sdf::NormalMethod::central, T(1e-3)).n);
      const double nd = glm::dot(n, n) > 0 ? angle_deg(n, exact.normal) : 180.0;
      // hit_eps along the normal is hit_eps / cos along the ray, plus float rounding of local coordinates (|q| <= 5).
      // Central differences at 1e-3 on a unit sphere are far under a degree off.
      const bool t_off = t_err > kFarEps / cos_i + march::tolerance::kFloatRoundingNearUnit, normal_off = !(nd <= 1);
      out.t_off += t_off;
      out.normal_off += normal_off;
      out.wrong += t_off || normal_off;
      out.t_err = std::max(out.t_err, t_err);
      out.normal_deg = std::max(out.normal_deg, nd);
    }
  return out;
}

void far_record(Run& r, const std::string& prefix, const FarErrors& e) {
  r.m[prefix + ".t_err"] = e.t_err;
  r.m[prefix + ".normal_err_deg"] = e.normal_deg;
  r.m[prefix + ".wrong"] = e.wrong;
}

// One precision's three clauses at one offset: every ray hits, within the t bound, with its normal within 1 degree.
void far_require(Run& r, const std::string& precision, dvec3 offset, const FarErrors& e) {
  const std::string at = precision + " at offset " + num(glm::length(offset)) + ": ";
  r.require(precision + ".hits", e.missed == 0, at + std::to_string(e.missed) + " rays missed");
  r.require(precision + ".t", e.t_off == 0, at + std::to_string(e.t_off) + " hits beyond hit_eps / cos + 1e-5");
  r.require(precision + ".normal", e.normal_off == 0, at + std::to_string(e.normal_off) + " normals off by over 1 degree");
}

// The variants that break one clause of far_require in one precision.
std::vector<StabilityVariant> far_variants(const std::string& precision) {
  return {{precision + ".one_step", precision + ".hits", precision + " marched with max_steps 1"},
          {precision + ".hit_lifted", precision + ".t", precision + " hits backed off 10 hit_eps along the ray"},
          {precision + ".normal_facing", precision + ".normal", precision + " normals taken as the ray reversed"}};
}

// The renderer's answer (camera-relative float; naive: float in world coordinates) and double must hold.
void far_offsets(Run& r, const std::vector<dvec3>& offsets, bool label_by_decade) {
  for (const dvec3& off : offsets) {
    const std::string at = label_by_decade ? decade(glm::length(off)) + "." : "";
    const FarErrors fl = far_errors<float>(off, !r.naive(), far_break(r, "float"));
    const FarErrors db = far_errors<double>(off, false, far_break(r, "double"));
    far_record(r, at + (r.naive() ? "float_world" : "float_camera_relative"), fl);
    far_record(r, at + "double", db);
    far_require(r, "float", off, fl);
    far_require(r, "double", off, db);
  }
}

std::vector<dvec3> decade_offsets() {
  std::vector<dvec3> out;
  for (int k = 1; k <= 7; ++k) out.push_back(dvec3(1, 1, 1) * (std::pow(10.0, k) / std::sqrt(3.0)));
  return out;
}

// Double holds at every offset; float in world coordinates breaks down where its spacing passes hit_eps.
void far_double(Run& r, const StabilityOptions&) {
  double breakdown = 0, predicted = 0;
  for (const dvec3& off : decade_offsets()) {
    // Float's spacing at the coordinates: once it passes hit_eps, rounding alone moves hits off by more.
    const float c = static_cast<float>(off.x);
    if (predicted == 0 && std::nextafter(c, INFINITY) - c > kFarEps) predicted = glm::length(off);
    const std::string at = decade(glm::length(off)) + ".";
    const FarErrors fl = far_errors<float>(off, false);
    const FarErrors db = r.naive() ? fl : far_errors<double>(off, false, far_break(r, "double"));
    far_record(r, at + "float_world", fl);
    far_record(r, at + (r.naive() ? "float_as_double" : "double"), db);
    if (fl.wrong > 0 && breakdown == 0) breakdown = glm::length(off);
    far_require(r, "double", off, db);
  }
  r.m["float_world.breakdown_offset"] = breakdown;
  r.m["float_world.breakdown_predicted"] = predicted;
}

// ---- far coordinates in the renderer ----

// Scenes moved to offsets 1e1..1e7 with their cameras and lights, rendered in camera coordinates, against their
// renders at the origin: pixels apart by over one 8-bit level. crum-smooth is lit by four point lights (the lights'
// frame); lee-textured has planar and spherical textures (the textures' frame; the offsets (1, 0.2, -1) 10^k keep
// the ground's period 5 in x and z). Measured: no pixel apart at any offset; in world coordinates crum-smooth is
// 4.6% to 8.7% apart from 1e3 on, lee-textured 26% at 1e6. Broken variants beside the battery's: the setting ignored
// (march-coordinates-ignored), rays, lights or textures in the wrong frame (march-relative-rays-from-world,
// march-relative-lights-in-world, march-relative-texture-relative), OpenImageIO's float coordinates unwrapped
// (march-texture-wrapped-in-float).
void far_render(Run& r, const StabilityOptions&) {
  for (const char* name : {"crum-smooth", "lee-textured"}) {
    const sdf::Scene near = sdf::scaled_to_width(sdf::builtin_scene(name), 96);
    const march::Image at_origin = march::render(near).color;
    for (int k = 1; k <= 7; ++k) {
      const double ten_k = std::pow(10.0, k);
      const dvec3 offset = dvec3(1, 0.2, -1) * ten_k;
      sdf::Scene far = sdf::moved_by(near, offset);
      far.march.coordinates = r.naive() ? sdf::Coordinates::world : sdf::Coordinates::camera;
      if (r.as("placement_rounded")) far.root = sdf::translate(offset * (1 + 0x1p-24), near.root);
      const march::Image difference = color_difference(march::render(far).color, at_origin);
      const double apart = static_cast<double>(std::count_if(difference.pixels.begin(), difference.pixels.end(),
                                                             [](float d) { return !(d <= 1.0f / 255); })) /
                           static_cast<double>(difference.pixels.size());
      r.m[std::string(name) + "." + decade(ten_k) + ".pixels_apart"] = apart;
      r.require("pixels", apart <= 0.002,
                std::string(name) + " at offset " + num(ten_k) + ": " + num(100 * apart) + "% of pixels apart");
    }
  }
}

// ---- far coordinates in a height field's hash ----

// lee-terrain's height field in float against double at points on circles of radius R about the origin (its
// height is -f at y = 0): the largest difference, the terrain's own height gap between the precisions.
double height_gap(const sdf::Tape& terrain, double radius) {
  double gap = 0;
  for (int i = 0; i < 64; ++i) {
    const double a = 2 * kPi * i / 64;
    const dvec3 p(radius * std::cos(a), 0, radius * std::sin(a));
    gap = std::max(gap, std::abs(double(sdf::evaluate(terrain, vec3(p))) - sdf::evaluate(terrain, p)));
  }
  return gap;
}

// The splitmix hash (lee-terrain's fix) is the same function in both precisions: its float terrain is double's
// within the rounding of the point, 16 unit roundoffs of 1 + R times the field's Lipschitz bound. The seed's sin
// hash is not (sin of |c| 55, times 43758, keeps a few digits in float): beside it, how far from the origin its
// gap first reaches 1e-3, 1e-2 and 1e-1 of the terrain's 0.56 amplitude (radii 0.1 to 1e5 in quarter decades).
// Measured: splitmix 6e-9 at radius 0.1 to 6.3e-4 at 1e5 (the point's own rounding); the sin hash reaches 1e-3
// at radius 0.18, 1e-2 at 1 and 1e-1 at 5.6 (its first lattice cells off the origin), and is another terrain,
// 0.3 to 0.4 apart, from 10 on.
void far_terrain_hash(Run& r, const StabilityOptions&) {
  const sdf::Scene lee = sdf::builtin_scene("lee-terrain");
  const sdf::Node& ground = lee.root.children[1].children[0];  // under translate(0, -1.2, 0)
  const std::span<const double> octaves = ground.param("octaves");
  const auto terrain = [&](sdf::NoiseHash hash) {
    return sdf::make(sdf::Op::heightfield, {{"hash", {static_cast<double>(hash)}},
                                           {"octaves", std::vector<double>(octaves.begin(), octaves.end())}});
  };
  const sdf::Node fixed = terrain(r.naive() ? sdf::NoiseHash::seed_sin : sdf::NoiseHash::splitmix);
  const sdf::Tape fixed_tape = sdf::compile(fixed), seed_tape = sdf::compile(terrain(sdf::NoiseHash::seed_sin));
  const double lipschitz = sdf::derive_info(fixed).lipschitz, u = std::numeric_limits<float>::epsilon();
  std::map<double, double> reach = {{1e-3, 0}, {1e-2, 0}, {1e-1, 0}};  // gap size: first radius reaching it
  for (int k = -4; k <= 20; ++k) {
    const double radius = std::pow(10.0, k / 4.0);
    const double seed_gap = height_gap(seed_tape, radius);
    for (auto& [size, at] : reach)
      if (at == 0 && seed_gap >= size) at = radius;
    if (k % 4 != 0) continue;  // the decades: the fixed hash's clause and both gaps
    const double gap = height_gap(fixed_tape, radius);
    const double rounding = 16 * u * (r.as("rounding_at_origin") ? 1 : 1 + radius) * lipschitz;
    r.m["splitmix." + decade(radius) + ".height_gap"] = gap;
    r.m["seed_sin." + decade(radius) + ".height_gap"] = seed_gap;
    r.require("height", gap <= rounding,
              "height gap " + num(gap) + " at radius " + num(radius) + ", past the rounding " + num(rounding));
  }
  for (const auto& [size, at] : reach) r.m["seed_sin.reach_" + decade(size)] = at;
}

// ---- scales from 1e-8 to 1e8 ----

// A sphere of radius S seen from 4 S: rays through its inner disk must hit within the threshold, rays past its
// silhouette must miss. Records the worst relative t error and each clause's count of wrong rays.
void scale_errors(Run& r, const std::string& label, double scale, march::EpsMode mode) {
  const sdf::Node node = sdf::sphere(scale);
  const sdf::Tape tape = sdf::compile(node);
  const TapeField field{&tape};
  const Reference ref(node, 0);
  sdf::CameraSpec spec;
  spec.position = {0, 0, 4 * scale};
  spec.fov_deg = 40;
  const march::Camera camera(spec, 64, 64);
  const march::MarchContext ctx = march::march_context(camera);
  MarchSettings ms;
  ms.eps_mode = r.naive() ? march::EpsMode::absolute : mode;
  ms.hit_eps = r.naive() ? 1e-3 : 1e-4;  // naive: the absolute epsilon that suits unit scenes
  ms.max_dist = 10 * scale;
  ms.max_steps = 1000;
  const double reference_max_dist = ms.max_dist;
  if (r.as("max_dist_short")) ms.max_dist = 2 * scale;  // a max_dist left unscaled: short of the sphere at 3 S
  int missed = 0, t_off = 0, outer_hit = 0;
  double worst = 0;
  const dvec3 eye = spec.position;
  for (int j = 0; j < 7; ++j)
    for (int i = 0; i < 7; ++i) {
      // Inner disk (radius 0.8 S at the centre plane) and a ring outside the silhouette (1.3 S).
      const double a = 2 * kPi * (i + 7 * j) / 49, rr = (i + j) % 2 ? 0.8 * scale * (j + 1) / 7 : 1.3 * scale;
      const dvec3 d = glm::normalize(dvec3(rr * std::cos(a), rr * std::sin(a), 0) - eye);
      const ReferenceHit exact = ref.first_hit(eye, d, reference_max_dist);
      auto rec = march::march<float>(field, vec3(eye), vec3(d), ms, ctx);
      if (r.as("miss_as_hit") && rec.outcome == Outcome::miss_far) rec.outcome = Outcome::hit;  // t < inf read as a hit
      if (!exact.hit) {
        outer_hit += rec.outcome != Outcome::miss_far;
        continue;
      }
      if (rec.outcome != Outcome::hit) {
        ++missed;
        continue;
      }
      // hit_lifted: the hit backed off 10 thresholds along the ray
      if (r.as("hit_lifted")) rec.t -= 10 * static_cast<float>(march::hit_threshold(ms, ctx, rec.t));
      const double rel = std::abs(double(rec.t) - exact.t) / exact.t;
      const double cos_i = -glm::dot(d, exact.normal);
      // The threshold along the normal is threshold / cos along the ray, plus float's rounding relative to t.
      const double bound =
          march::hit_threshold(ms, ctx, exact.t) / cos_i / exact.t + march::tolerance::kFloatRoundingRelative;
      t_off += !(rel <= bound);
      worst = std::max(worst, rel);
    }
  r.m[label + ".scale"] = scale;
  r.m[label + ".t_rel_err"] = worst;
  r.m[label + ".wrong"] = missed + t_off + outer_hit;
  const std::string at = " at scale " + num(scale);
  r.require("inner.hits", missed == 0, std::to_string(missed) + " inner rays missed" + at);
  r.require("inner.t", t_off == 0, std::to_string(t_off) + " inner hits beyond threshold / cos" + at);
  r.require("outer.miss", outer_hit == 0, std::to_string(outer_hit) + " rays past the silhouette did not miss" + at);
}

void scale_case(Run& r, march::EpsMode mode, const std::vector<double>& scales) {
  for (size_t i = 0; i < scales.size(); ++i)
    scale_errors(r, scales.size() == 1 ? decade(scales[i]) : "s" + std::to_string(i), scales[i], mode);
}

std::vector<double> log_uniform_scales() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-8, 8);
  std::vector<double> out;
  for (int i = 0; i < 12; ++i) out.push_back(std::pow(10.0, u(rng)));
  return out;
}

}  // namespace

void add_far_and_scale_cases(Battery& b) {
  const Variants far_both = plus(far_variants("float"), far_variants("double"));
  b.add("far.camera_relative", "a unit sphere offset 1e1..1e7, marched in float camera-relative, and in double",
        "every ray hits within hit_eps / cos + 1e-5, normals within 1 degree",
        plus({{"naive", "", "float in world coordinates"}}, far_both),
        [](Run& r, const StabilityOptions&) { far_offsets(r, decade_offsets(), true); });
  b.add("far.embree_offset",
        "the scene at Embree's offset (148376, 1234, -223423), float camera-relative and double",
        "every ray hits within hit_eps / cos + 1e-5, normals within 1 degree",
        plus({{"naive", "", "float in world coordinates"}}, far_both),
        [](Run& r, const StabilityOptions&) { far_offsets(r, {{148376, 1234, -223423}}, false); });
  b.add("far.render",
        "crum-smooth and lee-textured moved 1e1..1e7 from the origin with camera and lights, rendered in camera "
        "coordinates (96 px wide)",
        "at most 0.2% of pixels differ from the render at the origin by over one 8-bit level",
        {{"naive", "", "world coordinates, as a shader computes"},
         {"placement_rounded", "pixels", "the scene placed off its camera by float's rounding (2^-24 of the offset)"}},
        far_render);
  b.add("far.terrain_hash",
        "lee-terrain's height field in float against double on circles of radius 0.1..1e5 about the origin; the "
        "seed's sin hash beside it (how far out its gap reaches 1e-3, 1e-2 and 1e-1)",
        "the splitmix hash's float heights within 16 unit roundoffs of (1 + radius) times L of double's",
        {{"naive", "", "the seed's sin hash"},
         {"rounding_at_origin", "height", "the rounding allowed as at the origin, whatever the radius"}},
        far_terrain_hash);
  b.add("far.double", "world-coordinate double at offsets 1e1..1e7; float's error growth and breakdown beside it",
        "double: every ray within hit_eps / cos + 1e-5 and 1 degree",
        plus({{"naive", "", "float in place of double"}}, far_variants("double")), far_double);
  const Variants scale_variants = {{"naive", "", "absolute hit_eps 1e-3"},
                                   {"max_dist_short", "inner.hits", "max_dist 2 S, short of the sphere"},
                                   {"hit_lifted", "inner.t", "hits backed off 10 thresholds along the ray"},
                                   {"miss_as_hit", "outer.miss", "a ray past max_dist read as a hit"}};
  for (const auto& [label, mode] : std::vector<std::pair<std::string, march::EpsMode>>{
           {"relative", march::EpsMode::relative}, {"pixel", march::EpsMode::pixel}}) {
    for (const double s : {1e-8, 1e8})
      b.add("scale." + label + "." + decade(s), "a sphere of radius " + num(s) + " seen from 4x, eps_mode " + label,
            "inner rays hit within threshold / cos, outer rays miss", scale_variants,
            [mode = mode, s](Run& r, const StabilityOptions&) { scale_case(r, mode, {s}); });
    b.add("scale." + label + ".log_uniform", "12 sphere radii log-uniform in 1e-8..1e8 (seed 7), eps_mode " + label,
          "inner rays hit within threshold / cos, outer rays miss, at every scale", scale_variants,
          [mode = mode](Run& r, const StabilityOptions&) { scale_case(r, mode, log_uniform_scales()); });
  }
}

}  // namespace marchcheck::validation::stability
