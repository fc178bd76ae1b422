#include "marchcheck/sdf/scalar.hpp"
#include "marchcheck/validation/reference.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace marchcheck::validation {

using glm::dvec3;

namespace {

// One step of the orbit, w -> w^power + p, in the spherical coordinates the estimator uses (polar angle from
// +y, azimuth atan2(x, z)). T is double, or Dual<double> for the boundary's normal.
template <class T>
glm::vec<3, T> orbit_step(const glm::vec<3, T>& w, const glm::vec<3, T>& p, double power) {
  using namespace sdf::smath;
  const T r = length(w);
  if (!(sdf::value_of(r) > 0)) return p;  // 0^power: the angles do not matter
  const T polar = acos(clamp(w.y / r, T(-1), T(1))) * T(power);
  const T azimuth = atan2(w.x, w.z) * T(power);
  return p + glm::vec<3, T>(sin(polar) * sin(azimuth), cos(polar), sin(polar) * cos(azimuth)) * pow(r, power);
}

}  // namespace

EscapeTimeSet::EscapeTimeSet(const sdf::Node& mandelbulb)
    : power_(mandelbulb.scalar("power")), bailout2_(mandelbulb.scalar("bailout") * mandelbulb.scalar("bailout")),
      iterations_(static_cast<int>(mandelbulb.scalar("iterations"))) {
  // The root of R^power - R = bailout above 1 (the left side grows there), by bisection, then a margin.
  const double bailout = mandelbulb.scalar("bailout");
  double lo = 1, hi = 1 + bailout;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (std::pow(mid, power_) - mid > bailout ? hi : lo) = mid;
  }
  radius_ = hi * (1 + 1e-9);
}

double EscapeTimeSet::final_radius2(dvec3 p) const {
  dvec3 w = p;
  for (int i = 1; i <= iterations_; ++i) {
    w = orbit_step(w, p, power_);
    if (glm::dot(w, w) > bailout2_) return std::numeric_limits<double>::infinity();  // from here on |w| only grows
  }
  return glm::dot(w, w);
}

ReferenceHit EscapeTimeSet::first_hit(dvec3 o, dvec3 d, double t_max, double resolution) const {
  ReferenceHit out;
  if (contains(o)) {
    out.inside = true;
    return out;
  }
  // Only the ball of radius() can hold the set.
  const double b = glm::dot(o, d), c = glm::dot(o, o) - radius_ * radius_, disc = b * b - c;
  if (disc < 0) return out;
  const double t_end = std::min(t_max, -b + std::sqrt(disc));
  double t = std::max(0.0, -b - std::sqrt(disc));
  while (t < t_end) {
    const double next = std::min(t_end, t + std::clamp(0.01 * t, 1e-3 * resolution, resolution));
    if (contains(o + d * next)) {
      double outside = t, inside = next;
      while (inside - outside > 1e-11 * (1 + inside)) {
        const double mid = 0.5 * (outside + inside);
        (contains(o + d * mid) ? inside : outside) = mid;
      }
      out.hit = true;
      out.t = 0.5 * (outside + inside);
      // The boundary is |w_N| = 1 (an orbit past the bailout is far from it).
      using D = sdf::Dual<double>;
      const dvec3 q = o + d * outside;
      const glm::vec<3, D> p(D(q.x, {1, 0, 0}), D(q.y, {0, 1, 0}), D(q.z, {0, 0, 1}));
      glm::vec<3, D> w = p;
      for (int i = 0; i < iterations_; ++i) w = orbit_step(w, p, power_);
      const dvec3 g = sdf::smath::dot(w, w).d;
      out.normal = glm::length(g) > 0 ? glm::normalize(g) : -d;
      return out;
    }
    t = next;
  }
  return out;
}

}  // namespace marchcheck::validation
