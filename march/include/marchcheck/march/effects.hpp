// Shading effects with closed forms the tests check directly: Fresnel, refraction through a solid, shadows.
#pragma once

#include "marchcheck/march/marcher.hpp"
#include "marchcheck/march/normals.hpp"
#include "marchcheck/sdf/scene.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace marchcheck::march {

// Schlick's approximation of the Fresnel reflectance going from index n1 to n2 at cos(incidence).
inline double schlick_fresnel(double cos_incidence, double n1, double n2) {
  const double r0 = (n1 - n2) / (n1 + n2);
  const double c = 1 - std::clamp(cos_incidence, 0.0, 1.0);
  return r0 * r0 + (1 - r0 * r0) * c * c * c * c * c;
}

struct ShadowResult {
  double visibility = 1;  // 1 lit, 0 in full shadow
  int evals = 0;
};

// Where a shadow ray starts: p lifted along n by the light's bias, and its hit threshold.
template <class T>
struct ShadowStart {
  glm::vec<3, T> origin;
  T eps;
  double max_dist;  // the march's: no farther than the light
};

// Always inlined: the renderer calls it for every shadow ray, and GCC had kept it a call (1.6% of lee-flat's render).
template <class T>
[[gnu::always_inline]] inline ShadowStart<T> shadow_start(glm::vec<3, T> p, glm::vec<3, T> n, T light_dist, T t_hit,
                                                          const sdf::Light& light, const MarchSettings& s,
                                                          const MarchContext& c) {
  const T eps = hit_threshold(s, c, t_hit);
  T offset = eps * T(light.bias_factor);
  if (light.bias == sdf::ShadowBias::seed_ignore) offset = eps;
  if (light.bias == sdf::ShadowBias::scaled) {
    // Above the hit threshold and above the rounding of |p| and t, whatever the scene's scale.
    const T magnitude = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}) + t_hit;
    offset = T(2) * eps + T(light.bias_factor) * std::numeric_limits<T>::epsilon() * magnitude;
  }
  return {p + n * offset, eps, std::min<double>(s.max_dist, static_cast<double>(light_dist))};
}

// A hard shadow's visibility from its shadow ray's record.
template <class T>
double hard_visibility(const RayRecord<T>& r, const ShadowStart<T>& start, const sdf::Light& light) {
  bool blocked = r.outcome == Outcome::hit || r.outcome == Outcome::inside;
  if (light.bias == sdf::ShadowBias::seed_ignore && r.t <= T(light.bias_factor) * start.eps) blocked = false;
  return blocked ? 0.0 : 1.0;
}

// Visibility of a light from surface point p with normal n, hit at distance t_hit along its primary ray.
// light_dist: distance to a point light (infinity for a directional one).
template <class T, class F>
ShadowResult shadow_visibility(const F& f, glm::vec<3, T> p, glm::vec<3, T> n, glm::vec<3, T> to_light,
                                  T light_dist, T t_hit, const sdf::Light& light, const MarchSettings& s,
                                  const MarchContext& c) {
  ShadowResult out;
  const ShadowStart<T> start = shadow_start(p, n, light_dist, t_hit, light, s, c);
  const T eps = start.eps;
  const glm::vec<3, T> origin = start.origin;
  MarchSettings ss = s;
  ss.max_dist = start.max_dist;
  if (light.shadow == sdf::ShadowMode::hard) {
    const auto r = march<T>(f, origin, to_light, ss, c);
    out.evals = r.evals;
    out.visibility = hard_visibility(r, start, light);
    return out;
  }
  // Soft shadow: penumbra from the closest approach along the shadow ray (Quilez; improved: corrected with the
  // previous step's unbounding sphere).
  const T k = T(light.penumbra);
  const T step_scale = step_per_unit_f<T>(s, c);
  T res = 1, t = 0, prev_h = std::numeric_limits<T>::max();
  for (int i = 0; i < s.max_steps && t < T(ss.max_dist); ++i) {
    const T h = f(origin + to_light * t);
    ++out.evals;
    if (!std::isfinite(h)) break;
    if (h < eps) {
      res = 0;
      break;
    }
    if (light.soft == sdf::SoftShadow::classic || i == 0) {
      res = std::min(res, k * h / std::max(t, eps));
    } else {
      const T y = h * h / (T(2) * prev_h);
      const T d = std::sqrt(std::max(h * h - y * y, T(0)));
      res = std::min(res, k * d / std::max(T(0), t - y));
    }
    prev_h = h;
    t += h * step_scale;
  }
  out.visibility = std::clamp(static_cast<double>(res), 0.0, 1.0);
  return out;
}

template <class T>
struct Refraction {
  bool ok = false;  // false: the ray did not find its way out
  glm::vec<3, T> exit_point{0}, exit_direction{0};
  int evals = 0;
};

// Follows a ray into a solid of index ior through entry point p (normal n, direction d), marching the
// negated field inside, and refracts it out by Snell's law (total internal reflection bounces inside).
template <class T, class F>
Refraction<T> refract_through(const F& f, glm::vec<3, T> p, glm::vec<3, T> n, glm::vec<3, T> d, double ior,
                              const MarchSettings& s, const MarchContext& c, T normal_eps, int max_bounces = 4) {
  using V = glm::vec<3, T>;
  Refraction<T> out;
  V dir = glm::refract(d, n, T(1 / ior));
  if (glm::dot(dir, dir) == T(0)) return out;
  const auto inside = [&f](glm::vec<3, T> x) { return -f(x); };
  const T eps = hit_threshold(s, c, T(0)) + T(1e-6);
  V at = p - n * (T(2) * eps);
  for (int bounce = 0; bounce <= max_bounces; ++bounce) {
    const auto r = march<T>(inside, at, dir, s, c);
    out.evals += r.evals;
    if (r.outcome != Outcome::hit) return out;
    const V exit = at + dir * r.t;
    const auto nn = estimate_normal(f, exit, s.normal, normal_eps);
    out.evals += nn.evals;
    const V refracted = glm::refract(dir, -nn.n, T(ior));
    if (glm::dot(refracted, refracted) > T(0)) {
      out.ok = true;
      out.exit_point = exit + nn.n * (T(2) * eps);
      out.exit_direction = glm::normalize(refracted);
      return out;
    }
    dir = glm::reflect(dir, -nn.n);
    at = exit - nn.n * (T(2) * eps);
  }
  return out;
}

}  // namespace marchcheck::march
