// Value noise over a hashed integer lattice, identical in float and double (the hash sees integers only).
#pragma once

#include "marchcheck/sdf/scalar.hpp"

#include <cstdint>

namespace marchcheck::sdf {

// A lattice value in [0, 1].
inline double lattice_value(std::int64_t ix, std::int64_t iz) {
  // splitmix64 finaliser over both coordinates: no visible lattice pattern, no sin() precision issues.
  std::uint64_t h = static_cast<std::uint64_t>(ix) * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint64_t>(iz) * 0xC2B2AE3D27D4EB4Full;
  h ^= h >> 30;
  h *= 0xBF58476D1CE4E5B9ull;
  h ^= h >> 27;
  h *= 0x94D049BB133111EBull;
  h ^= h >> 31;
  return static_cast<double>(h >> 11) * (1.0 / 9007199254740992.0);
}

// Bilinear value noise with smoothstep interpolation; values in [0, 1].
template <class T>
inline T value_noise(T x, T z) {
  using namespace smath;
  const T fx = floor(x), fz = floor(z);
  // Lattice coordinates beyond int64 (or NaN) would be undefined behaviour: fold them to cell 0.
  auto cell = [](auto v) { return v == v && v > -4e18 && v < 4e18 ? static_cast<std::int64_t>(v) : std::int64_t{0}; };
  const std::int64_t ix = cell(value_of(fx)), iz = cell(value_of(fz));
  const T tx = x - fx, tz = z - fz;
  const T ux = tx * tx * (T(3) - T(2) * tx), uz = tz * tz * (T(3) - T(2) * tz);
  using V = decltype(value_of(T{}));
  const T a(static_cast<V>(lattice_value(ix, iz))), b(static_cast<V>(lattice_value(ix + 1, iz)));
  const T c(static_cast<V>(lattice_value(ix, iz + 1))), d(static_cast<V>(lattice_value(ix + 1, iz + 1)));
  return mix(mix(a, b, ux), mix(c, d, ux), uz);
}

}  // namespace marchcheck::sdf
