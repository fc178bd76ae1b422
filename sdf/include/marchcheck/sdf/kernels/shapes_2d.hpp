// Kernels of the 2D shapes (in the xy plane of their point) and of the operators that make 3D shapes of them
// (their rules: sdf/src/ops/shapes_2d.cpp).
#pragma once

#include "marchcheck/sdf/kernels/kernel.hpp"

#define MARCHCHECK_SHAPE_2D_KERNELS(X) \
  X(circle, source) X(rect, source) X(segment, source) X(extrude, value) X(p_revolve, point)

namespace marchcheck::sdf::kernels {

using namespace smath;

template <class T>
MARCHCHECK_KERNEL T circle(const Args<T>& k, vec3<T> p) {
  return length(vec2<T>(p.x - k(0), p.y - k(1))) - k(2);
}

template <class T>
MARCHCHECK_KERNEL T rect(const Args<T>& k, vec3<T> p) {
  const vec2<T> d = abs(vec2<T>(p.x - k(0), p.y - k(1))) - vec2<T>(k(2), k(3));
  return length(max(d, T(0))) + min(max(d.x, d.y), T(0));
}

template <class T>
MARCHCHECK_KERNEL T segment(const Args<T>& k, vec3<T> p) {
  const vec2<T> pa(p.x - k(0), p.y - k(1));
  const vec2<T> ba(k(2), k(3));  // b - a
  const T h = clamp(dot(pa, ba) * k(4), T(0), T(1));
  return length(pa - ba * h) - k(5);
}

// The 2D distance d combined with the slab |z| <= half_depth.
template <class T>
MARCHCHECK_KERNEL T extrude(const Args<T>& k, T d, vec3<T> p) {
  const vec2<T> w(d, abs(p.z) - k(0));
  return min(max(w.x, w.y), T(0)) + length(max(w, T(0)));
}

// (distance from the y axis minus offset, height): the 2D point a revolved shape is evaluated at.
template <class T>
MARCHCHECK_KERNEL vec3<T> p_revolve(const Args<T>& k, vec3<T> p) {
  return vec3<T>(length(vec2<T>(p.x, p.z)) - k(0), p.y, T(0));
}

}  // namespace marchcheck::sdf::kernels
