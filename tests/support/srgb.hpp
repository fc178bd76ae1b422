// The sRGB transfer curve as the tests state it, apart from marchcheck's own: the oracle its 8-bit bytes are
// checked against.
#pragma once

#include <algorithm>
#include <cmath>

namespace marchcheck::testing {

inline float to_srgb(float linear) {
  const float c = std::clamp(linear, 0.0f, 1.0f);
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

}  // namespace marchcheck::testing
