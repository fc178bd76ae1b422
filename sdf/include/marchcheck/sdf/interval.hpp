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

#include <algorithm>
#include <cmath>
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
  // The largest |x| over the interval.
  constexpr double magnitude() const { return std::max(lo < 0 ? -lo : lo, hi < 0 ? -hi : hi); }
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

// An upper bound on |g| for every g in the box of vectors g.
double norm_bound(const glm::vec<3, Interval>& g);

// Value and gradient over a box: the gradient's interval holds the gradient (one-sided ones at kinks) of every
// point of the box, and n bounds its length. The box of the gradient alone loses what a minimum of two unit
// gradients keeps (a convex combination of them, of length at most 1, where their box reaches sqrt 2): n
// follows each operation's own rule (the larger of the two for min, max and smooth minima, sums for sums) and
// is tightened by the box's length at every step. The basis of a certified Lipschitz bound.
template <>
struct Dual<Interval> {
  Interval v;
  glm::vec<3, Interval> d;
  double n;  // an upper bound on the gradient's length over the box

  Dual() = default;
  Dual(Interval value) : v(value), d(Interval(0.0)), n(0) {}  // NOLINT: constants promote implicitly
  Dual(double value) : Dual(Interval(value)) {}               // NOLINT
  Dual(Interval value, glm::vec<3, Interval> grad) : v(value), d(grad), n(norm_bound(grad)) {}
  Dual(Interval value, glm::vec<3, Interval> grad, double bound)
      : v(value), d(grad), n(std::min(bound, norm_bound(grad))) {}

  Dual& operator+=(Dual b);
  Dual& operator-=(Dual b);
  Dual& operator*=(Dual b);
  Dual& operator/=(Dual b);
};
using DualInterval = Dual<Interval>;

DualInterval operator+(DualInterval a, DualInterval b);
DualInterval operator-(DualInterval a, DualInterval b);
DualInterval operator-(DualInterval a);
DualInterval operator*(DualInterval a, DualInterval b);
DualInterval operator/(DualInterval a, DualInterval b);
DualInterval sqrt(DualInterval a);
DualInterval abs(DualInterval a);
DualInterval min(DualInterval a, DualInterval b);
DualInterval max(DualInterval a, DualInterval b);
DualInterval floor(DualInterval a);  // its jumps are the domain operators' to make continuous
DualInterval sign(DualInterval a);
DualInterval sin(DualInterval a);
DualInterval cos(DualInterval a);
DualInterval hull(DualInterval a, DualInterval b);

// A bound on the spectral norm of the Jacobian whose rows are the gradients of a: the largest eigenvalue of
// J J^T by Gershgorin's discs, each row's length bound squared plus its products with the other rows (intervals),
// so orthogonal rows of length 1 (the point itself, a revolution's (radius, height)) give 1.
template <int N>
double jacobian_bound(const glm::vec<N, DualInterval>& a) {
  Interval largest(0.0);
  for (int i = 0; i < N; ++i) {
    Interval disc = square(Interval(a[i].n));
    for (int j = 0; j < N; ++j) {
      if (j == i) continue;
      const Interval dot = a[i].d.x * a[j].d.x + a[i].d.y * a[j].d.y + a[i].d.z * a[j].d.z;
      disc += Interval(dot.magnitude());
    }
    largest = max(largest, disc);
  }
  return sqrt(largest).hi;
}

// The gradient of a length is the Jacobian's transpose times a unit vector: each of its components within
// [-1, 1] where the length may be 0, and its length at most the Jacobian's norm.
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
  return {len, d, jacobian_bound(a)};
}

// The field's range over the box p (each component an interval of coordinates). GLSL fields have no interval
// rule: their value over a box is the whole line (interval_supported says whether a tape has one).
template <>
Interval evaluate<Interval>(const Tape& tape, glm::vec<3, Interval> p);
// Its range and its gradient's over the box (p: seeded(box), scalar.hpp).
template <>
DualInterval evaluate<DualInterval>(const Tape& tape, glm::vec<3, DualInterval> p);

// The box seeded for the gradient evaluation, out of line: compiled where the gradient intervals are (GCC 12's
// SLP vectoriser with AVX-512 miscompiles them inlined elsewhere: sdf/CMakeLists.txt).
template <>
glm::vec<3, DualInterval> seeded<Interval>(glm::vec<3, Interval> box);

// Whether every instruction of the tape has an interval rule that can prove something (not a GLSL field).
bool interval_supported(const Tape& tape);

}  // namespace marchcheck::sdf
