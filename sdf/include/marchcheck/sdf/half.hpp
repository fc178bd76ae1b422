// IEEE binary16 arithmetic, as GLSL's mediump runs on mobile GPUs: a float that always holds a binary16 value,
// every operation computed in float and rounded to binary16 (GCC's _Float16 conversion, to nearest, ties to even).
// Rounding twice is exact here: float's 24 bits are at least twice binary16's 11 plus 2, so + - * / and sqrt
// computed in float and rounded give the correctly rounded binary16 result. Transcendentals are float's, rounded.
#pragma once

#include <cmath>
#include <type_traits>

namespace marchcheck::sdf {

// x rounded to binary16: past +-65520 (the midpoint above the largest, 65504, which rounds up: ties to even) to
// infinity, as IEEE rounds; converting there would be undefined in C++.
template <class F>
constexpr float round_to_half(F x) {
  if (x < F(65520) && x > F(-65520)) return static_cast<float>(static_cast<_Float16>(x));
  return x != x ? static_cast<float>(x) : x > 0 ? __builtin_inff() : -__builtin_inff();
}

struct Half {
  float v = 0;
  Half() = default;
  constexpr Half(double x) : v(round_to_half(x)) {}  // NOLINT: rounds, as a store does
  constexpr Half(float x) : v(round_to_half(x)) {}   // NOLINT
  constexpr Half(int x) : Half(static_cast<double>(x)) {}                        // NOLINT
  constexpr operator float() const { return v; }                                 // NOLINT: reads are exact
  Half& operator+=(Half b) { return *this = Half(v + b.v); }
  Half& operator-=(Half b) { return *this = Half(v - b.v); }
  Half& operator*=(Half b) { return *this = Half(v * b.v); }
  Half& operator/=(Half b) { return *this = Half(v / b.v); }
  friend constexpr Half operator-(Half a) { return Half(-a.v); }
};

// Half with Half, or with a number (rounded to binary16 first, as GLSL's mediump operands are): the templates
// match exactly, so no mix of the conversions above is ambiguous.
template <class A, class B>
concept HalfOperands = (std::is_same_v<A, Half> || std::is_same_v<B, Half>) &&
                       (std::is_same_v<A, Half> || std::is_arithmetic_v<A>) &&
                       (std::is_same_v<B, Half> || std::is_arithmetic_v<B>);
template <class A, class B>
  requires HalfOperands<A, B>
constexpr Half operator+(A a, B b) { return Half(Half(a).v + Half(b).v); }
template <class A, class B>
  requires HalfOperands<A, B>
constexpr Half operator-(A a, B b) { return Half(Half(a).v - Half(b).v); }
template <class A, class B>
  requires HalfOperands<A, B>
constexpr Half operator*(A a, B b) { return Half(Half(a).v * Half(b).v); }
template <class A, class B>
  requires HalfOperands<A, B>
constexpr Half operator/(A a, B b) { return Half(Half(a).v / Half(b).v); }
template <class A, class B>
  requires HalfOperands<A, B>
constexpr bool operator<(A a, B b) { return Half(a).v < Half(b).v; }
template <class A, class B>
  requires HalfOperands<A, B>
constexpr bool operator>(A a, B b) { return Half(a).v > Half(b).v; }
template <class A, class B>
  requires HalfOperands<A, B>
constexpr bool operator<=(A a, B b) { return Half(a).v <= Half(b).v; }
template <class A, class B>
  requires HalfOperands<A, B>
constexpr bool operator>=(A a, B b) { return Half(a).v >= Half(b).v; }
template <class A, class B>
  requires HalfOperands<A, B>
constexpr bool operator==(A a, B b) { return Half(a).v == Half(b).v; }

}  // namespace marchcheck::sdf
