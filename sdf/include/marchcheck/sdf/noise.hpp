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

// The lattice hashes a height field's noise takes. splitmix: lattice_value, the same function in every precision.
// seed_sin: the lee seed's fract(sin(dot(c, (12.9898, 54.233))) * 43758.5453123), computed in the march's own
// arithmetic as its shader does: sin of an argument of |c| * 55, times 43758, keeps a few correct digits in float,
// so the terrain is not the same in float and double, and moves farther from the origin (the seed's defect).
enum class NoiseHash { splitmix = 0, seed_sin = 1 };

template <class V>
inline V seed_sin_lattice(std::int64_t ix, std::int64_t iz) {
  const V s = vmath::sin(static_cast<V>(ix) * V(12.9898) + static_cast<V>(iz) * V(54.233)) * V(43758.5453123);
  return s - vmath::floor(s);
}

template <class V>
inline V lattice(NoiseHash hash, std::int64_t ix, std::int64_t iz) {
  return hash == NoiseHash::seed_sin ? seed_sin_lattice<V>(ix, iz) : static_cast<V>(lattice_value(ix, iz));
}

// Bilinear value noise with smoothstep interpolation; values in [0, 1]. Free of branches, so that a loop over the
// batched tape's lanes vectorises through it (the hash a template argument, the cells' fold a select).
template <NoiseHash Hash, class T>
inline T value_noise(T x, T z) {
  using namespace smath;
  using V = decltype(value_of(T{}));
  const T fx = floor(x), fz = floor(z);
  // Lattice coordinates beyond int64 (or NaN, for which both comparisons are false) would be undefined
  // behaviour: fold them to cell 0, selected before the conversion.
  auto cell = [](V v) { return static_cast<std::int64_t>(v > V(-4e18) && v < V(4e18) ? v : V(0)); };
  const std::int64_t ix = cell(value_of(fx)), iz = cell(value_of(fz));
  const T tx = x - fx, tz = z - fz;
  const T ux = tx * tx * (T(3) - T(2) * tx), uz = tz * tz * (T(3) - T(2) * tz);
  const T a(lattice<V>(Hash, ix, iz)), b(lattice<V>(Hash, ix + 1, iz));
  const T c(lattice<V>(Hash, ix, iz + 1)), d(lattice<V>(Hash, ix + 1, iz + 1));
  return mix(mix(a, b, ux), mix(c, d, ux), uz);
}

template <class T>
inline T value_noise(T x, T z, NoiseHash hash = NoiseHash::splitmix) {
  return hash == NoiseHash::seed_sin ? value_noise<NoiseHash::seed_sin>(x, z) : value_noise<NoiseHash::splitmix>(x, z);
}

}  // namespace marchcheck::sdf
