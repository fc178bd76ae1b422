// Zero-set references: exact primitives agree with the CGAL distance to their procedural meshes within the
// meshes' error bounds; a wrong sphere radius and a wrong torus minor radius are caught.
#include "marchcheck/validation/zero_set.hpp"

#include <gtest/gtest.h>

#include <cstdio>

namespace marchcheck::validation {
namespace {

TEST(ZeroSet, ExactPrimitivesMatchTheirMeshesWithinTheMeshError) {
  for (const sdf::Node& n : {sdf::sphere(1.3), sdf::torus(1, 0.3), sdf::box({0.5, 0.8, 0.3})}) {
    const auto mesh = zero_set_mesh(n);
    ASSERT_TRUE(mesh);
    const ZeroSetCheck c = exact_against_zero_set(sdf::compile(n), *mesh);
    std::printf("%s: sdf.exact_err_max %.3g, limit %.3g\n", sdf::op_info(n.op).name.data(), c.exact_err_max, c.limit);
    EXPECT_TRUE(c.pass()) << c.exact_err_max << " > " << c.limit;
  }
  EXPECT_FALSE(zero_set_mesh(sdf::plane({0, 1, 0}, 0)));
}

TEST(ZeroSet, WrongRadiiAreCaught) {
  // The field of a sphere 1% too large against the mesh of the intended one.
  const ZeroSetCheck radius = exact_against_zero_set(sdf::compile(sdf::sphere(1.01)), *zero_set_mesh(sdf::sphere(1)));
  EXPECT_FALSE(radius.pass()) << radius.exact_err_max;
  EXPECT_NEAR(radius.exact_err_max, 0.01, radius.limit);
  // The torus's minor radius off by 1%.
  const ZeroSetCheck minor = exact_against_zero_set(sdf::compile(sdf::torus(1, 0.303)), *zero_set_mesh(sdf::torus(1, 0.3)));
  EXPECT_FALSE(minor.pass()) << minor.exact_err_max;
  // A field at half the distance everywhere (a sphere of radius 0.5 seen through a doubling map: 0.5 (|p| - 1)),
  // too small inside and out. Broken variant: only a field larger than the distance counted.
  const sdf::Node halved = sdf::make(sdf::Op::affine, {{"model", {2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0}}}, {sdf::sphere(0.5)});
  const ZeroSetCheck half = exact_against_zero_set(sdf::compile(halved), *zero_set_mesh(sdf::sphere(1)));
  EXPECT_FALSE(half.pass()) << half.exact_err_max;
}

}  // namespace
}  // namespace marchcheck::validation
