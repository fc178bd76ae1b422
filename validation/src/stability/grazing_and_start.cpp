// Grazing rays and shallow incidence (steps against the closed-form laws), and rays starting in, on and just
// above a surface.
#include "battery.hpp"

#include "marchcheck/validation/convergence.hpp"

#include <cmath>
#include <string>
#include <utility>

namespace marchcheck::validation::stability {

namespace {

// ---- grazing rays and shallow incidence: steps against the closed-form laws ----

void grazing(Run& r, double b) {
  const double law = kPi * std::sqrt(2 / b);
  MarchSettings s = grazing_settings(b, r.naive() ? static_cast<int>(law / 2) : 1 << 24);
  if (r.as("eps_2b")) s.hit_eps = 2 * b;
  if (r.as("quarter_steps")) s.step_scale = 0.25;
  const GrazingRow row = grazing_row(b, s);
  r.m["steps"] = row.steps;
  r.m["law"] = law;
  r.m["steps_over_law"] = row.steps / law;
  r.require("no_hit", row.outcome != Outcome::hit, "a hit on a ray that passes b above the sphere (hit_eps is b / 1000)");
  r.require("decided", row.outcome == Outcome::miss_far || row.outcome == Outcome::hit,
            "undecided: max_steps ran out before the ray got past");
  // The band the convergence test uses: the law counts the steps near the sphere; approach and exit add a few.
  if (row.outcome == Outcome::miss_far)
    r.require("steps_law", row.steps > 0.5 * law && row.steps < 1.5 * law + 20, "steps outside [0.5 law, 1.5 law + 20]");
}

void incidence(Run& r, double deg) {
  const double s = std::sin(deg * kPi / 180), c = std::cos(deg * kPi / 180), h0 = 1, eps = 1e-4;
  const double law = std::log(eps / h0) / std::log(1 - s);
  const sdf::Tape tape = sdf::compile(sdf::plane({0, 1, 0}, 0));
  MarchSettings ms;
  ms.hit_eps = eps;
  ms.max_dist = 1e7;
  ms.max_steps = r.naive() ? static_cast<int>(law / 2) : 1 << 22;
  if (r.as("half_steps")) ms.step_scale = 0.5;
  auto rec = march::march<double>(TapeField{&tape}, dvec3(0, h0, 0), dvec3(c, -s, 0), ms, {});
  if (r.as("hit_lifted")) rec.t -= eps / s;  // a self-shadowing fix made on t: the hit lifted hit_eps off the plane
  const double t_err = std::abs(rec.t - h0 / s);
  r.m["steps"] = rec.steps;
  r.m["law"] = law;
  r.m["t_err"] = t_err;
  r.m["t_err_bound"] = eps / s;
  r.require("hit", rec.outcome == Outcome::hit, "the ray did not reach the plane: " + std::string(march::to_string(rec.outcome)));
  if (rec.outcome != Outcome::hit) return;
  // Each step keeps 1 - sin(theta) of the height: the hit comes on the first whole step past the law, plus the
  // evaluation that sees it.
  r.require("steps_law", std::abs(rec.steps - law) <= 2, "steps " + num(rec.steps) + " off the law " + num(law));
  // The march stops less than hit_eps above the plane, which is hit_eps / sin(theta) along the ray.
  r.require("t_err", t_err <= eps / s, "t error above hit_eps / sin(theta)");
}

// ---- rays starting in, on and just above a surface ----

enum class Start { inside, on, half_eps };

void start_case(Run& r, Start where) {
  const sdf::Tape tape = sdf::compile(sdf::sphere(1));
  const TapeField field{&tape};
  MarchSettings ms;
  ms.hit_eps = 1e-3;
  const float x = where == Start::inside ? 0.5f : where == Start::on ? 1.0f : 1.0005f;
  const Outcome expected = where == Start::inside ? Outcome::inside : Outcome::hit;
  int wrong_outcome = 0, wrong_t = 0, wrong_evals = 0;
  for (const float dir : {1.0f, -1.0f}) {
    const vec3 origin(x, 0, 0), d(dir, 0, 0);
    // naive: the skip-ahead workaround for self-hits (start hit_eps along the ray), or the shader loop inside;
    // skip_leaving: the skip-ahead on rays leaving the surface only, a quarter of hit_eps
    const float t_start = r.naive() ? float(ms.hit_eps) : r.as("skip_leaving") && dir > 0 ? float(ms.hit_eps) / 4 : 0;
    march::RayRecord<float> rec = (r.naive() && where == Start::inside) || r.as("shader_loop")
                                      ? naive_march<float>(field, origin, d, ms)
                                      : march::march<float>(field, origin, d, ms, {}, t_start);
    if (r.as("inside_below_eps") && field(origin) < float(ms.hit_eps)) rec.outcome = Outcome::inside;  // hit and
                                                                                                      // inside split at hit_eps, not 0
    if (r.as("inside_test_first")) ++rec.evals;  // the start evaluated once for an inside test, again in the loop
    wrong_outcome += rec.outcome != expected;
    wrong_t += rec.t != 0;
    wrong_evals += rec.evals != 1;
    r.m[dir > 0 ? "outward.t" : "inward.t"] = rec.t;
    r.m[dir > 0 ? "outward.outcome" : "inward.outcome"] = static_cast<double>(rec.outcome);
  }
  r.m["wrong"] = wrong_outcome + wrong_t + wrong_evals;
  r.require("outcome", wrong_outcome == 0, std::to_string(wrong_outcome) + " of 2 rays not reported " +
                                               (where == Start::inside ? "inside" : "hit"));
  r.require("t_zero", wrong_t == 0, std::to_string(wrong_t) + " of 2 rays not at t = 0");
  r.require("one_eval", wrong_evals == 0, std::to_string(wrong_evals) + " of 2 rays took other than one evaluation");
}

}  // namespace

void add_grazing_and_start_cases(Battery& b) {
  for (int k = 1; k <= 7; ++k) {
    const double clearance = std::pow(10.0, -k);
    b.add("grazing.b1e-" + std::to_string(k),
          "a double ray passing 1e-" + std::to_string(k) + " above a unit sphere: steps against pi sqrt(2R/b)",
          "miss_far (never a hit: hit_eps is b/1000), steps within [0.5 law, 1.5 law + 20]",
          {{"naive", "decided", "max_steps at half the law"},
           {"eps_2b", "no_hit", "hit_eps 2b: the ray hits"},
           {"quarter_steps", "steps_law", "steps of f / 4"}},
          [clearance](Run& r, const StabilityOptions&) { grazing(r, clearance); });
  }
  for (const auto& [label, deg] : std::vector<std::pair<std::string, double>>{
           {"30deg", 30}, {"5deg", 5}, {"1deg", 1}, {"0p1deg", 0.1}, {"0p01deg", 0.01}}) {
    b.add("plane.incidence_" + label,
          "a ray at " + num(deg) + " degrees to a plane: steps against ln(eps/h0)/ln(1 - sin)",
          "hit, steps within 2 of the law, t within hit_eps / sin(theta)",
          {{"naive", "hit", "max_steps at half the law"},
           {"half_steps", "steps_law", "steps of f / 2"},
           {"hit_lifted", "t_err", "the hit lifted hit_eps off the plane along the ray"}},
          [deg = deg](Run& r, const StabilityOptions&) { incidence(r, deg); });
  }
  const Variants start_variants = {
      {"skip_leaving", "t_zero", "rays leaving the surface start hit_eps / 4 along"},
      {"inside_test_first", "one_eval", "the start evaluated for an inside test, then again"}};
  b.add("start.inside", "rays starting inside a sphere, both ways", "outcome inside at t = 0 after one evaluation",
        plus({{"naive", "outcome", "the shader loop: no inside outcome"}}, start_variants),
        [](Run& r, const StabilityOptions&) { start_case(r, Start::inside); });
  const Variants skip_ahead = {{"naive", "", "start hit_eps along the ray (skip-ahead)"},
                               {"inside_below_eps", "outcome", "inside when f < hit_eps instead of f < 0"}};
  b.add("start.on", "rays starting exactly on a sphere, both ways", "hit at t = 0 after one evaluation",
        plus(skip_ahead, start_variants), [](Run& r, const StabilityOptions&) { start_case(r, Start::on); });
  b.add("start.half_eps", "rays starting hit_eps/2 above a sphere, both ways", "hit at t = 0 after one evaluation",
        plus(skip_ahead, start_variants), [](Run& r, const StabilityOptions&) { start_case(r, Start::half_eps); });
}

}  // namespace marchcheck::validation::stability
