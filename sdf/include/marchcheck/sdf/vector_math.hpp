// The float transcendentals of the march (sin, cos, atan, atan2, acos, pow, log, exp, floor): SLEEF's, so that
// the batched tape's loops vectorise through them and every lane of a batch gives the bits the one-point tape
// gives. Double evaluations (the references) keep the C library's: they share no approximation with the march.
// Accuracy, measured against double in VectorMath.*: every function within 1 ulp (SLEEF's u10 bound).
#pragma once

#include <cmath>

// The batched tape (tape_batch.cpp) declares the functions with GCC's vector function ABI: its vectoriser then
// calls their clones (_ZGV<isa>N<lanes>v_marchcheck_sinf, in vector_math.cpp for the instruction set the
// library is built for) and keeps the loops vectorised. Elsewhere they are plain functions.
#if defined(MARCHCHECK_VECTOR_CLONES) && defined(__GNUC__) && !defined(__clang__)
#define MARCHCHECK_VECTOR_FUNCTION __attribute__((simd("notinbranch"), const))
#else
#define MARCHCHECK_VECTOR_FUNCTION __attribute__((const))
#endif

// X(name, SLEEF's accuracy suffix): u10, within 1.0 ulp; floor is exact.
#define MARCHCHECK_VECTOR_MATH_UNARY(X) \
  X(sinf, u10) X(cosf, u10) X(atanf, u10) X(acosf, u10) X(logf, u10) X(expf, u10) X(floorf, )
#define MARCHCHECK_VECTOR_MATH_BINARY(X) X(atan2f, u10) X(powf, u10)

extern "C" {
#define MARCHCHECK_DECLARE_UNARY(name, accuracy) MARCHCHECK_VECTOR_FUNCTION float marchcheck_##name(float) noexcept;
#define MARCHCHECK_DECLARE_BINARY(name, accuracy) MARCHCHECK_VECTOR_FUNCTION float marchcheck_##name(float, float) noexcept;
MARCHCHECK_VECTOR_MATH_UNARY(MARCHCHECK_DECLARE_UNARY)
MARCHCHECK_VECTOR_MATH_BINARY(MARCHCHECK_DECLARE_BINARY)
#undef MARCHCHECK_DECLARE_UNARY
#undef MARCHCHECK_DECLARE_BINARY
}

namespace marchcheck::sdf::vmath {

inline float sin(float x) { return marchcheck_sinf(x); }
inline float cos(float x) { return marchcheck_cosf(x); }
inline float atan(float x) { return marchcheck_atanf(x); }
inline float acos(float x) { return marchcheck_acosf(x); }
inline float log(float x) { return marchcheck_logf(x); }
inline float exp(float x) { return marchcheck_expf(x); }
inline float atan2(float y, float x) { return marchcheck_atan2f(y, x); }
inline float pow(float x, float e) { return marchcheck_powf(x, e); }
// floor is exact in every implementation: with SSE4.1 the compiler's own instruction, inlined, is the same bits.
inline float floor(float x) {
#ifdef __SSE4_1__
  return std::floor(x);
#else
  return marchcheck_floorf(x);
#endif
}

inline double sin(double x) { return std::sin(x); }
inline double cos(double x) { return std::cos(x); }
inline double atan(double x) { return std::atan(x); }
inline double acos(double x) { return std::acos(x); }
inline double log(double x) { return std::log(x); }
inline double exp(double x) { return std::exp(x); }
inline double atan2(double y, double x) { return std::atan2(y, x); }
inline double pow(double x, double e) { return std::pow(x, e); }
inline double floor(double x) { return std::floor(x); }

}  // namespace marchcheck::sdf::vmath
