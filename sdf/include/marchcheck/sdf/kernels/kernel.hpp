// What every tape kernel is written against: the instruction's constants and the vector types. A kernel is one
// function template per tape instruction, evaluated alike in float, double and Dual (the one-point tape) and
// lane by lane in the batched tape, so both run the same expressions in the same order.
//
// Each family header lists its kernels in an X-macro, X(name, shape), that makes the TapeOp enum and the
// dispatch of both evaluators: a kernel is written once, in its family, and listed once. The shapes:
//   source: T name(const Args<T>&, vec3<T> p)              pushes a value (a primitive)
//   value:  T name(const Args<T>&, T d, vec3<T> p)         replaces the top value
//   binary: Combined<T> name(const Args<T>&, T a, T b)   pops b and replaces a (b_decides: b's material wins)
//   point:  vec3<T> name(const Args<T>&, vec3<T> p)          pushes a transformed point (popped by p_pop)
#pragma once

#include "marchcheck/sdf/scalar.hpp"

#include <cstdint>
#include <memory>
#include <type_traits>

// Kernels are inlined into both evaluators' loops whatever their size, as the cases of one switch would be: a
// call per lane would cost more than most kernels, and a kernel left out of line in a shared library is called
// through the PLT.
#define MARCHCHECK_KERNEL [[gnu::always_inline]] inline

namespace marchcheck::sdf {

class MeshDistance;
class GlslField;

namespace kernels {

using smath::vec2;
using smath::vec3;

// The constants of one instruction: k(i) in the evaluation type, raw(i) as stored (counts, flags), and the
// meshes and GLSL fields for their kernels. Float reads the constants rounded once at compile time, never converting.
template <class T>
struct Args {
  const double* constants;
  const float* constants_f;
  const std::shared_ptr<const MeshDistance>* meshes;
  const std::shared_ptr<const GlslField>* glsl_fields;
  std::uint32_t at;

  T operator()(std::uint32_t i) const {
    if constexpr (std::is_same_v<T, float>) {
      return constants_f[at + i];
    } else {
      return T(static_cast<decltype(value_of(T{}))>(constants[at + i]));
    }
  }
  double raw(std::uint32_t i) const { return constants[at + i]; }
};

template <class T>
struct Combined {
  T value;
  bool b_decides;  // the result's material is b's
};

// A constant of the evaluation's precision (the value type of a Dual).
template <class T>
MARCHCHECK_KERNEL T literal(double x) {
  return T(static_cast<decltype(value_of(T{}))>(x));
}

}  // namespace kernels
}  // namespace marchcheck::sdf
