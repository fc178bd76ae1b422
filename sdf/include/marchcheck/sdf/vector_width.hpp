#pragma once
// The width of the target's vector registers in bytes, for code that computes whole vectors of lanes with GCC's
// vector extension (packet marching, a mesh leaf's rows): wider vectors than the registers are split by the
// compiler, and their values spill when they no longer fit.

namespace marchcheck::sdf {

#if defined(__AVX512F__)
inline constexpr int kVectorBytes = 64;
#elif defined(__AVX__)
inline constexpr int kVectorBytes = 32;
#else
inline constexpr int kVectorBytes = 16;
#endif

}  // namespace marchcheck::sdf
