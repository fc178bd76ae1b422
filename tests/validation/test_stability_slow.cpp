// The slow sizes of the hard-case battery (labelled slow): the generated 1.3M-triangle mesh.
#include "marchcheck/validation/stability.hpp"

#include <gtest/gtest.h>

namespace marchcheck::validation {
namespace {

TEST(StabilitySlow, MillionTriangleMeshWithinItsStatedMemory) {
  StabilityOptions full;
  full.full = true;
  const auto c = run_stability_case("mesh.million_triangles", full);
  EXPECT_TRUE(c.stable) << c.detail;
  EXPECT_GE(c.metrics.at("triangles"), 1e6);
  EXPECT_LE(c.metrics.at("peak_rss_growth_mib"), c.metrics.at("memory_limit_mib"));
}

}  // namespace
}  // namespace marchcheck::validation
