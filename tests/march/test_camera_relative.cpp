// Camera-relative marching: the eye folded into the scene's translations in double keeps float's precision
// near the camera however far the scene is from the origin.
#include "marchcheck/march/camera_relative.hpp"
#include "marchcheck/sdf/tape.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace marchcheck::march {
namespace {

using glm::dvec3;
using glm::vec3;

TEST(CameraRelative, FloatNearTheEyeStaysExactWhereWrappingTheSceneDoesNot) {
  const dvec3 eye(1e7, -3e6, 2e5);
  const sdf::Node world = sdf::unite({sdf::translate(eye + dvec3(0, 0, -4), sdf::sphere(1)),
                                      sdf::subtract(sdf::translate(eye + dvec3(2, 0, -5), sdf::box({0.5, 0.5, 0.5})),
                                                    sdf::translate(eye + dvec3(2, 0.5, -5), sdf::sphere(0.3)))});
  const sdf::Tape truth = sdf::compile(world), relative = sdf::compile(camera_relative(world, eye)),
                  wrapped = sdf::compile(sdf::translate(-eye, world));
  double relative_err = 0, wrapped_err = 0;
  for (int i = 0; i < 200; ++i) {
    const dvec3 q(std::sin(i * 1.3) * 3, std::cos(i * 0.7) * 2, -6 + std::sin(i * 0.31) * 3);
    const double exact = sdf::evaluate(truth, q + eye);  // double at 1e7: spacing 2e-9
    relative_err = std::max(relative_err, std::abs(sdf::evaluate(relative, vec3(q)) - exact));
    wrapped_err = std::max(wrapped_err, std::abs(sdf::evaluate(wrapped, vec3(q)) - exact));
  }
  // Float at |q| <= 10 rounds to 1e-6; at 1e7 its spacing is 1, so the wrapped scene is off by up to half that.
  EXPECT_LE(relative_err, 4e-6);
  EXPECT_GT(wrapped_err, 0.1);
}

TEST(CameraRelative, WrapsWhatItCannotFoldAndStaysTheSameField) {
  const dvec3 eye(3, 4, 5);
  const sdf::Node twisted = sdf::make(sdf::Op::twist, {{"rate", {1}}}, {sdf::box({1, 2, 1})});
  const sdf::Node rel = camera_relative(twisted, eye);
  EXPECT_EQ(rel.op, sdf::Op::translate);
  const sdf::Tape a = sdf::compile(twisted), b = sdf::compile(rel);
  for (int i = 0; i < 50; ++i) {
    const dvec3 q(std::sin(i * 1.1) * 4, std::cos(i * 0.9) * 4, std::sin(i * 0.4) * 4);
    EXPECT_NEAR(sdf::evaluate(b, q), sdf::evaluate(a, q + eye), 1e-12);  // double rounding of q + eye
  }
}

}  // namespace
}  // namespace marchcheck::march
