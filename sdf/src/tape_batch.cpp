// Batched tape evaluation: the stacks hold kBatch lanes per entry (structure of arrays) and each instruction is
// one loop over the lanes, which GCC vectorises for the target (-march=native: AVX2 or AVX-512). Every loop
// writes the one-point code's expression in the same order, so contraction into FMA and rounding match it.
#include "marchcheck/sdf/tape.hpp"

namespace marchcheck::sdf {

namespace {

template <class T, bool WithMaterial>
struct Stacks {
  alignas(64) T v[kMaxValueStack][kBatch];
  int m[WithMaterial ? kMaxValueStack : 1][kBatch];  // the material of each value
  alignas(64) T x[kMaxPointStack][kBatch];
  alignas(64) T y[kMaxPointStack][kBatch];
  alignas(64) T z[kMaxPointStack][kBatch];
};

// One instruction for each lane through the one-point code: the lane's top two values and top point are copied
// to small stacks, stepped, and copied back (an instruction moves each stack by at most one entry).
template <class T, bool WithMaterial, class Values, class Points>
void step_lanes(const Tape& tape, const Instr& in, Stacks<T, WithMaterial>& s, const Values& v, const Points& p,
                int& vt, int& pt, int n) {
  const int below = vt >= 1 ? 1 : vt;  // index of the lane's old top in the small stack
  int lvt = below, lpt = 0;
  for (int i = 0; i < n; ++i) {
    T values[3];
    int materials[3];
    glm::vec<3, T> points[2];
    for (int j = 0; j <= below; ++j) values[j] = v(vt - below + j)[i];
    if constexpr (WithMaterial)
      for (int j = 0; j <= below; ++j) materials[j] = s.m[vt - below + j][i];
    points[0] = {p(pt, 0)[i], p(pt, 1)[i], p(pt, 2)[i]};
    lvt = below;
    lpt = 0;
    detail::step<T, WithMaterial>(tape, in, values, materials, lvt, points, lpt);
    for (int j = 0; j <= lvt; ++j) v(vt - below + j)[i] = values[j];
    if constexpr (WithMaterial)
      for (int j = 0; j <= lvt; ++j) s.m[vt - below + j][i] = materials[j];
    if (lpt == 1) {
      s.x[pt + 1][i] = points[1].x;
      s.y[pt + 1][i] = points[1].y;
      s.z[pt + 1][i] = points[1].z;
    }
  }
  vt += lvt - below;
  pt += lpt;
}

// The one-point code's rule for a binary instruction: the result's material is b's where b decides the value.
template <class T, bool WithMaterial, class Values>
void combine_materials(const Instr& in, Stacks<T, WithMaterial>& s, const Values& v, int vt, int n) {
  if constexpr (WithMaterial) {
    const T* __restrict x = v(vt);
    const T* __restrict b = v(vt + 1);
    int* __restrict m = s.m[vt];
    const int* __restrict mb = s.m[vt + 1];
    switch (in.op) {
      case TapeOp::min:
      case TapeOp::smooth_min:
        for (int i = 0; i < n; ++i) m[i] = b[i] < x[i] ? mb[i] : m[i];
        break;
      case TapeOp::max:
      case TapeOp::smooth_max:
        for (int i = 0; i < n; ++i) m[i] = x[i] < b[i] ? mb[i] : m[i];
        break;
      default:
        for (int i = 0; i < n; ++i) m[i] = x[i] < -b[i] ? mb[i] : m[i];
        break;
    }
  }
}

template <class T, bool WithMaterial>
void run_batch(const Tape& tape, const T* x, const T* y, const T* z, T* out, int* material, int n) {
  Stacks<T, WithMaterial> s;
  int vt = -1, pt = 0;
  // The bottom entries are the caller's arrays: the points read in place, the result written in place (copies
  // of 64 lanes were library calls, as costly as a cheap instruction).
  const auto v = [&](int level) { return level == 0 ? out : s.v[level]; };
  const auto p = [&](int level, int axis) -> T* {
    if (level == 0) return const_cast<T*>(axis == 0 ? x : axis == 1 ? y : z);  // only read
    return axis == 0 ? s.x[level] : axis == 1 ? s.y[level] : s.z[level];
  };
  for (const Instr& in : tape.code) {
    const std::uint32_t a = in.arg;
    if constexpr (WithMaterial) {
      // A vectorised primitive pushes a value whose material is its own (lane-by-lane ones set theirs).
      const bool vector_primitive = in.op == TapeOp::sphere || in.op == TapeOp::plane || in.op == TapeOp::box ||
                                    in.op == TapeOp::round_box || in.op == TapeOp::torus;
      if (vector_primitive)
        for (int i = 0; i < n; ++i) s.m[vt + 1][i] = in.material;
    }
    auto k = [&](std::uint32_t i) { return tape.c<T>(a + i); };
    const T* __restrict px = p(pt, 0);
    const T* __restrict py = p(pt, 1);
    const T* __restrict pz = p(pt, 2);
    switch (in.op) {
      case TapeOp::sphere: {
        T* __restrict r = v(++vt);
        const T k0 = k(0);
        for (int i = 0; i < n; ++i) {
          T d = px[i] * px[i];
          d += py[i] * py[i];
          d += pz[i] * pz[i];
          r[i] = std::sqrt(d) - k0;
        }
        break;
      }
      case TapeOp::plane: {
        T* __restrict r = v(++vt);
        const T k0 = k(0), k1 = k(1), k2 = k(2), k3 = k(3);
        for (int i = 0; i < n; ++i) r[i] = px[i] * k0 + py[i] * k1 + pz[i] * k2 + k3;
        break;
      }
      case TapeOp::box:
      case TapeOp::round_box: {
        T* __restrict r = v(++vt);
        const T bx = k(0), by = k(1), bz = k(2), rr = in.op == TapeOp::round_box ? k(3) : T(0);
        const bool rounded = in.op == TapeOp::round_box;
        for (int i = 0; i < n; ++i) {
          T qx = std::abs(px[i]) - bx, qy = std::abs(py[i]) - by, qz = std::abs(pz[i]) - bz;
          if (rounded) {
            qx = qx + rr;
            qy = qy + rr;
            qz = qz + rr;
          }
          const T mx = qx < T(0) ? T(0) : qx, my = qy < T(0) ? T(0) : qy, mz = qz < T(0) ? T(0) : qz;
          T d = mx * mx;
          d += my * my;
          d += mz * mz;
          T m = qx < qy ? qy : qx;
          m = m < qz ? qz : m;
          const T inside = T(0) < m ? T(0) : m;
          r[i] = std::sqrt(d) + inside;
          if (rounded) r[i] = r[i] - rr;
        }
        break;
      }
      case TapeOp::torus: {
        T* __restrict r = v(++vt);
        const T k0 = k(0), k1 = k(1);
        for (int i = 0; i < n; ++i) {
          T xz = px[i] * px[i];
          xz += pz[i] * pz[i];
          const T qx = std::sqrt(xz) - k0;
          T d = qx * qx;
          d += py[i] * py[i];
          r[i] = std::sqrt(d) - k1;
        }
        break;
      }
      case TapeOp::min:
      case TapeOp::max:
      case TapeOp::subtract: {
        combine_materials(in, s, v, vt - 1, n);
        const T* __restrict b = v(vt--);
        T* __restrict r = v(vt);
        if (in.op == TapeOp::min) {
          for (int i = 0; i < n; ++i) r[i] = b[i] < r[i] ? b[i] : r[i];
        } else if (in.op == TapeOp::max) {
          for (int i = 0; i < n; ++i) r[i] = r[i] < b[i] ? b[i] : r[i];
        } else {
          for (int i = 0; i < n; ++i) r[i] = r[i] < -b[i] ? -b[i] : r[i];
        }
        break;
      }
      case TapeOp::smooth_min:
      case TapeOp::smooth_max:
      case TapeOp::smooth_subtract: {
        combine_materials(in, s, v, vt - 1, n);
        const T* __restrict b = v(vt--);
        T* __restrict r = v(vt);
        const T kk = k(0);
        // -smooth_min(-x, -b) and -smooth_min(-x, b), as the one-point code: sa and sb give the signs.
        const T sa = in.op == TapeOp::smooth_min ? T(1) : T(-1);
        const T sb = in.op == TapeOp::smooth_subtract ? T(1) : sa;
        for (int i = 0; i < n; ++i) {
          const T u = sa * r[i], w = sb * b[i];
          const T e = kk - std::abs(u - w);
          const T h = (e < T(0) ? T(0) : e) / kk;
          r[i] = sa * ((w < u ? w : u) - h * h * kk * T(0.25));
        }
        break;
      }
      case TapeOp::round: {
        T* __restrict r = v(vt);
        const T k0 = k(0);
        for (int i = 0; i < n; ++i) r[i] -= k0;
        break;
      }
      case TapeOp::scale_value: {
        T* __restrict r = v(vt);
        const T k0 = k(0);
        for (int i = 0; i < n; ++i) r[i] *= k0;
        break;
      }
      case TapeOp::set_material:
        if constexpr (WithMaterial)
          for (int i = 0; i < n; ++i) s.m[vt][i] = in.material;
        break;
      case TapeOp::p_translate:
      case TapeOp::p_scale: {
        ++pt;
        T* __restrict qx = s.x[pt];
        T* __restrict qy = s.y[pt];
        T* __restrict qz = s.z[pt];
        if (in.op == TapeOp::p_translate) {
          const T k0 = k(0), k1 = k(1), k2 = k(2);
          for (int i = 0; i < n; ++i) {
            qx[i] = px[i] - k0;
            qy[i] = py[i] - k1;
            qz[i] = pz[i] - k2;
          }
        } else {
          const T k0 = k(0);
          for (int i = 0; i < n; ++i) {
            qx[i] = px[i] * k0;
            qy[i] = py[i] * k0;
            qz[i] = pz[i] * k0;
          }
        }
        break;
      }
      case TapeOp::p_affine: {
        ++pt;
        T* __restrict qx = s.x[pt];
        T* __restrict qy = s.y[pt];
        T* __restrict qz = s.z[pt];
        T m[12];
        for (std::uint32_t j = 0; j < 12; ++j) m[j] = k(j);
        for (int i = 0; i < n; ++i) {
          qx[i] = px[i] * m[0] + py[i] * m[1] + pz[i] * m[2] + m[3];
          qy[i] = px[i] * m[4] + py[i] * m[5] + pz[i] * m[6] + m[7];
          qz[i] = px[i] * m[8] + py[i] * m[9] + pz[i] * m[10] + m[11];
        }
        break;
      }
      case TapeOp::p_pop: --pt; break;
      default: step_lanes(tape, in, s, v, p, vt, pt, n); break;
    }
  }
  if constexpr (WithMaterial)
    for (int i = 0; i < n; ++i) material[i] = s.m[0][i];
}

}  // namespace

template <class T>
void evaluate_batch(const Tape& tape, const T* x, const T* y, const T* z, T* out, int n) {
  run_batch<T, false>(tape, x, y, z, out, nullptr, n);
}

template <class T>
void sample_batch(const Tape& tape, const T* x, const T* y, const T* z, T* out, int* material, int n) {
  run_batch<T, true>(tape, x, y, z, out, material, n);
}

template void sample_batch<float>(const Tape&, const float*, const float*, const float*, float*, int*, int);
template void sample_batch<double>(const Tape&, const double*, const double*, const double*, double*, int*, int);
template void evaluate_batch<float>(const Tape&, const float*, const float*, const float*, float*, int);
template void evaluate_batch<double>(const Tape&, const double*, const double*, const double*, double*, int);

}  // namespace marchcheck::sdf
