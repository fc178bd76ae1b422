// Interval arithmetic over the tape: the field evaluated over a box bounds every value it takes there, so a box
// where it is positive provably holds no surface (the certified references, validation/certified.hpp). The
// arithmetic is Boost.Interval's, rounded outwards by the hardware's directed rounding; the transcendental
// functions, which Boost only calls in the ordinary way, are glibc's widened by more than its documented error.
// Where a value may be NaN (a square root or logarithm of a negative, 0 x inf), the result is the whole line:
// libfive's "unsafe" flag, as an interval that proves nothing.
#pragma once

#include "marchcheck/sdf/scalar.hpp"
#include "marchcheck/sdf/tape.hpp"

#include <glm/glm.hpp>

#include <limits>

namespace marchcheck::sdf {

struct Interval {
  // No member initialisers: GLM vectors of intervals need a trivial default constructor.
  double lo, hi;

  Interval() = default;
  constexpr Interval(double x) : lo(x), hi(x) {}  // NOLINT: constants promote implicitly, as in the kernels
  constexpr Interval(double low, double high) : lo(low), hi(high) {}
  static constexpr Interval entire() {
    return {-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  }

  constexpr bool contains(double x) const { return lo <= x && x <= hi; }
  constexpr double width() const { return hi - lo; }
  constexpr bool is_entire() const { return lo == entire().lo && hi == entire().hi; }

  Interval& operator+=(Interval b);
  Interval& operator-=(Interval b);
  Interval& operator*=(Interval b);
  Interval& operator/=(Interval b);
};

// + - x / and the square root rounded outwards (Boost.Interval); the others exact or widened past libm's error.
Interval operator+(Interval a, Interval b);
Interval operator-(Interval a, Interval b);
Interval operator-(Interval a);
Interval operator*(Interval a, Interval b);
Interval operator/(Interval a, Interval b);
Interval square(Interval a);
Interval sqrt(Interval a);
Interval abs(Interval a);
Interval min(Interval a, Interval b);
Interval max(Interval a, Interval b);
Interval floor(Interval a);
Interval sign(Interval a);
Interval sin(Interval a);
Interval cos(Interval a);
Interval log(Interval a);
// The smallest interval holding both.
Interval hull(Interval a, Interval b);

// Length as the root of a sum of squares: x * x over an interval holding 0 would be negative in part.
template <int N>
Interval length(glm::vec<N, Interval> a) {
  Interval s = square(a[0]);
  for (int i = 1; i < N; ++i) s += square(a[i]);
  return sqrt(s);
}

// Value and gradient over a box: the gradient's interval holds the gradient (one-sided ones at kinks) of every
// point of the box, the basis of a certified Lipschitz bound.
using DualInterval = Dual<Interval>;

DualInterval sqrt(DualInterval a);
DualInterval abs(DualInterval a);
DualInterval min(DualInterval a, DualInterval b);
DualInterval max(DualInterval a, DualInterval b);
DualInterval floor(DualInterval a);  // its jumps are the domain operators' to make continuous
DualInterval sign(DualInterval a);
DualInterval sin(DualInterval a);
DualInterval cos(DualInterval a);
DualInterval hull(DualInterval a, DualInterval b);

// The gradient of a length is a unit vector: bounded by [-1, 1] per component where the length may be 0.
template <int N>
DualInterval length(glm::vec<N, DualInterval> a) {
  glm::vec<N, Interval> v;
  for (int i = 0; i < N; ++i) v[i] = a[i].v;
  const Interval len = length(v);
  glm::vec<3, Interval> d(0.0);
  for (int i = 0; i < N; ++i) {
    const Interval u = len.lo > 0 ? v[i] / len : Interval(-1, 1);
    const Interval unit(std::max(u.lo, -1.0), std::min(u.hi, 1.0));
    d += a[i].d * unit;
  }
  return {len, d};
}

// The field's range over the box p (each component an interval of coordinates). GLSL fields have no interval
// rule: their value over a box is the whole line (interval_supported says whether a tape has one).
template <>
Interval evaluate<Interval>(const Tape& tape, glm::vec<3, Interval> p);
// Its range and its gradient's over the box (seed p with the identity's derivatives).
template <>
DualInterval evaluate<DualInterval>(const Tape& tape, glm::vec<3, DualInterval> p);
// The box as the gradient evaluation takes it: each coordinate seeded with its unit derivative.
glm::vec<3, DualInterval> seeded(glm::vec<3, Interval> box);

// Whether every instruction of the tape has an interval rule that can prove something (not a GLSL field).
bool interval_supported(const Tape& tape);

}  // namespace marchcheck::sdf
