// Degenerate rays and settings: NaN, infinite and zero rays, max_steps 0, hit_eps 0, an infinite max_dist,
// denormals, and what bad rays cost a batch.
#include "battery.hpp"

#include "marchcheck/validation/statistics.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

namespace marchcheck::validation::stability {

namespace {

// ---- degenerate rays and settings ----

struct BadRay {
  vec3 origin, direction;
};

MarchSettings input_settings() {
  MarchSettings ms;
  ms.hit_eps = 1e-3;
  ms.max_steps = 1000;
  ms.max_dist = 100;
  return ms;
}

const vec3 kCleanOrigin(0.3f, 0.2f, -3.0f), kCleanDir(0, 0, 1);

// The marcher a degenerate-input case runs: as it is, the shader loop (naive), or one bookkeeping mistake.
template <class F>
march::RayRecord<float> march_input(const Run& r, const F& f, vec3 o, vec3 d, const MarchSettings& ms) {
  if (r.naive()) return naive_march<float>(f, o, d, ms);
  auto rec = march::march<float>(f, o, d, ms, {});
  const bool ran_out = rec.outcome == Outcome::miss_steps;
  if (r.as("invalid_as_miss") && rec.outcome == Outcome::invalid) rec.outcome = Outcome::miss_far;
  if (r.as("no_early_exit")) rec.evals = std::max(ms.max_steps, 0);  // a fixed trip count, bad input flagged after
  if (r.as("miss_at_infinity") && (ran_out || rec.outcome == Outcome::miss_far))  // Embree's tfar convention
    rec.t = std::numeric_limits<float>::infinity();
  if (r.as("ran_out_as_hit") && ran_out) rec.outcome = Outcome::hit;
  if (r.as("ran_out_as_miss_far") && ran_out) rec.outcome = Outcome::miss_far;
  if (r.as("one_more_eval") && ran_out) ++rec.evals;  // the field evaluated once more after the loop
  return rec;
}

// A NaN or infinite ray must come back invalid (principle 8), at no more cost than a clean ray.
void invalid_input(Run& r, BadRay ray) {
  const sdf::Tape tape = sdf::compile(sdf::sphere(1));
  const MarchSettings ms = input_settings();
  const auto clean = march::march<float>(TapeField{&tape}, kCleanOrigin, kCleanDir, ms, {});
  const auto rec = march_input(r, TapeField{&tape}, ray.origin, ray.direction, ms);
  r.m["outcome"] = static_cast<double>(rec.outcome);
  r.m["evals"] = rec.evals;
  r.m["clean_ray.evals"] = clean.evals;
  r.require("invalid", rec.outcome == Outcome::invalid, "outcome " + std::string(march::to_string(rec.outcome)) + ", not invalid");
  r.require("cost", rec.evals <= 2.5 * clean.evals, "cost " + std::to_string(rec.evals) + " evaluations, over 2.5x a clean ray");
}

float denormal() { return std::numeric_limits<float>::denorm_min() * 1000; }

// Well defined: t finite, the outcome honest (no hit claimed without the threshold met), evaluations bounded.
void defined_input(Run& r, const std::string& what, const MarchSettings& ms, const std::vector<BadRay>& rays) {
  const sdf::Tape tape = sdf::compile(sdf::sphere(1));
  const TapeField field{&tape};
  int t_bad = 0, dishonest = 0, over_budget = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    BadRay ray = rays[i];
    if (r.naive() && what == "denormal") ray.direction = glm::normalize(ray.direction);  // what shaders do first
    const auto rec = march_input(r, field, ray.origin, ray.direction, ms);
    const vec3 p = ray.origin + ray.direction * rec.t;
    const bool invalid = rec.outcome == Outcome::invalid;
    t_bad += !invalid && !std::isfinite(rec.t);
    dishonest += !invalid && rec.outcome == Outcome::hit && !(field(p) < march::hit_threshold(ms, {}, rec.t));
    over_budget += rec.evals > std::max(ms.max_steps, 0);
    r.m[what + ".ray" + std::to_string(i) + ".outcome"] = static_cast<double>(rec.outcome);
    r.m[what + ".ray" + std::to_string(i) + ".evals"] = rec.evals;
  }
  r.m[what + ".wrong"] = t_bad + dishonest + over_budget;
  r.require("t_finite", t_bad == 0, what + ": " + std::to_string(t_bad) + " rays ended with a non-finite t");
  r.require("honest_hit", dishonest == 0, what + ": " + std::to_string(dishonest) + " hits claimed off the surface");
  r.require("bounded", over_budget == 0, what + ": " + std::to_string(over_budget) + " rays ran past max_steps evaluations");
}

// max_steps 0: an honest "ran out of steps" at once, no evaluation, t finite.
void max_steps_zero(Run& r, const StabilityOptions&) {
  const sdf::Tape tape = sdf::compile(sdf::sphere(1));
  MarchSettings ms = input_settings();
  ms.max_steps = 0;
  const auto rec = march_input(r, TapeField{&tape}, kCleanOrigin, kCleanDir, ms);
  r.m["outcome"] = static_cast<double>(rec.outcome);
  r.m["evals"] = rec.evals;
  r.require("miss_steps", rec.outcome == Outcome::miss_steps, "outcome " + std::string(march::to_string(rec.outcome)));
  r.require("no_eval", rec.evals == 0, std::to_string(rec.evals) + " evaluations with max_steps 0");
  r.require("t_finite", std::isfinite(rec.t), "t not finite");
}

// eps 0 on a shallow plane: float's t stops moving once f drops under its spacing, so a loop waiting for
// f <= 0 never ends. The marcher stops at max_steps; the naive `while (f > eps)` loop runs to the budget.
void eps_zero(Run& r, const StabilityOptions&) {
  const sdf::Tape tape = sdf::compile(sdf::plane({0, 1, 0}, 0));
  const TapeField field{&tape};
  MarchSettings ms = input_settings();
  ms.hit_eps = r.as("default_eps") ? 1e-3 : 0;  // default_eps: hit_eps 0 replaced by a "sane" default
  ms.max_dist = 1e6;
  const vec3 origin(0, 1, 0), d(std::cos(0.17f), -std::sin(0.17f), 0);
  march::RayRecord<float> rec;
  if (r.naive()) {
    constexpr int kBudget = 1'000'000;  // stands in for "forever"
    float t = 0;
    for (float v = field(origin); v > 0 && rec.evals < kBudget; v = field(origin + d * t)) {
      ++rec.evals;
      t += v;
    }
    rec.outcome = rec.evals < kBudget ? Outcome::hit : Outcome::miss_steps;
    rec.t = t;
  } else {
    rec = march_input(r, field, origin, d, ms);
  }
  r.m["outcome"] = static_cast<double>(rec.outcome);
  r.m["evals"] = rec.evals;
  r.m["t"] = rec.t;
  const double t_err = std::abs(double(rec.t) - 1 / std::sin(0.17));
  r.require("bounded", rec.evals <= ms.max_steps, "ran " + std::to_string(rec.evals) + " evaluations: past max_steps (a hang)");
  r.require("t_finite", std::isfinite(rec.t), "t not finite");
  // A hit claimed with eps 0 must be where f reached 0, up to float's rounding at t (about 6).
  r.require("hit_on_plane", rec.outcome != Outcome::hit || t_err <= march::tolerance::kFloatRoundingNearUnit,
            "a hit off the plane");
}

// Like Embree's verify: a batch with bad rays costs no more than 2.5x a clean one (evaluations; seconds too).
void batch_cost(Run& r, const StabilityOptions&) {
  const sdf::Tape tape = sdf::compile(sdf::sphere(1));
  const TapeField field{&tape};
  const MarchSettings ms = input_settings();
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const std::vector<BadRay> bad = {{kCleanOrigin, {nan, 0, 1}}, {kCleanOrigin, {inf, 0, 1}}, {kCleanOrigin, {0, 0, 0}},
                                   {{nan, 0, -3}, kCleanDir},   {{0, inf, -3}, kCleanDir}};
  std::vector<BadRay> clean_batch, mixed_batch;
  for (int i = 0; i < 64; ++i) {
    const BadRay ray{kCleanOrigin + vec3(0.02f * float(i % 8), 0.02f * float(i / 8), 0), kCleanDir};
    clean_batch.push_back(ray);
    mixed_batch.push_back(i % 2 ? bad[static_cast<size_t>(i / 2) % bad.size()] : ray);
  }
  const auto cost = [&](const std::vector<BadRay>& batch, double& seconds) {
    std::vector<double> times;
    long evals = 0;
    for (int rep = 0; rep < 5; ++rep) {
      evals = 0;
      const auto start = std::chrono::steady_clock::now();
      for (const BadRay& ray : batch) evals += march_input(r, field, ray.origin, ray.direction, ms).evals;
      times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    seconds = median(times);
    return static_cast<double>(evals);
  };
  double clean_s = 0, mixed_s = 0;
  const double clean = cost(clean_batch, clean_s), mixed = cost(mixed_batch, mixed_s);
  r.m["clean.evals"] = clean;
  r.m["mixed.evals"] = mixed;
  r.m["evals_ratio"] = mixed / clean;
  r.m["clean.seconds"] = clean_s;
  r.m["mixed.seconds"] = mixed_s;
  r.require("cost", mixed <= 2.5 * clean, "the batch with bad rays costs " + num(mixed / clean) + "x the clean one (limit 2.5x)");
}

}  // namespace

void add_input_cases(Battery& b) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  for (const auto& [label, ray] : std::vector<std::pair<std::string, BadRay>>{
           {"nan_direction", {kCleanOrigin, {nan, 0, 1}}},
           {"inf_direction", {kCleanOrigin, {inf, 0, 1}}},
           {"zero_direction", {kCleanOrigin, {0, 0, 0}}},
           {"nan_origin", {{nan, 0.2f, -3}, kCleanDir}},
           {"inf_origin", {{0.3f, -inf, -3}, kCleanDir}}}) {
    b.add("input." + label,
          "a ray with a " + label.substr(0, label.find('_')) + " " + label.substr(label.find('_') + 1),
          "outcome invalid, at most 2.5x a clean ray's evaluations",
          {{"naive", "", "the shader loop: no input guard"},
           {"invalid_as_miss", "invalid", "a bad ray rejected as a miss"},
           {"no_early_exit", "cost", "a fixed trip count: bad input flagged after every step"}},
          [ray = ray](Run& r, const StabilityOptions&) { invalid_input(r, ray); });
  }
  b.add("input.eps_zero", "hit_eps 0 on a shallow plane in float",
        "stops within max_steps; a hit only where f reached 0",
        {{"naive", "bounded", "a `while (f > eps)` loop without a step limit"},
         {"miss_at_infinity", "t_finite", "a miss reported at t = infinity"},
         {"default_eps", "hit_on_plane", "hit_eps 0 replaced by a default of 1e-3"}},
        eps_zero);
  b.add("input.max_steps_zero", "max_steps 0", "miss_steps after no evaluation, t finite",
        {{"naive", "", "the shader loop"},
         {"ran_out_as_miss_far", "miss_steps", "a march that ran out of steps reported as miss_far"},
         {"one_more_eval", "no_eval", "the field evaluated once more after the loop"},
         {"miss_at_infinity", "t_finite", "a miss reported at t = infinity"}},
        max_steps_zero);
  const Variants defined_variants = {{"miss_at_infinity", "t_finite", "a miss reported at t = infinity"},
                                     {"ran_out_as_hit", "honest_hit", "a march that ran out of steps read as a hit"},
                                     {"one_more_eval", "bounded", "the field evaluated once more after the loop"}};
  b.add("input.max_dist_inf", "max_dist infinite, rays toward and away from a sphere (and away with 50 steps)",
        "t finite (or invalid), a hit only on the surface, evaluations within max_steps",
        plus({{"naive", "", "the shader loop"}}, defined_variants), [](Run& r, const StabilityOptions&) {
          MarchSettings ms = input_settings();
          ms.max_dist = std::numeric_limits<double>::infinity();
          // The ray away doubles t each step until it overflows (invalid); with 50 steps it runs out first.
          defined_input(r, "max_dist_inf", ms, {{kCleanOrigin, kCleanDir}, {kCleanOrigin, -kCleanDir}});
          ms.max_steps = 50;
          defined_input(r, "max_dist_inf_50_steps", ms, {{kCleanOrigin, -kCleanDir}});
        });
  b.add("input.denormal", "denormal direction, origin and hit_eps",
        "t finite (or invalid), a hit only on the surface, evaluations within max_steps",
        plus({{"naive", "", "the shader loop, normalising the direction first"}}, defined_variants),
        [](Run& r, const StabilityOptions&) {
          MarchSettings ms = input_settings();
          defined_input(r, "denormal", ms,
                        {{kCleanOrigin, {denormal(), 0, denormal()}}, {{denormal(), 0, -3}, kCleanDir}});
          ms.hit_eps = denormal();
          // head-on, and shallow: float's t stalls above the surface and the march runs out of steps
          defined_input(r, "denormal_eps", ms,
                        {{kCleanOrigin, kCleanDir}, {{0, 1, -3}, glm::normalize(vec3(0, -0.01f, 1))}});
        });
  b.add("input.batch_cost", "64 clean rays against the same with every other ray NaN, Inf or zero",
        "the mixed batch costs at most 2.5x the clean batch's evaluations (seconds reported, not judged)",
        {{"naive", "cost", "the shader loop: no input guard"}}, batch_cost);
}

}  // namespace marchcheck::validation::stability
