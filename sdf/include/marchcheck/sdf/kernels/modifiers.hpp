// Kernels of the operators that modify a distance (their rules: sdf/src/ops/modifiers.cpp).
#pragma once

#include "marchcheck/sdf/kernels/kernel.hpp"

#include <algorithm>

#define MARCHCHECK_MODIFIER_KERNELS(X) X(round_, value) X(onion, value) X(displace, value) X(grid, source)

namespace marchcheck::sdf::kernels {

using namespace smath;

template <class T>
MARCHCHECK_KERNEL T round_(const Args<T>& k, T d, vec3<T>) {
  return d - k(0);
}

template <class T>
MARCHCHECK_KERNEL T onion(const Args<T>& k, T d, vec3<T>) {
  return abs(d) - k(0);
}

template <class T>
MARCHCHECK_KERNEL T displace(const Args<T>& k, T d, vec3<T> p) {
  const T f = k(1);
  return d + k(0) * sin(f * p.x) * sin(f * p.y) * sin(f * p.z);
}

// Trilinear interpolation of the child's samples; outside the grid, the nearest grid point's value plus the
// distance to it. k: counts, lowest corner, cell, then the samples (x fastest).
template <class T>
MARCHCHECK_KERNEL T grid(const Args<T>& k, vec3<T> p) {
  using S = decltype(value_of(T{}));
  int n[3], cell0[3];
  vec3<T> f;
  const T cell = k(6);
  const vec3<T> g = (p - vec3<T>(k(3), k(4), k(5))) / cell;  // in cells from the lowest sample
  vec3<T> c;
  for (int i = 0; i < 3; ++i) {
    n[i] = static_cast<int>(k.raw(static_cast<std::uint32_t>(i)));
    c[i] = clamp(g[i], T(0), T(static_cast<S>(n[i] - 1)));
    cell0[i] = std::min(static_cast<int>(value_of(c[i])), n[i] - 2);
    f[i] = c[i] - T(static_cast<S>(cell0[i]));
  }
  auto s = [&](int dx, int dy, int dz) {
    return k(7 + static_cast<std::uint32_t>(cell0[0] + dx + n[0] * (cell0[1] + dy + n[1] * (cell0[2] + dz))));
  };
  const T y0 = mix(mix(s(0, 0, 0), s(1, 0, 0), f.x), mix(s(0, 1, 0), s(1, 1, 0), f.x), f.y);
  const T y1 = mix(mix(s(0, 0, 1), s(1, 0, 1), f.x), mix(s(0, 1, 1), s(1, 1, 1), f.x), f.y);
  return mix(y0, y1, f.z) + length(g - c) * cell;
}

}  // namespace marchcheck::sdf::kernels
