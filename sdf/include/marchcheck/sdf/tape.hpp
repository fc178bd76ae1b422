// A scene tree compiled to a flat program ("tape"): evaluated by one loop over instructions with fixed-size
// stacks, so a scene loaded from a file costs no allocation and no virtual call per evaluation.
#pragma once

#include "marchcheck/sdf/kernels/combinations.hpp"
#include "marchcheck/sdf/kernels/domain.hpp"
#include "marchcheck/sdf/kernels/modifiers.hpp"
#include "marchcheck/sdf/kernels/primitives.hpp"
#include "marchcheck/sdf/kernels/shapes_2d.hpp"
#include "marchcheck/sdf/node.hpp"

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <vector>

namespace marchcheck::sdf {

// The tape's instructions: the kernels of every family (marchcheck/sdf/kernels/), then the tape's own two.
#define MARCHCHECK_TAPE_KERNELS(X)                                                                          \
  MARCHCHECK_PRIMITIVE_KERNELS(X) MARCHCHECK_SHAPE_2D_KERNELS(X) MARCHCHECK_COMBINATION_KERNELS(X)          \
  MARCHCHECK_MODIFIER_KERNELS(X) MARCHCHECK_DOMAIN_KERNELS(X)

enum class TapeOp : std::uint8_t {
#define MARCHCHECK_TAPE_OP(name, shape) name,
  MARCHCHECK_TAPE_KERNELS(MARCHCHECK_TAPE_OP)
#undef MARCHCHECK_TAPE_OP
  set_material,  // the top value takes the instruction's material
  p_pop,         // drops the top point
};

struct Instr {
  TapeOp op;
  std::uint32_t arg = 0;  // offset into Tape::constants (mesh and glsl: index into Tape::meshes, glsl_fields)
  std::int32_t material = -1;
};

inline constexpr int kMaxValueStack = 32;
inline constexpr int kMaxPointStack = 32;

struct Tape {
  std::vector<Instr> code;
  std::vector<double> constants;
  std::vector<float> constants_f;  // the same constants rounded once, so float evaluation never converts
  std::vector<std::shared_ptr<const MeshDistance>> meshes;
  std::vector<std::shared_ptr<const GlslField>> glsl_fields;
  int value_depth = 0;
  int point_depth = 0;
  // GLSL's mediump as mobile GPUs run it: the float evaluations computed in IEEE binary16 (half.hpp), every
  // operation rounded; double and dual evaluations stay as they are. A scene's precision "half".
  bool half = false;

  template <class T>
  kernels::Args<T> args(const Instr& in) const {
    return {constants.data(), constants_f.data(), meshes.data(), glsl_fields.data(), in.arg};
  }
};

struct CompileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Throws CompileError when the tree is invalid or needs deeper stacks than the fixed ones.
Tape compile(const Node& root, double time = 0.0);
struct Scene;
// The scene's tree (or root, one made from it) at its time, in its precision (half: float evaluations in binary16).
Tape compile(const Scene& scene);
Tape compile(const Scene& scene, const Node& root);

template <class T>
struct Sample {
  T distance;
  int material;
};

namespace detail {

using smath::vec3;

// A GLSL field's own material, where its result's .y selects one (GlslSpec::materials).
template <class T>
inline void glsl_material(const kernels::Args<T>& k, vec3<T> p, int& material) {
  const int m = k.glsl_fields[k.at]->material(glm::dvec3(value_of(p.x), value_of(p.y), value_of(p.z)));
  if (m >= 0) material = m;
}

// One instruction on the stacks (vt, pt: the top value and point), by its kernel's shape.
template <auto Kernel, class T, bool WithMaterial>
MARCHCHECK_KERNEL void source(const kernels::Args<T>& k, const Instr& in, T* values, int* materials, int& vt,
                              vec3<T>* points,
                   int& pt) {
  values[++vt] = Kernel(k, points[pt]);
  if constexpr (WithMaterial) {
    materials[vt] = in.material;
    if (in.op == TapeOp::glsl) glsl_material(k, points[pt], materials[vt]);
  }
}
template <auto Kernel, class T, bool WithMaterial>
MARCHCHECK_KERNEL void value(const kernels::Args<T>& k, const Instr&, T* values, int*, int& vt, vec3<T>* points,
                             int& pt) {
  values[vt] = Kernel(k, values[vt], points[pt]);
}
template <auto Kernel, class T, bool WithMaterial>
MARCHCHECK_KERNEL void binary(const kernels::Args<T>& k, const Instr&, T* values, int* materials, int& vt, vec3<T>*,
                              int&) {
  const T b = values[vt--];
  const kernels::Combined<T> r = Kernel(k, values[vt], b);
  if constexpr (WithMaterial)
    if (r.b_decides) materials[vt] = materials[vt + 1];
  values[vt] = r.value;
}
template <auto Kernel, class T, bool WithMaterial>
MARCHCHECK_KERNEL void point(const kernels::Args<T>& k, const Instr&, T*, int*, int&, vec3<T>* points, int& pt) {
  const vec3<T> q = Kernel(k, points[pt]);
  points[++pt] = q;
}

template <class T, bool WithMaterial>
inline void step(const Tape& tape, const Instr& in, T* values, int* materials, int& vt, vec3<T>* points, int& pt) {
  const kernels::Args<T> k = tape.args<T>(in);
  switch (in.op) {
#define MARCHCHECK_STEP(name, shape)                                                         \
  case TapeOp::name:                                                                         \
    shape<kernels::name<T>, T, WithMaterial>(k, in, values, materials, vt, points, pt); \
    break;
    MARCHCHECK_TAPE_KERNELS(MARCHCHECK_STEP)
#undef MARCHCHECK_STEP
    case TapeOp::set_material:
      if constexpr (WithMaterial) materials[vt] = in.material;
      break;
    case TapeOp::p_pop: --pt; break;
  }
}

template <class T, bool WithMaterial>
inline Sample<T> run(const Tape& tape, vec3<T> p0) {
  T values[kMaxValueStack];
  values[0] = T(0);  // every tape writes it; GCC cannot see that through the kernels' switch
  int materials[WithMaterial ? kMaxValueStack : 1];
  materials[0] = -1;
  vec3<T> points[kMaxPointStack];
  int vt = -1, pt = 0;
  points[0] = p0;
  for (const Instr& in : tape.code) step<T, WithMaterial>(tape, in, values, materials, vt, points, pt);
  if constexpr (WithMaterial) {
    return {values[0], materials[0]};
  } else {
    return {values[0], -1};
  }
}

// A half tape's float evaluation: p rounded to binary16, the tape run in binary16 (out of line, in one unit).
float evaluate_half(const Tape& tape, glm::vec3 p);
Sample<float> sample_half(const Tape& tape, glm::vec3 p);

}  // namespace detail

// The field's value at p.
template <class T>
inline T evaluate(const Tape& tape, glm::vec<3, T> p) {
  if constexpr (std::is_same_v<T, float>)
    if (tape.half) return detail::evaluate_half(tape, p);
  return detail::run<T, false>(tape, p).distance;
}

// The field's value at p and the material of the child that decides it.
template <class T>
inline Sample<T> sample(const Tape& tape, glm::vec<3, T> p) {
  if constexpr (std::is_same_v<T, float>)
    if (tape.half) return detail::sample_half(tape, p);
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
