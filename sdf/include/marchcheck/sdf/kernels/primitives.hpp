// Kernels of the 3D primitives (their rules: sdf/src/ops/primitives.cpp).
#pragma once

#include "marchcheck/sdf/glsl_field.hpp"
#include "marchcheck/sdf/half.hpp"
#include "marchcheck/sdf/kernels/kernel.hpp"
#include "marchcheck/sdf/mesh_distance.hpp"
#include "marchcheck/sdf/noise.hpp"

#include <cmath>

#define MARCHCHECK_PRIMITIVE_KERNELS(X)                                                                       \
  X(sphere, source) X(plane, source) X(box, source) X(round_box, source) X(box_frame, source) X(torus, source) \
  X(capped_torus, source) X(capsule, source) X(capped_cylinder, source) X(cone, source) X(ellipsoid, source)   \
  X(octahedron, source) X(octahedron_bound, source) X(heightfield, source) X(mandelbulb, source) X(mesh, source)  \
  X(glsl, source)

namespace marchcheck::sdf::kernels {

using namespace smath;

template <class T>
MARCHCHECK_KERNEL T box_distance(vec3<T> q) {
  return length(max(q, T(0))) + min(max_component(q), T(0));
}

template <class T>
MARCHCHECK_KERNEL T sphere(const Args<T>& k, vec3<T> p) {
  return length(p) - k(0);
}

template <class T>
MARCHCHECK_KERNEL T plane(const Args<T>& k, vec3<T> p) {  // k: the unit normal, then the offset
  return p.x * k(0) + p.y * k(1) + p.z * k(2) + k(3);
}

template <class T>
MARCHCHECK_KERNEL T box(const Args<T>& k, vec3<T> p) {
  return box_distance(abs(p) - vec3<T>(k(0), k(1), k(2)));
}

template <class T>
MARCHCHECK_KERNEL T round_box(const Args<T>& k, vec3<T> p) {
  const T r = k(3);
  return box_distance(abs(p) - vec3<T>(k(0), k(1), k(2)) + vec3<T>(r)) - r;
}

template <class T>
MARCHCHECK_KERNEL T box_frame(const Args<T>& k, vec3<T> p) {
  const vec3<T> b(k(0), k(1), k(2));
  const T e = k(3) * T(0.5);  // iq's e: the bars span [b - 2e, b], so e is half the thickness
  const vec3<T> q = abs(p) - b;
  const vec3<T> w = abs(q + vec3<T>(e)) - vec3<T>(e);
  return min(min(box_distance(vec3<T>(q.x, w.y, w.z)), box_distance(vec3<T>(w.x, q.y, w.z))),
             box_distance(vec3<T>(w.x, w.y, q.z)));
}

template <class T>
MARCHCHECK_KERNEL T torus(const Args<T>& k, vec3<T> p) {
  const vec2<T> q(length(vec2<T>(p.x, p.z)) - k(0), p.y);
  return length(q) - k(1);
}

template <class T>
MARCHCHECK_KERNEL T capped_torus(const Args<T>& k, vec3<T> p) {  // k: sin and cos of the half-angle, major, minor
  const T sx = k(0), cy = k(1), ra = k(2), rb = k(3);
  p.x = abs(p.x);
  const T kk = cy * p.x > sx * p.y ? p.x * sx + p.y * cy : length(vec2<T>(p.x, p.y));
  return sqrt(max(dot(p, p) + ra * ra - T(2) * ra * kk, T(0))) - rb;
}

template <class T>
MARCHCHECK_KERNEL T capsule(const Args<T>& k, vec3<T> p) {
  const vec3<T> pa = p - vec3<T>(k(0), k(1), k(2));
  const vec3<T> ba(k(3), k(4), k(5));                   // b - a, precomputed
  const T h = clamp(dot(pa, ba) * k(6), T(0), T(1));  // k(6) = 1 / dot(ba, ba)
  return length(pa - ba * h) - k(7);
}

template <class T>
MARCHCHECK_KERNEL T capped_cylinder(const Args<T>& k, vec3<T> p) {
  const vec2<T> d = abs(vec2<T>(length(vec2<T>(p.x, p.z)), p.y)) - vec2<T>(k(1), k(0));
  return min(max(d.x, d.y), T(0)) + length(max(d, T(0)));
}

template <class T>
MARCHCHECK_KERNEL T cone(const Args<T>& k, vec3<T> p) {
  const vec2<T> q(k(0), k(1));  // the base rim in (radius, height): h (tan a, -1)
  const vec2<T> w(length(vec2<T>(p.x, p.z)), p.y);
  const vec2<T> ea = w - q * clamp(dot(w, q) / dot(q, q), T(0), T(1));
  const vec2<T> eb = w - q * vec2<T>(clamp(w.x / q.x, T(0), T(1)), T(1));
  const T d = min(dot(ea, ea), dot(eb, eb));
  const T s = max(-(w.x * q.y - w.y * q.x), -(w.y - q.y));  // sign(q.y) = -1
  return sqrt(d) * sign(s);
}

template <class T>
MARCHCHECK_KERNEL T ellipsoid(const Args<T>& k, vec3<T> p) {
  const vec3<T> r(k(0), k(1), k(2));
  const T k0 = length(vec3<T>(p.x / r.x, p.y / r.y, p.z / r.z));
  const T smallest = min(r.x, min(r.y, r.z));
  // Inside, k0 (k0 - 1) / k1 overestimates badly near the centre; (k0 - 1) min(r) is 1-Lipschitz and
  // vanishes on the surface, hence a bound.
  if (value_of(k0) < 1) return (k0 - T(1)) * smallest;
  const T k1 = length(vec3<T>(p.x / (r.x * r.x), p.y / (r.y * r.y), p.z / (r.z * r.z)));
  return k0 * (k0 - T(1)) / k1;
}

template <class T>
MARCHCHECK_KERNEL T octahedron(const Args<T>& k, vec3<T> p) {
  const T s = k(0);
  p = abs(p);
  const T m = p.x + p.y + p.z - s;
  vec3<T> q;
  if (T(3) * p.x < m) {
    q = p;
  } else if (T(3) * p.y < m) {
    q = vec3<T>(p.y, p.z, p.x);
  } else if (T(3) * p.z < m) {
    q = vec3<T>(p.z, p.x, p.y);
  } else {
    return m * literal<T>(0.57735026918962576);
  }
  const T kk = clamp(T(0.5) * (q.z - q.y + s), T(0), s);
  return length(vec3<T>(q.x, q.y - s + kk, q.z - kk));
}

template <class T>
MARCHCHECK_KERNEL T octahedron_bound(const Args<T>& k, vec3<T> p) {
  p = abs(p);
  return (p.x + p.y + p.z - k(0)) * literal<T>(0.57735026918962576);
}

// k: the number of pairs, the lattice hash (NoiseHash), then [amplitude, frequency] pairs. The height h is summed
// octave by octave (heightfield_octave, given the noise of the hash), which the batched tape runs as one loop over
// the lanes per octave with the hash chosen once.
template <class T>
MARCHCHECK_KERNEL std::uint32_t heightfield_octaves(const Args<T>& k) {
  return static_cast<std::uint32_t>(k.raw(0));
}
template <class T>
MARCHCHECK_KERNEL NoiseHash heightfield_hash(const Args<T>& k) {
  return static_cast<NoiseHash>(static_cast<int>(k.raw(1)));
}
template <class T, class Noise>
MARCHCHECK_KERNEL T heightfield_octave(const Args<T>& k, std::uint32_t i, T h, vec3<T> p, Noise noise) {
  const T amp = k(2 + 2 * i), freq = k(3 + 2 * i);
  return h + amp * noise(p.x * freq, p.z * freq);
}
template <class T>
MARCHCHECK_KERNEL T heightfield(const Args<T>& k, vec3<T> p) {
  const NoiseHash hash = heightfield_hash(k);
  T h(0);
  for (std::uint32_t i = 0; i < heightfield_octaves(k); ++i)
    h = heightfield_octave(k, i, h, p, [hash](T x, T z) { return value_noise(x, z, hash); });
  return p.y - h;
}

template <class T>
MARCHCHECK_KERNEL T mandelbulb(const Args<T>& k, vec3<T> p) {  // k: power, iterations, bailout
  const T power = k(0);
  const auto iterations = static_cast<int>(k.raw(1));
  const T bailout2 = k(2) * k(2);
  vec3<T> w = p;
  T m = dot(w, w);
  // Far out the estimate (about 0.5 r log r) overflows in r^power and exceeds the distance to the ball that
  // holds the set (radius 2^(1 / (power - 1)): beyond it |w| grows every iteration). From r = 2 on the field
  // is the smaller of the two (a bound, finite, and continuous: at r = 2 the estimate is the smaller one);
  // from r = 8 on, where the estimate is well above the ball's distance, that distance alone.
  const T set_radius = literal<T>(std::pow(2.0, 1.0 / (k.raw(0) - 1)));
  const T big = max(abs(p.x), max(abs(p.y), abs(p.z)));
  if (value_of(big) > 8) return big * length(p / big) - set_radius;  // scaled: |p|^2 overflows float at 2e19
  const T ball = sqrt(m) - set_radius;
  T dz(1);
  for (int i = 0; i < iterations; ++i) {
    const T r = sqrt(m);
    if (!(value_of(r) > 0)) break;  // at the origin the angles are undefined; it is inside
    dz = power * pow(r, value_of(power) - 1) * dz + T(1);
    const T b = power * acos(clamp(w.y / r, T(-1), T(1)));
    const T az = power * atan2(w.x, w.z);
    const T rp = pow(r, value_of(power));
    w = p + vec3<T>(sin(b) * sin(az), cos(b), sin(b) * cos(az)) * rp;
    m = dot(w, w);
    if (m > bailout2) break;
  }
  if (!(value_of(m) > 0)) return -sqrt(dot(p, p));
  const T estimate = T(0.25) * log(m) * sqrt(m) / dz;
  return value_of(dot(p, p)) > 4 && value_of(ball) < value_of(estimate) ? ball : estimate;
}

template <class T>
MARCHCHECK_KERNEL T mesh(const Args<T>& k, vec3<T> p) {  // at: the index of the mesh, not of constants
  // A mesh is no shader's code: in binary16 its distance is float's, rounded once.
  if constexpr (std::is_same_v<T, Half>) return T(k.meshes[k.at]->signed_distance(vec3<float>(p)));
  else return k.meshes[k.at]->signed_distance(p);
}

template <class T>
MARCHCHECK_KERNEL T glsl(const Args<T>& k, vec3<T> p) {  // at: the index of the field, not of constants
  return k.glsl_fields[k.at]->distance(p);
}

}  // namespace marchcheck::sdf::kernels
