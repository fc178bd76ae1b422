// A scene tree compiled to a flat program ("tape"): evaluated by one loop over instructions with fixed-size
// stacks, so a scene loaded from a file costs no allocation and no virtual call per evaluation.
#pragma once

#include "marchcheck/sdf/mesh_distance.hpp"
#include "marchcheck/sdf/node.hpp"
#include "marchcheck/sdf/noise.hpp"
#include "marchcheck/sdf/scalar.hpp"

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <vector>

namespace marchcheck::sdf {

enum class TapeOp : std::uint8_t {
  // primitives: read the top point, push a value
  sphere, plane, box, round_box, box_frame, torus, capped_torus, capsule, capped_cylinder, cone, ellipsoid,
  octahedron, octahedron_bound, heightfield, mandelbulb, circle, rect, segment,
  mesh,  // arg: index into Tape::meshes
  grid,  // arg: counts, lowest corner, cell, then the samples (x fastest)
  // values: pop two, push one
  min, max, subtract, smooth_min, smooth_max, smooth_subtract,
  // values: modify the top one
  round, onion, scale_value, displace, extrude, set_material,
  // points: push a transformed copy of the top point, or pop one
  p_translate, p_affine, p_scale, p_repeat, p_repeat_limited, p_mirror, p_twist, p_warp, p_revolve, p_pop,
};

struct Instr {
  TapeOp op;
  std::uint32_t arg = 0;  // offset into Tape::constants
  std::int32_t material = -1;
};

inline constexpr int kMaxValueStack = 32;
inline constexpr int kMaxPointStack = 32;

struct Tape {
  std::vector<Instr> code;
  std::vector<double> constants;
  std::vector<float> constants_f;  // the same constants rounded once, so float evaluation never converts
  std::vector<std::shared_ptr<const MeshDistance>> meshes;
  int value_depth = 0;
  int point_depth = 0;

  template <class T>
  T c(std::uint32_t i) const {
    if constexpr (std::is_same_v<T, float>) {
      return constants_f[i];
    } else {
      return T(static_cast<decltype(value_of(T{}))>(constants[i]));
    }
  }
};

struct CompileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Throws CompileError when the tree is invalid or needs deeper stacks than the fixed ones.
Tape compile(const Node& root, double time = 0.0);

template <class T>
struct Sample {
  T distance;
  int material;
};

namespace detail {

template <class T>
using v3 = glm::vec<3, T>;
template <class T>
using v2 = glm::vec<2, T>;

template <class T>
inline T box_distance(v3<T> q) {
  using namespace smath;
  return length(max(q, T(0))) + min(max_component(q), T(0));
}

template <class T>
inline T eval_primitive(const Tape& tape, const Instr& in, v3<T> p) {
  using namespace smath;
  const std::uint32_t a = in.arg;
  auto k = [&](std::uint32_t i) { return tape.c<T>(a + i); };
  switch (in.op) {
    case TapeOp::sphere: return length(p) - k(0);
    case TapeOp::plane: return p.x * k(0) + p.y * k(1) + p.z * k(2) + k(3);
    case TapeOp::box: return box_distance(abs(p) - v3<T>(k(0), k(1), k(2)));
    case TapeOp::round_box: {
      const T r = k(3);
      return box_distance(abs(p) - v3<T>(k(0), k(1), k(2)) + v3<T>(r)) - r;
    }
    case TapeOp::box_frame: {
      const v3<T> b(k(0), k(1), k(2));
      const T e = k(3) * T(0.5);  // iq's e: the bars span [b - 2e, b], so e is half the thickness
      const v3<T> q = abs(p) - b;
      const v3<T> w = abs(q + v3<T>(e)) - v3<T>(e);
      return min(min(box_distance(v3<T>(q.x, w.y, w.z)), box_distance(v3<T>(w.x, q.y, w.z))),
                 box_distance(v3<T>(w.x, w.y, q.z)));
    }
    case TapeOp::torus: {
      const v2<T> q(length(v2<T>(p.x, p.z)) - k(0), p.y);
      return length(q) - k(1);
    }
    case TapeOp::capped_torus: {
      const T sx = k(0), cy = k(1), ra = k(2), rb = k(3);
      p.x = abs(p.x);
      const T kk = cy * p.x > sx * p.y ? p.x * sx + p.y * cy : length(v2<T>(p.x, p.y));
      return sqrt(max(dot(p, p) + ra * ra - T(2) * ra * kk, T(0))) - rb;
    }
    case TapeOp::capsule: {
      const v3<T> pa = p - v3<T>(k(0), k(1), k(2));
      const v3<T> ba(k(3), k(4), k(5));  // b - a, precomputed
      const T h = clamp(dot(pa, ba) * k(6), T(0), T(1));  // k(6) = 1 / dot(ba, ba)
      return length(pa - ba * h) - k(7);
    }
    case TapeOp::capped_cylinder: {
      const v2<T> d = abs(v2<T>(length(v2<T>(p.x, p.z)), p.y)) - v2<T>(k(1), k(0));
      return min(max(d.x, d.y), T(0)) + length(max(d, T(0)));
    }
    case TapeOp::cone: {
      const v2<T> q(k(0), k(1));  // the base rim in (radius, height): h (tan a, -1)
      const v2<T> w(length(v2<T>(p.x, p.z)), p.y);
      const v2<T> ea = w - q * clamp(dot(w, q) / dot(q, q), T(0), T(1));
      const v2<T> eb = w - q * v2<T>(clamp(w.x / q.x, T(0), T(1)), T(1));
      const T d = min(dot(ea, ea), dot(eb, eb));
      const T s = max(-(w.x * q.y - w.y * q.x), -(w.y - q.y));  // sign(q.y) = -1
      return sqrt(d) * sign(s);
    }
    case TapeOp::ellipsoid: {
      const v3<T> r(k(0), k(1), k(2));
      const T k0 = length(v3<T>(p.x / r.x, p.y / r.y, p.z / r.z));
      const T smallest = min(r.x, min(r.y, r.z));
      // Inside, k0 (k0 - 1) / k1 overestimates badly near the centre; (k0 - 1) min(r) is 1-Lipschitz and
      // vanishes on the surface, hence a bound.
      if (value_of(k0) < 1) return (k0 - T(1)) * smallest;
      const T k1 = length(v3<T>(p.x / (r.x * r.x), p.y / (r.y * r.y), p.z / (r.z * r.z)));
      return k0 * (k0 - T(1)) / k1;
    }
    case TapeOp::octahedron: {
      const T s = k(0);
      p = abs(p);
      const T m = p.x + p.y + p.z - s;
      v3<T> q;
      if (T(3) * p.x < m) {
        q = p;
      } else if (T(3) * p.y < m) {
        q = v3<T>(p.y, p.z, p.x);
      } else if (T(3) * p.z < m) {
        q = v3<T>(p.z, p.x, p.y);
      } else {
        return m * T(static_cast<decltype(value_of(T{}))>(0.57735026918962576));
      }
      const T kk = clamp(T(0.5) * (q.z - q.y + s), T(0), s);
      return length(v3<T>(q.x, q.y - s + kk, q.z - kk));
    }
    case TapeOp::octahedron_bound: {
      p = abs(p);
      return (p.x + p.y + p.z - k(0)) * T(static_cast<decltype(value_of(T{}))>(0.57735026918962576));
    }
    case TapeOp::heightfield: {
      const auto pairs = static_cast<std::uint32_t>(value_of(tape.constants[a]));
      T h(0);
      for (std::uint32_t i = 0; i < pairs; ++i) {
        const T amp = k(1 + 2 * i), freq = k(2 + 2 * i);
        h += amp * value_noise(p.x * freq, p.z * freq);
      }
      return p.y - h;
    }
    case TapeOp::mandelbulb: {
      const T power = k(0);
      const auto iterations = static_cast<int>(tape.constants[a + 1]);
      const T bailout2 = k(2) * k(2);
      v3<T> w = p;
      T m = dot(w, w);
      // Far out the estimate (about 0.5 r log r) overflows in r^power and exceeds the distance to the ball that
      // holds the set (radius 2^(1 / (power - 1)): beyond it |w| grows every iteration). From r = 2 on the field
      // is the smaller of the two (a bound, finite, and continuous: at r = 2 the estimate is the smaller one);
      // from r = 8 on, where the estimate is well above the ball's distance, that distance alone.
      const T set_radius(static_cast<decltype(value_of(T{}))>(std::pow(2.0, 1.0 / (tape.constants[a] - 1))));
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
        w = p + v3<T>(sin(b) * sin(az), cos(b), sin(b) * cos(az)) * rp;
        m = dot(w, w);
        if (m > bailout2) break;
      }
      if (!(value_of(m) > 0)) return -sqrt(dot(p, p));
      const T estimate = T(0.25) * log(m) * sqrt(m) / dz;
      return value_of(dot(p, p)) > 4 && value_of(ball) < value_of(estimate) ? ball : estimate;
    }
    case TapeOp::circle: return length(v2<T>(p.x - k(0), p.y - k(1))) - k(2);
    case TapeOp::rect: {
      const v2<T> d = abs(v2<T>(p.x - k(0), p.y - k(1))) - v2<T>(k(2), k(3));
      return length(max(d, T(0))) + min(max(d.x, d.y), T(0));
    }
    case TapeOp::segment: {
      const v2<T> pa(p.x - k(0), p.y - k(1));
      const v2<T> ba(k(2), k(3));  // b - a
      const T h = clamp(dot(pa, ba) * k(4), T(0), T(1));
      return length(pa - ba * h) - k(5);
    }
    case TapeOp::mesh: return tape.meshes[a]->signed_distance(p);
    case TapeOp::grid: {
      using S = decltype(value_of(T{}));
      int n[3], cell0[3];
      v3<T> f;
      const T cell = k(6);
      const v3<T> g = (p - v3<T>(k(3), k(4), k(5))) / cell;  // in cells from the lowest sample
      v3<T> c;
      for (int i = 0; i < 3; ++i) {
        n[i] = static_cast<int>(tape.constants[a + static_cast<std::uint32_t>(i)]);
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
    default: return T(0);
  }
}

// Polynomial smooth minimum (Inigo Quilez): min(a, b) - h^2 k / 4.
template <class T>
inline T smooth_min(T a, T b, T k) {
  using namespace smath;
  const T h = max(k - abs(a - b), T(0)) / k;
  return min(a, b) - h * h * k * T(0.25);
}

// One instruction on the stacks (vt, pt: the top value and point): shared by the one-point evaluation and the
// batched one's per-lane fallback, so an operator written here works in both.
template <class T, bool WithMaterial>
inline void step(const Tape& tape, const Instr& in, T* values, int* materials, int& vt, v3<T>* points, int& pt) {
  using namespace smath;
  const std::uint32_t a = in.arg;
  auto k = [&](std::uint32_t i) { return tape.c<T>(a + i); };
  const v3<T> p = points[pt];
  switch (in.op) {
    case TapeOp::min:
    case TapeOp::max:
    case TapeOp::subtract:
    case TapeOp::smooth_min:
    case TapeOp::smooth_max:
    case TapeOp::smooth_subtract: {
      const T b = values[vt--];
      T& x = values[vt];
      // The result's material is the one of the child that decides the value.
      bool take_b = false;
      T r;
      switch (in.op) {
        case TapeOp::min: take_b = b < x; r = take_b ? b : x; break;
        case TapeOp::max: take_b = x < b; r = take_b ? b : x; break;
        case TapeOp::subtract: take_b = x < -b; r = take_b ? -b : x; break;
        case TapeOp::smooth_min: take_b = b < x; r = smooth_min(x, b, k(0)); break;
        case TapeOp::smooth_max: take_b = x < b; r = -smooth_min(-x, -b, k(0)); break;
        default: take_b = x < -b; r = -smooth_min(-x, b, k(0)); break;
      }
      if constexpr (WithMaterial)
        if (take_b) materials[vt] = materials[vt + 1];
      x = r;
      break;
    }
    case TapeOp::round: values[vt] -= k(0); break;
    case TapeOp::onion: values[vt] = abs(values[vt]) - k(0); break;
    case TapeOp::scale_value: values[vt] *= k(0); break;
    case TapeOp::displace: {
      const T f = k(1);
      values[vt] += k(0) * sin(f * p.x) * sin(f * p.y) * sin(f * p.z);
      break;
    }
    case TapeOp::extrude: {
      const v2<T> w(values[vt], abs(p.z) - k(0));
      values[vt] = min(max(w.x, w.y), T(0)) + length(max(w, T(0)));
      break;
    }
    case TapeOp::set_material:
      if constexpr (WithMaterial) materials[vt] = in.material;
      break;
    case TapeOp::p_translate: points[++pt] = p - v3<T>(k(0), k(1), k(2)); break;
    case TapeOp::p_affine:  // row-major 3x4
      points[++pt] = v3<T>(p.x * k(0) + p.y * k(1) + p.z * k(2) + k(3), p.x * k(4) + p.y * k(5) + p.z * k(6) + k(7),
                           p.x * k(8) + p.y * k(9) + p.z * k(10) + k(11));
      break;
    case TapeOp::p_scale: points[++pt] = p * k(0); break;
    case TapeOp::p_repeat: {
      v3<T> q = p;
      for (int i = 0; i < 3; ++i) {
        const T c = k(static_cast<std::uint32_t>(i));
        if (value_of(c) > 0) q[i] = p[i] - c * round(p[i] / c);
      }
      points[++pt] = q;
      break;
    }
    case TapeOp::p_repeat_limited: {
      v3<T> q = p;
      for (int i = 0; i < 3; ++i) {
        const T c = k(static_cast<std::uint32_t>(i)), n = k(3 + static_cast<std::uint32_t>(i));
        if (value_of(c) > 0) q[i] = p[i] - c * clamp(round(p[i] / c), -n, n);
      }
      points[++pt] = q;
      break;
    }
    case TapeOp::p_mirror: {
      v3<T> q = p;
      for (int i = 0; i < 3; ++i)
        if (tape.constants[a + static_cast<std::uint32_t>(i)] > 0.5) q[i] = abs(q[i]);
      points[++pt] = q;
      break;
    }
    case TapeOp::p_twist: {
      const T ang = k(0) * p.y;
      const T c = cos(ang), s = sin(ang);
      points[++pt] = v3<T>(c * p.x - s * p.z, p.y, s * p.x + c * p.z);
      break;
    }
    case TapeOp::p_warp:  // k = (ax, kx, ay, ky, oz): q = p - (ax sin(kx y), ay sin(ky x), oz)
      points[++pt] = v3<T>(p.x - k(0) * sin(k(1) * p.y), p.y - k(2) * sin(k(3) * p.x), p.z - k(4));
      break;
    case TapeOp::p_revolve:
      points[++pt] = v3<T>(length(v2<T>(p.x, p.z)) - k(0), p.y, T(0));
      break;
    case TapeOp::p_pop: --pt; break;
    default:
      values[++vt] = eval_primitive(tape, in, p);
      if constexpr (WithMaterial) materials[vt] = in.material;
      break;
  }
}

template <class T, bool WithMaterial>
inline Sample<T> run(const Tape& tape, v3<T> p0) {
  T values[kMaxValueStack];
  int materials[WithMaterial ? kMaxValueStack : 1];
  v3<T> points[kMaxPointStack];
  int vt = -1, pt = 0;
  points[0] = p0;
  for (const Instr& in : tape.code) step<T, WithMaterial>(tape, in, values, materials, vt, points, pt);
  if constexpr (WithMaterial) {
    return {values[0], materials[0]};
  } else {
    return {values[0], -1};
  }
}

}  // namespace detail

// The field's value at p.
template <class T>
inline T evaluate(const Tape& tape, glm::vec<3, T> p) {
  return detail::run<T, false>(tape, p).distance;
}

// The field's value at p and the material of the child that decides it.
template <class T>
inline Sample<T> sample(const Tape& tape, glm::vec<3, T> p) {
  return detail::run<T, true>(tape, p);
}

// Points per batch of evaluate_batch: a whole packet of rays (a 16 x 16 render tile) in one pass over the tape.
// 64 cost lee-flat's render 8% more (the instructions' dispatch and loop ends per batch); the stacks, 32 entries
// deep, take 128 KiB of stack in float (256 KiB in double) per call.
inline constexpr int kBatch = 256;

// out[i] = evaluate(tape, (x[i], y[i], z[i])) for i < n <= kBatch, bit for bit, with each instruction run as one
// loop over the batch (structure of arrays, vectorised by the compiler). Operators not worth vectorising run
// lane by lane through the one-point code. T: float or double. out is written as the tape runs: it must not
// overlap x, y or z.
template <class T>
void evaluate_batch(const Tape& tape, const T* x, const T* y, const T* z, T* out, int n);

// evaluate_batch, and material[i] = sample(tape, point i).material.
template <class T>
void sample_batch(const Tape& tape, const T* x, const T* y, const T* z, T* out, int* material, int n);

}  // namespace marchcheck::sdf
