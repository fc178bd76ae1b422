// Marchers: sphere tracing, over-relaxed sphere tracing, Lipschitz-scaled tracing, fixed step + bisection.
// Each ray returns a record, never a sentinel: a miss is a miss, not t = 0 or t = +inf.
#pragma once

#include "marchcheck/sdf/scalar.hpp"
#include "marchcheck/sdf/scene.hpp"

#include <glm/glm.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string_view>
#include <type_traits>

namespace marchcheck::march {

using sdf::EpsMode;
using sdf::Marcher;
using sdf::MarchSettings;

enum class Outcome : std::uint8_t { hit, miss_far, miss_steps, inside, invalid };

std::string_view to_string(Outcome outcome);

// A march that reached a verdict: it hit, or got past max_dist (not out of steps, inside or invalid).
constexpr bool decided(Outcome o) { return o == Outcome::hit || o == Outcome::miss_far; }

template <class T>
struct RayRecord {
  Outcome outcome = Outcome::invalid;
  T t = 0;  // distance along the ray (in units of |direction|) where the march ended
  int steps = 0;
  int evals = 0;
  T min_abs_f = std::numeric_limits<T>::infinity();  // smallest |f| seen
  T t_at_min = 0;                                    // and where
  T last_abs_f = std::numeric_limits<T>::infinity();
  bool decided() const { return march::decided(outcome); }
};

// The record as the scene's consumer reads it (MarchSettings::reading): as it is; through the fogerty seed's
// distance alone, shaded where t > 0 (a miss returns 0); or as the lee seed's, every ray shaded (a miss at +inf).
template <class T>
RayRecord<T> as_read(RayRecord<T> r, const MarchSettings& s) {
  if (s.reading == sdf::RecordReading::seed_infinity && r.outcome != Outcome::hit) {
    r.outcome = Outcome::hit;
    r.t = std::numeric_limits<T>::infinity();
  }
  if (s.reading != sdf::RecordReading::seed_distance) return r;
  if (r.outcome == Outcome::miss_far) r.t = 0;
  const bool shaded = (r.outcome == Outcome::hit || r.outcome == Outcome::miss_steps) && r.t > 0;
  r.outcome = shaded ? Outcome::hit : Outcome::miss_far;
  return r;
}

// What a march needs beyond the settings: the field's declared Lipschitz bound (for the scaled marcher) and the
// camera's pixel footprint at distance t, footprint_at_0 + footprint_slope * t (for eps_mode pixel).
struct MarchContext {
  double lipschitz = 1;
  double footprint_at_0 = 0;
  double footprint_slope = 0;
  // The field's (sdf::FieldInfo::perturbation_or_plain), for StepBound::perturbed; an infinite band: none.
  sdf::Perturbation perturbation{1, INFINITY};
  // Clip::bounds: boxes whose union holds the field's zero set and inside (sdf::bounding_boxes), in the march's
  // coordinates; one infinite box where unknown.
  static constexpr size_t kMaxClipBoxes = 4;
  std::array<sdf::Box3, kMaxClipBoxes> clip_boxes{};
  int clip_box_count = 1;
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

// How far a step goes per unit of f (sdf::step_per_unit_f with the context's declared L), in T.
template <class T>
inline T step_per_unit_f(const MarchSettings& s, const MarchContext& c) {
  return T(sdf::step_per_unit_f(s, c.lipschitz));
}

// How far a sphere-traced step goes from a point where the field is v, and how far from it no surface can be (an
// unbounding sphere's radius), in T: v per unit each, or on a field stepped by its perturbed bound (v - width) per
// the smooth part's unit where that is longer. Without it width is +inf: (v - inf) * k = -inf never wins, so the
// plain expressions' bits are kept.
template <class T>
struct StepRule {
  T scale = 1, radius = 1;  // per unit of f: a step (sdf::step_per_unit_f), an unbounding radius (1 / L)
  T width = std::numeric_limits<T>::infinity(), smooth_scale = 1, smooth_radius = 1;

  StepRule() = default;
  StepRule(const MarchSettings& s, const MarchContext& c)
      : scale(step_per_unit_f<T>(s, c)),
        radius(T(1 / c.lipschitz)),
        width(T(sdf::stepped_perturbation(s, c.perturbation.width))),
        smooth_scale(T(sdf::step_per_unit_f(s, c.perturbation.lipschitz))),
        smooth_radius(T(1 / c.perturbation.lipschitz)) {}
  // Each works on T, or on a vector of T when named (step<V>(v, omega): GCC's vector extension, the packets'
  // lanes), the same expressions.
  // A step of omega times the bound (omega 1: a plain step).
  template <class U = T>
  U step(std::type_identity_t<U> v, std::type_identity_t<U> omega) const {
    return longer<U>(plain_step<U>(v, omega), (v - width) * omega * smooth_scale);
  }
  // The radii of the unbounding spheres at two points where |f| is a and b, summed (perturbed: a lower bound of
  // the sum, each radius's longer term taken alike).
  template <class U = T>
  U radii(std::type_identity_t<U> a, std::type_identity_t<U> b) const {
    return longer<U>(plain_radii<U>(a, b), (a + b - 2 * width) * smooth_radius);
  }
  // Their terms without the perturbation: step and radii themselves, bit for bit, where width is +inf.
  template <class U = T>
  U plain_step(std::type_identity_t<U> v, std::type_identity_t<U> omega) const {
    return v * omega * scale;
  }
  template <class U = T>
  U plain_radii(std::type_identity_t<U> a, std::type_identity_t<U> b) const {
    return (a + b) * radius;
  }

 private:
  template <class U>
  static U longer(U plain, U perturbed) {
    return plain < perturbed ? perturbed : plain;  // NaN: plain
  }
};

// The root of the line through the samples (prev_t, prev_f) and (t, v): a Newton step on f(o + t d) = 0 with the
// derivative along the ray taken between them (HitRefine::secant). Only where they approach the surface
// (prev_f > v); else t (NaN compares false: t).
template <class T>
inline T secant_root(T prev_t, T prev_f, T t, T v) {
  const T dt = t - prev_t, df = prev_f - v, root = t + v * dt / df;
  return df > 0 && dt > 0 && std::isfinite(root) ? root : t;
}

// The part [t0, t1] of [t_start, max_dist] a ray marches (MarchSettings::clip): all of it, or only from where it
// first enters one of the boxes c.clip_boxes to where it last leaves one, found in double and widened by the hit
// threshold and 1e-5 (1 + t) so that neither the march's rounding nor a hit reached before the surface falls outside
// (and its end by fixed_step for the fixed marcher, whose step past a box's far side still finds a surface just
// inside it); t0 > t1 where the ray misses every box. A finite, non-degenerate ray.
template <class T>
struct Span {
  T t0, t1;
  bool empty() const { return !(t0 <= t1); }
};

template <class T>
Span<T> clip_span(const MarchSettings& s, const MarchContext& c, glm::vec<3, T> origin, glm::vec<3, T> direction,
                  T t_start, T max_dist) {
  if (s.clip == sdf::Clip::none) return {t_start, max_dist};
  const auto pad = [&](double t) {
    return static_cast<double>(hit_threshold<double>(s, c, std::abs(t))) + 1e-5 * (1 + std::abs(t));
  };
  double first = INFINITY, last = -INFINITY;
  for (int i = 0; i < c.clip_box_count; ++i) {
    const sdf::Box3& box = c.clip_boxes[i];
    double t0 = -INFINITY, t1 = INFINITY;
    bool beside = false;  // parallel to a slab, outside it: never in the box
    for (int k = 0; k < 3; ++k) {
      const double o = origin[k], d = direction[k], lo = box.lo[k], hi = box.hi[k];
      if (d == 0) {
        beside = beside || !(o >= lo && o <= hi);
        continue;
      }
      const double a = (lo - o) / d, b = (hi - o) / d;
      t0 = std::max(t0, std::min(a, b));
      t1 = std::min(t1, std::max(a, b));
    }
    if (beside) continue;
    t0 = std::max(static_cast<double>(t_start), t0 - pad(t0));
    t1 = std::min(static_cast<double>(max_dist), t1 + pad(t1) + (s.marcher == Marcher::fixed ? s.fixed_step : 0.0));
    if (!(t0 <= t1)) continue;
    first = std::min(first, t0);
    last = std::max(last, t1);
  }
  if (!(first <= last)) return {t_start, std::numeric_limits<T>::lowest()};
  return {static_cast<T>(first), static_cast<T>(last)};
}

// True when the settings and context make no sense (NaN, negative, out of range): such rays are `invalid`.
bool settings_invalid(const MarchSettings& s, const MarchContext& c);

namespace detail {

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

namespace detail {

// v is finite (NaN fails both compares). On T, or on a vector of T when named (U: the packets' lanes, a mask).
template <class T, class U = T>
inline auto finite_component(U v) {
  return (-std::numeric_limits<T>::max() <= v) & (v <= std::numeric_limits<T>::max());
}

// A ray's six components can be marched: all finite, and a direction. On T, or on vectors of T when named (the
// packets test a vector of rays at once): one expression for both. Every test made (`&`, not `&&`): a branch per
// component cost more than the tests.
template <class T, class U = T>
inline auto marchable_components(U ox, U oy, U oz, U dx, U dy, U dz) {
  return finite_component<T, U>(ox) & finite_component<T, U>(oy) & finite_component<T, U>(oz) &
         finite_component<T, U>(dx) & finite_component<T, U>(dy) & finite_component<T, U>(dz) &
         ((dx != T(0)) | (dy != T(0)) | (dz != T(0)));
}

// A ray whose geometry cannot be marched: not finite or no direction.
template <class T>
inline bool ray_degenerate(glm::vec<3, T> origin, glm::vec<3, T> direction, T t_start) {
  return !(marchable_components<T>(origin.x, origin.y, origin.z, direction.x, direction.y, direction.z) &
           finite_component<T>(t_start));
}

// A ray that cannot be marched: degenerate, or settings that make no sense.
template <class T>
inline bool ray_invalid(glm::vec<3, T> origin, glm::vec<3, T> direction, T t_start, const MarchSettings& s,
                        const MarchContext& c) {
  return ray_degenerate(origin, direction, t_start) || settings_invalid(s, c);
}

}  // namespace detail

// Sphere tracing; scaled: steps of f / L; relaxed: steps of omega * f / L, falling back to a plain step from the
// previous point when the unbounding spheres of two consecutive points (radius f / L) do not overlap (Keinert et
// al. 2014); each bound by StepRule (on a perturbed field, the perturbed bound where longer).
// Written as a state machine fed one field value at a time, so that march() and a packet of rays sharing
// batched evaluations (packet.hpp) take exactly the same steps.
template <class T>
class SphereTrace {
 public:
  SphereTrace() = default;
  // s and c must outlive the trace; max_dist replaces s.max_dist (shadow rays stop at their light).
  SphereTrace(const MarchSettings& s, const MarchContext& c, T t_start, T max_dist)
      : s_(&s),
        c_(&c),
        rule_(s, c),
        max_dist_(max_dist),
        omega_(s.marcher == Marcher::relaxed ? T(s.relaxation) : T(1)),
        t_(t_start),
        prev_t_(t_start) {
    if (!(r_.steps < s.max_steps)) end(Outcome::miss_steps);
  }
  bool done() const { return done_; }
  T t() const { return t_; }  // where the field is wanted next
  const StepRule<T>& rule() const { return rule_; }
  const RayRecord<T>& record() const { return r_; }

  // Takes the field's value at t(): records the step, then moves t or ends the record.
  void feed(T v) {
    ++r_.steps;
    detail::Tracker<T>{r_}.saw(t_, v);
    if (refining_) {  // the secant's root: the hit moves there only where |f| is smaller than where it stopped
      if (!(std::abs(v) < stopped_abs_f_)) t_ = stopped_t_;
      return end(Outcome::hit);
    }
    if (!std::isfinite(v)) return end(Outcome::invalid);
    const T eps = hit_threshold(*s_, *c_, t_);
    if (r_.steps == 1 && v < -eps) return end(Outcome::inside);
    if (omega_ > T(1) && rule_.radii(std::abs(v), prev_f_) < prev_step_) {
      omega_ = 1;
      prev_step_ = rule_.step(prev_f_, T(1));
      t_ = prev_t_ + prev_step_;
    } else {
      if (v < eps) {
        // HitRefine::secant: one evaluation more, at the secant's root, where a step is left for it.
        const T root = s_->refine == sdf::HitRefine::secant && r_.steps > 1 && r_.steps < s_->max_steps
                           ? secant_root(prev_t_, prev_f_, t_, v)
                           : t_;
        if (root == t_) return end(Outcome::hit);
        refining_ = true;
        stopped_t_ = t_;
        stopped_abs_f_ = std::abs(v);
        t_ = root;
        return;
      }
      const T step = rule_.step(v, omega_);
      // An over-relaxed step past max_dist may yet be stepped back: the ray ends only where a plain step passes
      // max_dist too (the same test for the other marchers).
      const T plain_reach = t_ + rule_.step(v, T(1));
      prev_t_ = t_;
      prev_f_ = v;
      prev_step_ = step;
      t_ += step;
      if (t_ > max_dist_ && plain_reach > max_dist_) return end(Outcome::miss_far);
    }
    if (!(r_.steps < s_->max_steps)) end(Outcome::miss_steps);
  }

 private:
  void end(Outcome o) {
    r_.outcome = o;
    r_.t = t_;
    done_ = true;
  }
  const MarchSettings* s_ = nullptr;
  const MarchContext* c_ = nullptr;
  StepRule<T> rule_;
  T max_dist_ = 0, omega_ = 1, t_ = 0, prev_t_ = 0, prev_f_ = 0, prev_step_ = 0;
  T stopped_t_ = 0, stopped_abs_f_ = 0;  // where the march stopped, while its secant root is evaluated
  RayRecord<T> r_;
  bool done_ = false, refining_ = false;
};

// Fixed steps of fixed_step; a step that lands inside (f below -threshold) bisects the bracket from the previous
// point until |f| is below the threshold there. A state machine fed one value at a time, like SphereTrace.
template <class T>
class FixedTrace {
 public:
  FixedTrace() = default;
  // s and c must outlive the trace; max_dist replaces s.max_dist.
  FixedTrace(const MarchSettings& s, const MarchContext& c, T t_start, T max_dist)
      : s_(&s), c_(&c), max_dist_(max_dist), step_(T(s.fixed_step)), at_(t_start), prev_t_(t_start) {
    if (!(r_.steps < s.max_steps)) end(Outcome::miss_steps, at_);
  }
  bool done() const { return done_; }
  T t() const { return at_; }  // where the field is wanted next
  const RayRecord<T>& record() const { return r_; }

  void feed(T v) {
    ++r_.steps;
    detail::Tracker<T>{r_}.saw(at_, v);
    if (!std::isfinite(v)) return end(Outcome::invalid, at_);
    if (bisecting_) {
      const T mid = at_;
      if (std::abs(v) < hit_threshold(*s_, *c_, mid) || !(mid > lo_ && mid < hi_)) return end(Outcome::hit, mid);
      (v > 0 ? lo_ : hi_) = mid;
      return next_midpoint();
    }
    const T t = at_, eps = hit_threshold(*s_, *c_, t);
    if (r_.steps == 1 && v < -eps) return end(Outcome::inside, t);
    if (v < eps) {
      if (v > -eps || r_.steps == 1) return end(Outcome::hit, t);
      // Crossed the surface between the previous point (outside) and t (inside): bisect the bracket.
      bisecting_ = true;
      lo_ = prev_t_;
      hi_ = t;
      return next_midpoint();
    }
    prev_t_ = t;
    at_ = t + step_;
    if (at_ > max_dist_) return end(Outcome::miss_far, at_);
    if (!(r_.steps < s_->max_steps)) end(Outcome::miss_steps, at_);
  }

 private:
  void next_midpoint() {
    if (!(r_.steps < s_->max_steps)) return end(Outcome::miss_steps, lo_);
    at_ = lo_ + (hi_ - lo_) * T(0.5);
  }
  void end(Outcome o, T t) {
    detail::Tracker<T>{r_}.end(o, t);
    done_ = true;
  }
  const MarchSettings* s_ = nullptr;
  const MarchContext* c_ = nullptr;
  T max_dist_ = 0, step_ = 0, at_ = 0, prev_t_ = 0, lo_ = 0, hi_ = 0;
  RayRecord<T> r_;
  bool bisecting_ = false, done_ = false;
};

// Marches field f (any callable vec3<T> -> T) from origin along direction, starting at t_start.
// t is measured in units of |direction|: a direction that is not normalised is marched as given (as the
// seed shaders that forget to normalise do), which is what lets validation catch them.
template <class T, class F>
RayRecord<T> march(const F& f, glm::vec<3, T> origin, glm::vec<3, T> direction, const MarchSettings& s,
                   const MarchContext& c, T t_start = 0) {
  if (detail::ray_invalid(origin, direction, t_start, s, c)) {
    RayRecord<T> r;
    return detail::Tracker<T>{r}.end(Outcome::invalid, t_start);
  }
  const Span<T> span = clip_span(s, c, origin, direction, t_start, static_cast<T>(s.max_dist));
  if (span.empty()) {
    RayRecord<T> r;
    return detail::Tracker<T>{r}.end(Outcome::miss_far, t_start);
  }
  const auto run = [&](auto trace) {
    while (!trace.done()) trace.feed(f(origin + direction * trace.t()));
    return trace.record();
  };
  if (s.marcher == Marcher::fixed) return run(FixedTrace<T>(s, c, span.t0, span.t1));
  return run(SphereTrace<T>(s, c, span.t0, span.t1));
}

}  // namespace marchcheck::march
