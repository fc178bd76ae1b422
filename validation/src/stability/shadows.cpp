// Shadow rays from marched hit points: self-hits per bias strategy.
#include "battery.hpp"

#include "marchcheck/march/effects.hpp"
#include "marchcheck/march/normals.hpp"

#include <limits>
#include <string>
#include <utility>

namespace marchcheck::validation::stability {

namespace {

// Lit points on a lone sphere (convex: nothing can shadow them) whose shadow ray is blocked anyway.
int self_hits(double radius, sdf::ShadowBias bias, bool no_bias, int& lit) {
  const sdf::Tape tape = sdf::compile(sdf::sphere(radius));
  const TapeField field{&tape};
  MarchSettings ms;
  ms.hit_eps = 1e-3;
  ms.max_dist = 10 * radius;
  ms.max_steps = 1000;
  sdf::Light light;
  light.shadow = sdf::ShadowMode::hard;
  light.bias = bias;
  const vec3 to_light = glm::normalize(vec3(0.3f, 0.5f, 1.0f));
  const dvec3 eye(0, 0, 3 * radius);
  int blocked = 0;
  lit = 0;
  for (int j = 0; j < 12; ++j)
    for (int i = 0; i < 12; ++i) {
      const dvec3 target((i - 5.5) / 8 * radius, (j - 5.5) / 8 * radius, 0);
      const vec3 d(glm::normalize(target - eye));
      const auto rec = march::march<float>(field, vec3(eye), d, ms, {});
      if (rec.outcome != Outcome::hit) continue;
      const vec3 p = vec3(eye) + d * rec.t;
      const vec3 n = march::estimate_normal(field, p, sdf::NormalMethod::central, float(1e-3 * radius)).n;
      if (glm::dot(n, to_light) < 0.1f) continue;
      ++lit;
      if (no_bias) {
        const auto s = march::march<float>(field, p, to_light, ms, {});
        blocked += s.outcome == Outcome::hit || s.outcome == Outcome::inside;
      } else {
        blocked += march::shadow_visibility<float>(field, p, n, to_light, std::numeric_limits<float>::infinity(),
                                                   rec.t, light, ms, {})
                       .visibility < 0.5;
      }
    }
  return blocked;
}

void shadow_case(Run& r, sdf::ShadowBias bias, double radius) {
  int lit = 0;
  const int hits = self_hits(radius, bias, r.naive(), lit);
  r.m["lit_points"] = lit;
  r.m["self_hits"] = hits;
  if (radius > 1) {  // the other strategies at this scale, for comparison
    int unused = 0;
    r.m["seed_offset.self_hits"] = self_hits(radius, sdf::ShadowBias::seed_offset, false, unused);
    r.m["seed_ignore.self_hits"] = self_hits(radius, sdf::ShadowBias::seed_ignore, false, unused);
  }
  r.needs("lit_points", lit >= 20, "too few lit hit points to test");
  r.require("no_self_hit", hits == 0, std::to_string(hits) + " shadow rays re-hit their own surface");
}

}  // namespace

void add_shadow_cases(Battery& b) {
  const Variants unbiased = {{"naive", "no_self_hit", "the shadow ray starts at the hit point"}};
  for (const auto& [label, bias] : std::vector<std::pair<std::string, sdf::ShadowBias>>{
           {"seed_offset", sdf::ShadowBias::seed_offset}, {"seed_ignore", sdf::ShadowBias::seed_ignore},
           {"scaled", sdf::ShadowBias::scaled}}) {
    b.add("shadow.self_hits." + label, "shadow rays from marched hits on a unit sphere, bias " + label,
          "no lit point's shadow ray re-hits its own surface", unbiased,
          [bias = bias](Run& r, const StabilityOptions&) { shadow_case(r, bias, 1); });
  }
  b.add("shadow.self_hits.scaled_far",
        "the scale-aware bias on a sphere of radius 1e5 (other strategies' counts beside)",
        "no self-hit with the scale-aware strategy", unbiased,
        [](Run& r, const StabilityOptions&) { shadow_case(r, sdf::ShadowBias::scaled, 1e5); });
}

}  // namespace marchcheck::validation::stability
