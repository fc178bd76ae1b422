// Kernels of the domain operators: each pushes the point its child is evaluated at (their rules:
// sdf/src/ops/domain.cpp). scale_value is the scale's second half, f(p / s) * s.
#pragma once

#include "marchcheck/sdf/kernels/kernel.hpp"

#define MARCHCHECK_DOMAIN_KERNELS(X)                                                                         \
  X(p_translate, point) X(p_affine, point) X(p_scale, point) X(scale_value, value) X(p_repeat, point)     \
  X(p_repeat_limited, point) X(p_mirror, point) X(p_twist, point) X(p_warp, point)

namespace marchcheck::sdf::kernels {

using namespace smath;

template <class T>
MARCHCHECK_KERNEL vec3<T> p_translate(const Args<T>& k, vec3<T> p) {
  return p - vec3<T>(k(0), k(1), k(2));
}

template <class T>
MARCHCHECK_KERNEL vec3<T> p_affine(const Args<T>& k, vec3<T> p) {  // row-major 3x4
  return vec3<T>(p.x * k(0) + p.y * k(1) + p.z * k(2) + k(3), p.x * k(4) + p.y * k(5) + p.z * k(6) + k(7),
               p.x * k(8) + p.y * k(9) + p.z * k(10) + k(11));
}

template <class T>
MARCHCHECK_KERNEL vec3<T> p_scale(const Args<T>& k, vec3<T> p) {  // k: 1 / factor
  return p * k(0);
}

template <class T>
MARCHCHECK_KERNEL T scale_value(const Args<T>& k, T d, vec3<T>) {
  return d * k(0);
}

template <class T>
MARCHCHECK_KERNEL vec3<T> p_repeat(const Args<T>& k, vec3<T> p) {
  vec3<T> q = p;
  for (int i = 0; i < 3; ++i) {
    const T c = k(static_cast<std::uint32_t>(i));
    if (value_of(c) > 0) q[i] = p[i] - c * round(p[i] / c);
  }
  return q;
}

template <class T>
MARCHCHECK_KERNEL vec3<T> p_repeat_limited(const Args<T>& k, vec3<T> p) {
  vec3<T> q = p;
  for (int i = 0; i < 3; ++i) {
    const T c = k(static_cast<std::uint32_t>(i)), n = k(3 + static_cast<std::uint32_t>(i));
    if (value_of(c) > 0) q[i] = p[i] - c * clamp(round(p[i] / c), -n, n);
  }
  return q;
}

template <class T>
MARCHCHECK_KERNEL vec3<T> p_mirror(const Args<T>& k, vec3<T> p) {
  vec3<T> q = p;
  for (int i = 0; i < 3; ++i)
    if (k.raw(static_cast<std::uint32_t>(i)) > 0.5) q[i] = abs(q[i]);
  return q;
}

template <class T>
MARCHCHECK_KERNEL vec3<T> p_twist(const Args<T>& k, vec3<T> p) {
  const T ang = k(0) * p.y;
  const T c = cos(ang), s = sin(ang);
  return vec3<T>(c * p.x - s * p.z, p.y, s * p.x + c * p.z);
}

// k = (ax, kx, ay, ky, oz): q = p - (ax sin(kx y), ay sin(ky x), oz)
template <class T>
MARCHCHECK_KERNEL vec3<T> p_warp(const Args<T>& k, vec3<T> p) {
  return vec3<T>(p.x - k(0) * sin(k(1) * p.y), p.y - k(2) * sin(k(3) * p.x), p.z - k(4));
}

}  // namespace marchcheck::sdf::kernels
