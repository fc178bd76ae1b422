// Kernels of the combinations of two values (their rules: sdf/src/ops/combinations.cpp). The result's
// material is the one of the operand that decides the value.
#pragma once

#include "marchcheck/sdf/kernels/kernel.hpp"

#define MARCHCHECK_COMBINATION_KERNELS(X)                                                            \
  X(min_, binary) X(max_, binary) X(subtract, binary) X(smooth_min, binary) X(smooth_max, binary) \
  X(smooth_subtract, binary)

namespace marchcheck::sdf::kernels {

using namespace smath;

// Polynomial smooth minimum (Inigo Quilez): min(a, b) - h^2 k / 4.
template <class T>
MARCHCHECK_KERNEL T polynomial_smooth_min(T a, T b, T k) {
  const T h = max(k - abs(a - b), T(0)) / k;
  return min(a, b) - h * h * k * T(0.25);
}

template <class T>
MARCHCHECK_KERNEL Combined<T> min_(const Args<T>&, T a, T b) {
  const bool take_b = b < a;
  return {take_b ? b : a, take_b};
}

template <class T>
MARCHCHECK_KERNEL Combined<T> max_(const Args<T>&, T a, T b) {
  const bool take_b = a < b;
  return {take_b ? b : a, take_b};
}

template <class T>
MARCHCHECK_KERNEL Combined<T> subtract(const Args<T>&, T a, T b) {  // max(a, -b)
  const bool take_b = a < -b;
  return {take_b ? -b : a, take_b};
}

template <class T>
MARCHCHECK_KERNEL Combined<T> smooth_min(const Args<T>& k, T a, T b) {
  return {polynomial_smooth_min(a, b, k(0)), b < a};
}

template <class T>
MARCHCHECK_KERNEL Combined<T> smooth_max(const Args<T>& k, T a, T b) {
  return {-polynomial_smooth_min(-a, -b, k(0)), a < b};
}

template <class T>
MARCHCHECK_KERNEL Combined<T> smooth_subtract(const Args<T>& k, T a, T b) {
  return {-polynomial_smooth_min(-a, b, k(0)), a < -b};
}

}  // namespace marchcheck::sdf::kernels
