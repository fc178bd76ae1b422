// Every numerical tolerance the suite judges with, named and derived in one place, as render, validate, the
// references and the stability battery use them. The model is pbrt's gamma(n): n floating-point operations,
// each rounding by at most the unit roundoff u, move a result by at most gamma(n) = n u / (1 - n u) relative.
#pragma once

#include <glm/glm.hpp>

#include <limits>


namespace marchcheck::march::tolerance {

// A length of 1e-7 relative to the magnitude x of the coordinates involved, absolute near zero: about float's
// rounding of a coordinate of that size (2^-24 = 6e-8 relative), eight orders above double's (1.1e-16). The
// scale of "the same place" for points a float march found.
inline double position_slack(double x) { return 1e-7 * (1 + x); }

// How far along its normal a reference shadow ray starts from the surface point p, so that it does not meet the
// surface it leaves: position_slack(|p|). (A float hit point can lie deeper inside than that.)
inline double shadow_lift(glm::dvec3 p) { return position_slack(glm::length(p)); }

// How far the hit point o + d t of a march in arithmetic of machine epsilon eps (twice the unit roundoff u) may
// lie from the exact point by rounding alone: each coordinate rounds three times (d t, the sum, and t itself,
// summed by the march), gamma(3) = 3 u to first order, relative to |o| + t; 4 eps = 8 u leaves a factor 2.7.
inline double hit_point_rounding(double eps, glm::dvec3 origin, double t) {
  return 4 * eps * (glm::length(origin) + t);
}

// How far a reference's double-precision hit o + d t (d unit length) may lie from the surface: its t's own error
// bound (exact casts 0, bisections their half width), which moves the point along d by as much and off the surface
// by at most that, plus double rounding of the point, hit_point_rounding at double's epsilon (every reference
// computes t and the point in a few dozen operations at most). Reference shadow rays start this far off.
inline double reference_hit_slack(glm::dvec3 origin, double t, double t_error) {
  return t_error + hit_point_rounding(std::numeric_limits<double>::epsilon(), origin, t);
}

// The numerical reference's march (steps of f / L, every sign change bisected): it never steps less than
// position_slack(t) (so it cannot stall where f vanishes without a sign change), reads |f| below kTouch as a touch
// of the surface, and bisects a crossing to kBisection in t, which is its t's error bound.
inline double reference_min_step(double t) { return position_slack(t); }
inline constexpr double kReferenceTouch = 1e-12;
inline constexpr double kReferenceBisection = 1e-9;

// Rays whose neighbours this far aside disagree with the reference are left out of the hit counts: two hit
// thresholds at the ray's scale plus position_slack there.
inline double grazing_band(double hit_threshold, double t) { return 2 * hit_threshold + position_slack(t); }

// Shadow rays whose neighbours this far aside (twice the hit threshold along the ray, plus 1e-6 of the shadow
// ray's length for the reference's own steps) change their verdict lie on a shadow's edge, left out.
inline double shadow_edge_band(double hit_threshold_along_ray, double shadow_ray_length) {
  return 2 * hit_threshold_along_ray + 1e-6 * (1 + shadow_ray_length);
}

// Neighbouring reference normals further apart than acos(0.985) = 9.9 degrees: a sharp edge or crease at this
// pixel.
inline constexpr double kSharpEdgeCos = 0.985;

// A float march's t at unit scale may sit this far from the exact one on top of its threshold: float rounding
// (machine epsilon 1.2e-7) of coordinates up to about 5 through the few dozen operations of one evaluation
// (5 x 1.2e-7 x 16 = 1e-5).
inline constexpr double kFloatRoundingNearUnit = 1e-5;

// The same relative to t at any scale S: float rounds the point's coordinates (about 4 S) to within 4 machine
// epsilons over one evaluation's few operations, 16 epsilons of t.
inline constexpr double kFloatRoundingRelative = 16 * static_cast<double>(std::numeric_limits<float>::epsilon());

}  // namespace marchcheck::march::tolerance
