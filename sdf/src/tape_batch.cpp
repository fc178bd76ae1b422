// Batched tape evaluation: the stacks hold kBatch lanes per entry (structure of arrays) and each instruction is
// one loop over the lanes calling its kernel, the same function the one-point tape calls, so the two agree bit
// for bit (no FMA contraction: -ffp-contract=off). GCC vectorises the loops of the branch-free kernels for the
// target (-march=native: AVX2 or AVX-512); the others run lane after lane without the one-point tape's
// dispatch per instruction.
// The kernels' float transcendentals vectorise through their SLEEF clones (vector_math.hpp).
#define MARCHCHECK_VECTOR_CLONES
#include "marchcheck/sdf/tape.hpp"
#include <type_traits>

namespace marchcheck::sdf {

namespace {

using smath::vec3;

template <class T, bool WithMaterial>
struct Stacks {
  alignas(64) T v[kMaxValueStack][kBatch];
  int m[WithMaterial ? kMaxValueStack : 1][kBatch];  // the material of each value
  alignas(64) T x[kMaxPointStack][kBatch];
  alignas(64) T y[kMaxPointStack][kBatch];
  alignas(64) T z[kMaxPointStack][kBatch];
};

// The stacks of one batch. The bottom entries are the caller's arrays: the points read in place, the result
// written in place (copies of 64 lanes were library calls, as costly as a cheap instruction).
template <class T, bool WithMaterial>
struct Lanes {
  Stacks<T, WithMaterial> s;  // left uninitialised: every entry is written before it is read
  const T* x0;
  const T* y0;
  const T* z0;
  T* out;
  int n;
  int vt = -1, pt = 0;

  Lanes(const T* x, const T* y, const T* z, T* out_, int n_) : x0(x), y0(y), z0(z), out(out_), n(n_) {}

  T* value(int level) { return level == 0 ? out : s.v[level]; }
  const T* px() const { return pt == 0 ? x0 : s.x[pt]; }
  const T* py() const { return pt == 0 ? y0 : s.y[pt]; }
  const T* pz() const { return pt == 0 ? z0 : s.z[pt]; }
};

// Which kernel a template was given, by template identity: comparing the function addresses is not a constant
// expression under GCC's -fsanitize=address.
template <auto Kernel>
struct KernelIs {};
template <auto Kernel, auto Other>
constexpr bool kernel_is = std::is_same_v<KernelIs<Kernel>, KernelIs<Other>>;

// One loop per kernel shape (see kernels/kernel.hpp), each lane as the one-point tape's step does it.
template <auto Kernel, class T, bool WithMaterial>
MARCHCHECK_KERNEL void source(const kernels::Args<T>& k, const Instr& in, Lanes<T, WithMaterial>& l) {
  const T* __restrict px = l.px();
  const T* __restrict py = l.py();
  const T* __restrict pz = l.pz();
  T* __restrict r = l.value(++l.vt);
  if constexpr (kernel_is<Kernel, kernels::heightfield<T>>) {
    // Octave by octave, each one loop over the lanes with the hash chosen before it: an octave loop inside each
    // lane's, or a choice of hash, would keep the lanes' loop from vectorising.
    auto octaves = [&](auto noise) {
      for (int i = 0; i < l.n; ++i) r[i] = T(0);
      for (std::uint32_t o = 0; o < kernels::heightfield_octaves(k); ++o)
        for (int i = 0; i < l.n; ++i)
          r[i] = kernels::heightfield_octave(k, o, r[i], vec3<T>(px[i], py[i], pz[i]), noise);
      for (int i = 0; i < l.n; ++i) r[i] = py[i] - r[i];
    };
    if (kernels::heightfield_hash(k) == NoiseHash::seed_sin)
      octaves([](T x, T z) { return value_noise<NoiseHash::seed_sin>(x, z); });
    else
      octaves([](T x, T z) { return value_noise<NoiseHash::splitmix>(x, z); });
  } else if constexpr (kernel_is<Kernel, kernels::mesh<T>>) {
    k.meshes[k.at]->signed_distances(px, py, pz, r, l.n);  // the lanes' searches start where their neighbours' ended
  } else {
    for (int i = 0; i < l.n; ++i) r[i] = Kernel(k, vec3<T>(px[i], py[i], pz[i]));
  }
  if constexpr (WithMaterial) {
    for (int i = 0; i < l.n; ++i) l.s.m[l.vt][i] = in.material;
    if (in.op == TapeOp::glsl)
      for (int i = 0; i < l.n; ++i) detail::glsl_material(k, vec3<T>(px[i], py[i], pz[i]), l.s.m[l.vt][i]);
  }
}

template <auto Kernel, class T, bool WithMaterial>
MARCHCHECK_KERNEL void value(const kernels::Args<T>& k, const Instr&, Lanes<T, WithMaterial>& l) {
  const T* __restrict px = l.px();
  const T* __restrict py = l.py();
  const T* __restrict pz = l.pz();
  T* __restrict r = l.value(l.vt);
  for (int i = 0; i < l.n; ++i) r[i] = Kernel(k, r[i], vec3<T>(px[i], py[i], pz[i]));
}

template <auto Kernel, class T, bool WithMaterial>
MARCHCHECK_KERNEL void binary(const kernels::Args<T>& k, const Instr&, Lanes<T, WithMaterial>& l) {
  const T* __restrict b = l.value(l.vt--);
  T* __restrict r = l.value(l.vt);
  if constexpr (WithMaterial) {
    int* __restrict m = l.s.m[l.vt];
    const int* __restrict mb = l.s.m[l.vt + 1];
    for (int i = 0; i < l.n; ++i) {
      const kernels::Combined<T> c = Kernel(k, r[i], b[i]);
      m[i] = c.b_decides ? mb[i] : m[i];
      r[i] = c.value;
    }
  } else {
    for (int i = 0; i < l.n; ++i) r[i] = Kernel(k, r[i], b[i]).value;
  }
}

template <auto Kernel, class T, bool WithMaterial>
MARCHCHECK_KERNEL void point(const kernels::Args<T>& k, const Instr&, Lanes<T, WithMaterial>& l) {
  const T* __restrict px = l.px();
  const T* __restrict py = l.py();
  const T* __restrict pz = l.pz();
  ++l.pt;
  T* __restrict qx = l.s.x[l.pt];
  T* __restrict qy = l.s.y[l.pt];
  T* __restrict qz = l.s.z[l.pt];
  for (int i = 0; i < l.n; ++i) {
    const vec3<T> q = Kernel(k, vec3<T>(px[i], py[i], pz[i]));
    qx[i] = q.x;
    qy[i] = q.y;
    qz[i] = q.z;
  }
}

template <class T, bool WithMaterial>
void run_batch(const Tape& tape, const T* x, const T* y, const T* z, T* out, int* material, int n) {
  Lanes<T, WithMaterial> l(x, y, z, out, n);
  for (const Instr& in : tape.code) {
    const kernels::Args<T> k = tape.args<T>(in);
    switch (in.op) {
#define MARCHCHECK_BATCH(name, shape)                      \
  case TapeOp::name:                                       \
    shape<kernels::name<T>, T, WithMaterial>(k, in, l); \
    break;
      MARCHCHECK_TAPE_KERNELS(MARCHCHECK_BATCH)
#undef MARCHCHECK_BATCH
      case TapeOp::set_material:
        if constexpr (WithMaterial)
          for (int i = 0; i < n; ++i) l.s.m[l.vt][i] = in.material;
        break;
      case TapeOp::p_pop: --l.pt; break;
    }
  }
  if constexpr (WithMaterial)
    for (int i = 0; i < n; ++i) material[i] = l.s.m[0][i];
}

}  // namespace

// A half tape runs lane after lane through the one-point binary16 code (a model of a GPU's arithmetic, not a
// fast path).
template <class T>
void evaluate_batch(const Tape& tape, const T* x, const T* y, const T* z, T* out, int n) {
  if constexpr (std::is_same_v<T, float>)
    if (tape.half) {
      for (int i = 0; i < n; ++i) out[i] = detail::evaluate_half(tape, {x[i], y[i], z[i]});
      return;
    }
  run_batch<T, false>(tape, x, y, z, out, nullptr, n);
}

template <class T>
void sample_batch(const Tape& tape, const T* x, const T* y, const T* z, T* out, int* material, int n) {
  if constexpr (std::is_same_v<T, float>)
    if (tape.half) {
      for (int i = 0; i < n; ++i) {
        const Sample<float> s = detail::sample_half(tape, {x[i], y[i], z[i]});
        out[i] = s.distance;
        material[i] = s.material;
      }
      return;
    }
  run_batch<T, true>(tape, x, y, z, out, material, n);
}

template void sample_batch<float>(const Tape&, const float*, const float*, const float*, float*, int*, int);
template void sample_batch<double>(const Tape&, const double*, const double*, const double*, double*, int*, int);
template void evaluate_batch<float>(const Tape&, const float*, const float*, const float*, float*, int);
template void evaluate_batch<double>(const Tape&, const double*, const double*, const double*, double*, int);

}  // namespace marchcheck::sdf
