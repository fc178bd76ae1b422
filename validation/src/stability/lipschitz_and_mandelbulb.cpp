// Non-Lipschitz fields (plain sphere tracing against steps f / L), and the Mandelbulb far out and deep.
#include "battery.hpp"

#include "marchcheck/march/camera.hpp"
#include "marchcheck/sdf/builtin_scenes.hpp"
#include "marchcheck/sdf/lipschitz.hpp"
#include "marchcheck/validation/reference.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <utility>

namespace marchcheck::validation::stability {

namespace {

// ---- non-Lipschitz fields ----

// Plain sphere tracing overshoots on a field steeper than 1; the scaled marcher with the measured L does not.
// An overshoot: a hit that ended deeper than hit_eps inside, a hit beyond the first surface, or a miss through it.
void lipschitz_case(Run& r, sdf::Scene scene, dvec3 lo, dvec3 hi) {
  const sdf::Tape tape = sdf::compile(scene.root, scene.time);
  const TapeField field{&tape};
  const double measured = sdf::measured_slope([&](dvec3 p) { return field(p); }, lo, hi, 20000, 1e-5);
  const Reference ref(scene.root, scene.time);
  const march::Camera camera(scene.camera, 32, 18);
  const double max_dist = std::min(scene.march.max_dist, 50.0);
  const auto count = [&](march::Marcher m, double lipschitz, double& evals) {
    MarchSettings ms = scene.march;
    ms.marcher = m;
    ms.max_dist = max_dist;
    ms.max_steps = 2000;
    march::MarchContext ctx;
    ctx.lipschitz = lipschitz;
    int over = 0;
    evals = 0;
    for (int j = 0; j < 18; ++j)
      for (int i = 0; i < 32; ++i) {
        const march::Ray ray = camera.ray(i + 0.5, j + 0.5);
        const dvec3 d = glm::normalize(ray.direction);
        const auto rec = march::march<double>(field, ray.origin, d, ms, ctx);
        evals += rec.evals;
        const ReferenceHit exact = ref.first_hit(ray.origin, d, max_dist);
        if (exact.unknown) continue;
        const double eps = march::hit_threshold(ms, ctx, rec.t);
        const bool hit = rec.outcome == Outcome::hit;
        // 0.01: far past hit_eps / cos at every incidence these scenes show, and under any feature's size.
        over += (hit && rec.last_abs_f > eps) || (hit && exact.hit && rec.t > exact.t + 0.01) ||
                (rec.outcome == Outcome::miss_far && exact.hit);
      }
    evals /= 32 * 18;
    return over;
  };
  double plain_evals = 0, scaled_evals = 0;
  const int plain = count(march::Marcher::sphere, 1, plain_evals);
  const int scaled = count(march::Marcher::scaled, r.naive() ? 1 : measured, scaled_evals);
  r.m["lipschitz.measured"] = measured;
  r.m["lipschitz.declared"] = sdf::derive_info(scene.root, scene.time).lipschitz;
  r.m["plain.overshoots"] = plain;
  r.m["scaled.overshoots"] = scaled;
  r.m["plain.evals_per_ray"] = plain_evals;
  r.m["scaled.evals_per_ray"] = scaled_evals;
  r.needs("steep", measured > 1, "the field measures 1-Lipschitz: nothing to test");
  r.needs("plain_overshoots", plain > 0, "plain sphere tracing showed no overshoot: the case cannot tell the marchers apart");
  r.require("no_overshoot", scaled == 0, std::to_string(scaled) + " overshoots left with steps f / L");
}

sdf::Scene twist_scene() {
  sdf::Scene s;
  s.name = "twist";
  s.root = sdf::make(sdf::Op::twist, {{"rate", {4}}}, {sdf::box({0.6, 1.2, 0.15})});
  s.camera.position = {0.3, 0.2, 3};
  s.camera.fov_deg = 50;
  s.march.hit_eps = 1e-4;
  return s;
}

// ---- the Mandelbulb far out and deep ----

// The textbook estimator (no guard at the origin, powers taken as they come), for the naive variants.
double textbook_mandelbulb(dvec3 p, int iterations) {
  dvec3 w = p;
  double dr = 1, r = 0;
  for (int i = 0; i < iterations; ++i) {
    r = glm::length(w);
    if (r > 2) break;
    const double theta = std::acos(w.y / r) * 8, phi = std::atan2(w.x, w.z) * 8;
    dr = 8 * std::pow(r, 7) * dr + 1;
    w = p + std::pow(r, 8) * dvec3(std::sin(theta) * std::sin(phi), std::cos(theta), std::sin(theta) * std::cos(phi));
  }
  return 0.5 * std::log(r) * r / dr;
}

void mandelbulb_far(Run& r, const StabilityOptions&) {
  const sdf::Node bulb = sdf::make(sdf::Op::mandelbulb, {{"iterations", {8}}});
  const sdf::Tape tape = sdf::compile(bulb);
  int bad = 0, samples = 0;
  for (int k = 1; k <= 37; ++k)
    for (const dvec3 dir : {dvec3(1, 0, 0), dvec3(0, 1, 0), glm::normalize(dvec3(1, -2, 3))}) {
      const dvec3 p = dir * std::pow(10.0, k);
      const float vf = r.naive() ? static_cast<float>(textbook_mandelbulb(p, 8)) : sdf::evaluate(tape, vec3(p));
      const double vd = r.naive() ? textbook_mandelbulb(p, 8) : sdf::evaluate(tape, p);
      samples += 2;
      // The set lies within 1.25 of the origin, so a sane estimate far out is positive and finite.
      bad += !(std::isfinite(vf) && vf > 0) + !(std::isfinite(vd) && vd > 0);
    }
  // A march from 1e5 away in float ends decided or honestly undecided, never on a non-finite value.
  MarchSettings ms;
  ms.marcher = march::Marcher::scaled;
  ms.max_dist = 2e5;
  ms.hit_eps = 1e-3;
  ms.max_steps = 2000;
  march::MarchContext ctx;
  ctx.lipschitz = r.as("lipschitz_zero") ? 0 : 2;  // lipschitz_zero: a field's constant left at 0, steps f / 0
  const auto rec = march::march<float>(TapeField{&tape}, vec3(0, 0, 1e5f), vec3(0, 0, -1), ms, ctx);
  r.m["samples"] = samples;
  r.m["non_finite_or_negative"] = bad;
  r.m["march_from_1e5.outcome"] = static_cast<double>(rec.outcome);
  r.m["march_from_1e5.t"] = rec.t;
  r.require("far_finite", bad == 0, std::to_string(bad) + " of " + std::to_string(samples) +
                                        " far samples (1e1..1e37, float and double) not finite and positive");
  r.require("march_finite", rec.outcome != Outcome::invalid && std::isfinite(rec.t),
            "the march from 1e5 met a non-finite value");
}

void mandelbulb_deep(Run& r, const StabilityOptions&) {
  const sdf::Node bulb = sdf::make(sdf::Op::mandelbulb, {{"iterations", {64}}});
  const sdf::Tape tape = sdf::compile(bulb);
  int bad = 0, samples = 0;
  for (int i = -6; i <= 6; ++i)
    for (int j = -6; j <= 6; ++j)
      for (int k = -6; k <= 6; ++k) {
        const dvec3 p = dvec3(i, j, k) * 0.22;  // includes the origin, where the angles are undefined
        const double vd = r.naive() ? textbook_mandelbulb(p, 64) : sdf::evaluate(tape, p);
        const float vf = r.naive() ? static_cast<float>(vd) : sdf::evaluate(tape, vec3(p));
        samples += 2;
        bad += !std::isfinite(vd) + !std::isfinite(vf);
      }
  r.m["iterations"] = 64;
  r.m["samples"] = samples;
  r.m["non_finite"] = bad;
  r.require("finite", bad == 0, std::to_string(bad) + " of " + std::to_string(samples) + " samples at 64 iterations not finite");
}

}  // namespace

void add_lipschitz_and_mandelbulb_cases(Battery& b) {
  const auto lip = [&](std::string name, std::string what, std::function<sdf::Scene()> scene, dvec3 lo, dvec3 hi) {
    b.add("lipschitz." + name, what + ": plain sphere tracing against steps f / L with the measured L",
          "plain tracing's overshoots counted (> 0), none left with the measured L",
          {{"naive", "no_overshoot", "steps f / 1"}},
          [scene = std::move(scene), lo, hi](Run& r, const StabilityOptions&) { lipschitz_case(r, scene(), lo, hi); });
  };
  lip("warp", "the warped sphere seen from above (rays cross the warp's ripples in y)", [] {
    sdf::Scene s = sdf::builtin_scene("warped");
    s.camera.position = {0, 5, 2};
    s.camera.target = {0, 0, 2};
    s.camera.up = {0, 0, 1};
    s.camera.fov_deg = 60;
    return s;
  }, {-3, -3, -1}, {3, 3, 5});
  lip("lattice_displacement", "the displaced box-frame lattice", [] { return sdf::builtin_scene("crum-lattice"); },
      {-6, -6, -6}, {6, 6, 6});
  lip("terrain", "a value-noise height field like lee-terrain's, steeper", [] {
    sdf::Scene s = sdf::builtin_scene("lee-terrain");
    s.root = sdf::make(sdf::Op::heightfield, {{"octaves", {-1.5, 1, -0.3, 3, -0.05, 6}}});
    // The view this case was measured from (eye on +z, the OpenCV lens): from lee's own eye on -z the slopes
    // facing it are too gentle for plain tracing to overshoot.
    s.camera.axes = sdf::CameraAxes::right_handed;
    s.camera.lens = sdf::LensConvention::opencv;
    return s;
  }, {-8, -3, -8}, {8, 3, 8});
  lip("twist", "a slab twisted at 4 radians per unit", twist_scene, {-1, -1.5, -1}, {1, 1.5, 1});
  b.add("mandelbulb.far", "the Mandelbulb at 1e1..1e37 from the origin (float and double), and a march from 1e5",
        "finite positive values; the march never meets a non-finite value",
        {{"naive", "far_finite", "the textbook estimator"},
         {"lipschitz_zero", "march_finite", "the march's Lipschitz constant left at 0"}},
        mandelbulb_far);
  b.add("mandelbulb.iterations_64", "the Mandelbulb at 64 iterations on a grid through the origin",
        "every value finite, float and double", {{"naive", "finite", "the textbook estimator"}}, mandelbulb_deep);
}

}  // namespace marchcheck::validation::stability
