// Marchers: sphere tracing, over-relaxed sphere tracing, Lipschitz-scaled tracing, fixed step + bisection.
// Each ray returns a record, never a sentinel: a miss is a miss, not t = 0 or t = +inf.
#pragma once

#include "marchcheck/sdf/scalar.hpp"
#include "marchcheck/sdf/scene.hpp"

#include <glm/glm.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string_view>

namespace marchcheck::march {

using sdf::EpsMode;
using sdf::Marcher;
using sdf::MarchSettings;

enum class Outcome : std::uint8_t { hit, miss_far, miss_steps, inside, invalid };

std::string_view to_string(Outcome outcome);

template <class T>
struct RayRecord {
  Outcome outcome = Outcome::invalid;
  T t = 0;  // distance along the ray (in units of |direction|) where the march ended
  int steps = 0;
  int evals = 0;
  T min_abs_f = std::numeric_limits<T>::infinity();  // smallest |f| seen
  T t_at_min = 0;                                    // and where
  T last_abs_f = std::numeric_limits<T>::infinity();
  bool decided() const { return outcome == Outcome::hit || outcome == Outcome::miss_far; }
};

// What a march needs beyond the settings: the field's declared Lipschitz bound (for the scaled marcher) and the
// camera's pixel footprint at distance t, footprint_at_0 + footprint_slope * t (for eps_mode pixel).
struct MarchContext {
  double lipschitz = 1;
  double footprint_at_0 = 0;
  double footprint_slope = 0;
};

// The hit threshold at distance t.
template <class T>
inline T hit_threshold(const MarchSettings& s, const MarchContext& c, T t) {
  switch (s.eps_mode) {
    case EpsMode::absolute: return T(s.hit_eps);
    case EpsMode::relative: return T(s.hit_eps) * t;
    case EpsMode::pixel: return T(c.footprint_at_0) + T(c.footprint_slope) * t;
  }
  return T(s.hit_eps);
}

// True when the settings and context make no sense (NaN, negative, out of range): such rays are `invalid`.
bool settings_invalid(const MarchSettings& s, const MarchContext& c);

namespace detail {

template <class T>
inline bool finite3(glm::vec<3, T> v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

template <class T>
struct Tracker {
  RayRecord<T>& r;
  void saw(T t, T v) {
    ++r.evals;
    const T a = std::abs(v);
    r.last_abs_f = a;
    if (a < r.min_abs_f) {
      r.min_abs_f = a;
      r.t_at_min = t;
    }
  }
  RayRecord<T>& end(Outcome o, T t) {
    r.outcome = o;
    r.t = t;
    return r;
  }
};

}  // namespace detail

// Marches field f (any callable vec3<T> -> T) from origin along direction, starting at t_start.
// t is measured in units of |direction|: a direction that is not normalised is marched as given (as the
// seed shaders that forget to normalise do), which is what lets validation catch them.
template <class T, class F>
RayRecord<T> march(const F& f, glm::vec<3, T> origin, glm::vec<3, T> direction, const MarchSettings& s,
                   const MarchContext& c, T t_start = 0) {
  RayRecord<T> r;
  detail::Tracker<T> track{r};
  if (!detail::finite3(origin) || !detail::finite3(direction) || !std::isfinite(t_start) ||
      (direction.x == 0 && direction.y == 0 && direction.z == 0) || settings_invalid(s, c))
    return track.end(Outcome::invalid, t_start);

  const T max_dist = static_cast<T>(s.max_dist);
  const T scale = s.marcher == Marcher::scaled ? T(s.step_scale / c.lipschitz) : T(s.step_scale);
  T t = t_start;
  // One step: one evaluation, recorded.
  auto probe = [&](T tt) {
    const T v = f(origin + direction * tt);
    ++r.steps;
    track.saw(tt, v);
    return v;
  };

  if (s.marcher == Marcher::fixed) {
    const T step = T(s.fixed_step);
    T prev_t = t;
    while (r.steps < s.max_steps) {
      const T v = probe(t);
      if (!std::isfinite(v)) return track.end(Outcome::invalid, t);
      const T eps = hit_threshold(s, c, t);
      if (r.steps == 1 && v < -eps) return track.end(Outcome::inside, t);
      if (v < eps) {
        if (v > -eps || r.steps == 1) return track.end(Outcome::hit, t);
        // Crossed the surface between prev_t (outside) and t (inside): bisect the bracket.
        T lo = prev_t, hi = t;
        while (r.steps < s.max_steps) {
          const T mid = lo + (hi - lo) * T(0.5);
          const T vm = probe(mid);
          if (!std::isfinite(vm)) return track.end(Outcome::invalid, mid);
          if (std::abs(vm) < hit_threshold(s, c, mid) || !(mid > lo && mid < hi)) return track.end(Outcome::hit, mid);
          (vm > 0 ? lo : hi) = mid;
        }
        return track.end(Outcome::miss_steps, lo);
      }
      prev_t = t;
      t += step;
      if (t > max_dist) return track.end(Outcome::miss_far, t);
    }
    return track.end(Outcome::miss_steps, t);
  }

  // Sphere tracing; relaxed: steps of omega * f, falling back to a plain step from the previous point when
  // the unbounding spheres of two consecutive points do not overlap (Keinert et al. 2014).
  T omega = s.marcher == Marcher::relaxed ? T(s.relaxation) : T(1);
  T prev_t = t, prev_f = 0, prev_step = 0;
  while (r.steps < s.max_steps) {
    const T v = probe(t);
    if (!std::isfinite(v)) return track.end(Outcome::invalid, t);
    const T eps = hit_threshold(s, c, t);
    if (r.steps == 1 && v < -eps) return track.end(Outcome::inside, t);
    if (omega > T(1) && std::abs(v) + prev_f < prev_step) {
      omega = 1;
      t = prev_t + prev_f * scale;
      prev_step = prev_f * scale;
      continue;
    }
    if (v < eps) return track.end(Outcome::hit, t);
    const T step = v * omega * scale;
    prev_t = t;
    prev_f = v;
    prev_step = step;
    t += step;
    if (t > max_dist) return track.end(Outcome::miss_far, t);
  }
  return track.end(Outcome::miss_steps, t);
}

}  // namespace marchcheck::march
