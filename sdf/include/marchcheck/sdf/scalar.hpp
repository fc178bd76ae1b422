// Scalar types the distance-field language runs in: float (what a shader does), double (references) and
// Dual<T> (forward-mode automatic differentiation for analytic normals), with the math the fields use.
#pragma once

#include "marchcheck/sdf/vector_math.hpp"

#include <glm/glm.hpp>

#include <cmath>
#include <type_traits>

namespace marchcheck::sdf {

// A value with its gradient with respect to the evaluation point.
template <class T>
struct Dual {
  // No member initialisers: GLM vectors of Dual need a trivial default constructor.
  T v;
  glm::vec<3, T> d;

  Dual() = default;
  constexpr Dual(T value) : v(value), d(0) {}  // NOLINT: constants promote implicitly, as in GLSL
  constexpr Dual(T value, glm::vec<3, T> grad) : v(value), d(grad) {}

  friend constexpr Dual operator+(Dual a, Dual b) { return {a.v + b.v, a.d + b.d}; }
  friend constexpr Dual operator-(Dual a, Dual b) { return {a.v - b.v, a.d - b.d}; }
  friend constexpr Dual operator-(Dual a) { return {-a.v, -a.d}; }
  friend constexpr Dual operator*(Dual a, Dual b) { return {a.v * b.v, a.d * b.v + b.d * a.v}; }
  friend constexpr Dual operator/(Dual a, Dual b) {
    return {a.v / b.v, (a.d * b.v - b.d * a.v) / (b.v * b.v)};
  }
  Dual& operator+=(Dual b) { return *this = *this + b; }
  Dual& operator-=(Dual b) { return *this = *this - b; }
  Dual& operator*=(Dual b) { return *this = *this * b; }
  Dual& operator/=(Dual b) { return *this = *this / b; }
  friend constexpr bool operator<(Dual a, Dual b) { return a.v < b.v; }
  friend constexpr bool operator>(Dual a, Dual b) { return a.v > b.v; }
  friend constexpr bool operator<=(Dual a, Dual b) { return a.v <= b.v; }
  friend constexpr bool operator>=(Dual a, Dual b) { return a.v >= b.v; }
};

template <class T>
struct is_dual : std::false_type {};
template <class T>
struct is_dual<Dual<T>> : std::true_type {};

// The plain value of a scalar (strips derivatives).
template <class T>
constexpr auto value_of(T x) {
  if constexpr (is_dual<T>::value) {
    return x.v;
  } else {
    return x;
  }
}

// The point as forward-mode differentiation takes it: each coordinate seeded with its unit derivative, so that
// a field evaluated at it carries its gradient.
template <class T>
glm::vec<3, Dual<T>> seeded(glm::vec<3, T> p) {
  using V = glm::vec<3, T>;
  return {Dual<T>(p.x, V(T(1), T(0), T(0))), Dual<T>(p.y, V(T(0), T(1), T(0))), Dual<T>(p.z, V(T(0), T(0), T(1)))};
}

namespace smath {

template <class T>
using vec2 = glm::vec<2, T>;
template <class T>
using vec3 = glm::vec<3, T>;

template <class T>
inline T sqrt(T x) {
  if constexpr (is_dual<T>::value) {
    const auto s = std::sqrt(x.v);
    // The derivative at 0 is infinite; report 0 so a gradient through a kink stays finite.
    const auto k = s > 0 ? decltype(s)(0.5) / s : decltype(s)(0);
    return {s, x.d * k};
  } else {
    return std::sqrt(x);
  }
}
template <class T>
inline T abs(T x) {
  if constexpr (is_dual<T>::value) {
    return x.v < 0 ? -x : x;
  } else {
    return std::abs(x);
  }
}
template <class T>
inline T sin(T x) {
  if constexpr (is_dual<T>::value) {
    return {vmath::sin(x.v), x.d * vmath::cos(x.v)};
  } else {
    return vmath::sin(x);
  }
}
template <class T>
inline T cos(T x) {
  if constexpr (is_dual<T>::value) {
    return {vmath::cos(x.v), x.d * -vmath::sin(x.v)};
  } else {
    return vmath::cos(x);
  }
}
template <class T>
inline T log(T x) {
  if constexpr (is_dual<T>::value) {
    return {vmath::log(x.v), x.d / x.v};
  } else {
    return vmath::log(x);
  }
}
template <class T>
inline T atan2(T y, T x) {
  if constexpr (is_dual<T>::value) {
    const auto r2 = x.v * x.v + y.v * y.v;
    return {vmath::atan2(y.v, x.v), (y.d * x.v - x.d * y.v) / r2};
  } else {
    return vmath::atan2(y, x);
  }
}
template <class T>
inline T acos(T x) {
  if constexpr (is_dual<T>::value) {
    const auto s = std::sqrt(std::max(decltype(x.v)(0), 1 - x.v * x.v));
    return {vmath::acos(x.v), s > 0 ? x.d * (-1 / s) : x.d * decltype(x.v)(0)};
  } else {
    return vmath::acos(x);
  }
}
// x^e for a constant exponent.
template <class T, class E>
inline T pow(T x, E e) {
  if constexpr (is_dual<T>::value) {
    using S = decltype(x.v);
    const S p = vmath::pow(x.v, static_cast<S>(e));
    return {p, x.d * (static_cast<S>(e) * vmath::pow(x.v, static_cast<S>(e - 1)))};
  } else {
    return vmath::pow(x, static_cast<T>(e));
  }
}
// floor is piecewise constant: its derivative is zero.
template <class T>
inline T floor(T x) {
  if constexpr (is_dual<T>::value) {
    return T(vmath::floor(x.v));
  } else {
    return vmath::floor(x);
  }
}
template <class T>
inline T round(T x) {
  return floor(x + T(0.5));
}
template <class T>
inline T min(T a, T b) {
  return b < a ? b : a;
}
template <class T>
inline T max(T a, T b) {
  return a < b ? b : a;
}
template <class T>
inline T clamp(T x, T lo, T hi) {
  return min(max(x, lo), hi);
}
template <class T>
inline T mix(T a, T b, T t) {
  return a + (b - a) * t;
}
template <class T>
inline T sign(T x) {
  return T(value_of(x) > 0 ? 1 : (value_of(x) < 0 ? -1 : 0));
}

template <class T, int N>
inline T dot(glm::vec<N, T> a, glm::vec<N, T> b) {
  T s = a[0] * b[0];
  for (int i = 1; i < N; ++i) s += a[i] * b[i];
  return s;
}
template <class T, int N>
inline T length(glm::vec<N, T> a) {
  return sqrt(dot(a, a));
}
template <class T, int N>
inline glm::vec<N, T> abs(glm::vec<N, T> a) {
  for (int i = 0; i < N; ++i) a[i] = abs(a[i]);
  return a;
}
template <class T, int N>
inline glm::vec<N, T> max(glm::vec<N, T> a, T b) {
  for (int i = 0; i < N; ++i) a[i] = max(a[i], b);
  return a;
}
template <class T, int N>
inline glm::vec<N, T> min(glm::vec<N, T> a, T b) {
  for (int i = 0; i < N; ++i) a[i] = min(a[i], b);
  return a;
}
template <class T, int N>
inline T max_component(glm::vec<N, T> a) {
  T m = a[0];
  for (int i = 1; i < N; ++i) m = max(m, a[i]);
  return m;
}

}  // namespace smath
}  // namespace marchcheck::sdf
