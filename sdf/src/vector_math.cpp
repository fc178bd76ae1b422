// The vector math functions (vector_math.hpp) over SLEEF: the scalar function and the vector clones of every
// instruction set this library's code may call them from. SLEEF's deterministic variants give the same bits in
// every lane width: "finz" with fused multiply-adds, "cinz" without. Which kind is the build target's, so the
// scalar function (the one-point tape) and each clone (the batched tape) agree bit for bit.
#include "marchcheck/sdf/vector_math.hpp"

#include <sleef.h>

#if defined(__AVX2__) && defined(__FMA__)
#define MARCHCHECK_SLEEF_1(name, acc) Sleef_finz_##name##1_##acc##purecfma
#define MARCHCHECK_SLEEF_4(name, acc) Sleef_finz_##name##4_##acc##avx2128
#define MARCHCHECK_SLEEF_8(name, acc) Sleef_finz_##name##8_##acc##avx2
#define MARCHCHECK_SLEEF_16(name, acc) Sleef_finz_##name##16_##acc##avx512f
#else
#define MARCHCHECK_SLEEF_1(name, acc) Sleef_cinz_##name##1_##acc##purec
#define MARCHCHECK_SLEEF_4(name, acc) Sleef_cinz_##name##4_##acc##sse2
#define MARCHCHECK_SLEEF_8(name, acc) Sleef_cinz_##name##8_##acc##avx
#define MARCHCHECK_SLEEF_16(name, acc) Sleef_cinz_##name##16_##acc##avx512fnofma
#endif

// The x86-64 vector function ABI's clones: b SSE (4 lanes), c AVX and d AVX2 (8), e AVX-512 (16). GCC calls one
// only from code built for its instruction set, the library's own, so the clones past it are not needed.
#define MARCHCHECK_CLONE_UNARY(isa, lanes, type, name, acc) \
  type _ZGV##isa##N##lanes##v_marchcheck_##name(type x) { return MARCHCHECK_SLEEF_##lanes(name, acc)(x); }
#define MARCHCHECK_CLONE_BINARY(isa, lanes, type, name, acc)         \
  type _ZGV##isa##N##lanes##vv_marchcheck_##name(type x, type y) { \
    return MARCHCHECK_SLEEF_##lanes(name, acc)(x, y);              \
  }

#if defined(__AVX512F__)
#define MARCHCHECK_CLONES_E(shape, name, acc) MARCHCHECK_CLONE_##shape(e, 16, __m512, name, acc)
#else
#define MARCHCHECK_CLONES_E(shape, name, acc)
#endif
#if defined(__AVX2__)
#define MARCHCHECK_CLONES_D(shape, name, acc) MARCHCHECK_CLONE_##shape(d, 8, __m256, name, acc)
#else
#define MARCHCHECK_CLONES_D(shape, name, acc)
#endif
#if defined(__AVX__)
#define MARCHCHECK_CLONES_C(shape, name, acc) MARCHCHECK_CLONE_##shape(c, 8, __m256, name, acc)
#else
#define MARCHCHECK_CLONES_C(shape, name, acc)
#endif
#define MARCHCHECK_CLONES(shape, name, acc)                                                            \
  MARCHCHECK_CLONE_##shape(b, 4, __m128, name, acc) MARCHCHECK_CLONES_C(shape, name, acc)               \
      MARCHCHECK_CLONES_D(shape, name, acc) MARCHCHECK_CLONES_E(shape, name, acc)

extern "C" {
#define MARCHCHECK_DEFINE_UNARY(name, acc)                                                   \
  float marchcheck_##name(float x) noexcept { return MARCHCHECK_SLEEF_1(name, acc)(x); }          \
  MARCHCHECK_CLONES(UNARY, name, acc)
#define MARCHCHECK_DEFINE_BINARY(name, acc)                                                    \
  float marchcheck_##name(float x, float y) noexcept { return MARCHCHECK_SLEEF_1(name, acc)(x, y); } \
  MARCHCHECK_CLONES(BINARY, name, acc)
MARCHCHECK_VECTOR_MATH_UNARY(MARCHCHECK_DEFINE_UNARY)
MARCHCHECK_VECTOR_MATH_BINARY(MARCHCHECK_DEFINE_BINARY)
}
