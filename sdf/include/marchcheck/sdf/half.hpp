// IEEE binary16 arithmetic, as GLSL's mediump runs on mobile GPUs: a float that always holds a binary16 value,
// every operation computed in float and rounded to binary16 (to nearest, ties to even). Rounding twice is exact
// here: float's 24 bits are at least twice binary16's 11 plus 2, so + - * / and sqrt computed in float and
// rounded give the correctly rounded binary16 result. Transcendentals are float's, rounded. The rounding is done on
// the bits (clang 14 has no _Float16 on x86); a test holds it to GCC's _Float16 conversion.
#pragma once

#include <bit>
#include <concepts>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

namespace marchcheck::sdf {

// x (float or double) rounded to binary16: normal values to 11 significant bits, subnormals to multiples of
// 2^-24, and past +-65520 (the midpoint above the largest, 65504, which rounds up: ties to even) to infinity.
template <class F>
inline float round_to_half(F x) {
  if (!(x < F(65520) && x > F(-65520))) return x != x ? static_cast<float>(x) : x > 0 ? INFINITY : -INFINITY;
  if (x < F(0x1p-14) && x > F(-0x1p-14)) return static_cast<float>(std::nearbyint(x * F(0x1p24)) * F(0x1p-24));
  using U = std::conditional_t<sizeof(F) == 4, std::uint32_t, std::uint64_t>;
  constexpr int drop = std::numeric_limits<F>::digits - 11;  // significand bits binary16 has no room for
  U bits = std::bit_cast<U>(x);
  bits += (U(1) << (drop - 1)) - 1 + ((bits >> drop) & 1);  // half an ulp up, a hair less where it would tie odd
  bits &= ~((U(1) << drop) - 1);
  return static_cast<float>(std::bit_cast<F>(bits));
}

struct Half {
  float v;  // no initialiser: GLM vectors of Half (the tape's points) need a trivial default constructor
  Half() = default;
  Half(double x) : v(round_to_half(x)) {}  // NOLINT: rounds, as a store does
  Half(float x) : v(round_to_half(x)) {}   // NOLINT
  template <std::integral I>
  Half(I x) : Half(static_cast<double>(x)) {}  // NOLINT
  operator float() const { return v; }           // NOLINT: reads are exact
  Half& operator+=(Half b) { return *this = Half(v + b.v); }
  Half& operator-=(Half b) { return *this = Half(v - b.v); }
  Half& operator*=(Half b) { return *this = Half(v * b.v); }
  Half& operator/=(Half b) { return *this = Half(v / b.v); }
  friend Half operator-(Half a) { return Half(-a.v); }
};

// Half with Half, or with a number (rounded to binary16 first, as GLSL's mediump operands are): the templates
// match exactly, so no mix of the conversions above is ambiguous.
template <class A, class B>
concept HalfOperands = (std::is_same_v<A, Half> || std::is_same_v<B, Half>) &&
                       (std::is_same_v<A, Half> || std::is_arithmetic_v<A>) &&
                       (std::is_same_v<B, Half> || std::is_arithmetic_v<B>);
template <class A, class B>
  requires HalfOperands<A, B>
Half operator+(A a, B b) { return Half(Half(a).v + Half(b).v); }
template <class A, class B>
  requires HalfOperands<A, B>
Half operator-(A a, B b) { return Half(Half(a).v - Half(b).v); }
template <class A, class B>
  requires HalfOperands<A, B>
Half operator*(A a, B b) { return Half(Half(a).v * Half(b).v); }
template <class A, class B>
  requires HalfOperands<A, B>
Half operator/(A a, B b) { return Half(Half(a).v / Half(b).v); }
template <class A, class B>
  requires HalfOperands<A, B>
bool operator<(A a, B b) { return Half(a).v < Half(b).v; }
template <class A, class B>
  requires HalfOperands<A, B>
bool operator>(A a, B b) { return Half(a).v > Half(b).v; }
template <class A, class B>
  requires HalfOperands<A, B>
bool operator<=(A a, B b) { return Half(a).v <= Half(b).v; }
template <class A, class B>
  requires HalfOperands<A, B>
bool operator>=(A a, B b) { return Half(a).v >= Half(b).v; }
template <class A, class B>
  requires HalfOperands<A, B>
bool operator==(A a, B b) { return Half(a).v == Half(b).v; }

}  // namespace marchcheck::sdf
