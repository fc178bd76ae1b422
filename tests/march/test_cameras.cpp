// Every camera model and pose reprojects: the ray through pixel (x, y) projects back to (x, y).
#include "marchcheck/march/camera.hpp"
#include "marchcheck/sdf/builtin_scenes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace marchcheck::march {
namespace {

using sdf::CameraModel;
using sdf::CameraPose;
using sdf::CameraSpec;

CameraSpec spec(CameraModel model, CameraPose pose) {
  CameraSpec s;
  s.model = model;
  s.pose = pose;
  s.position = {1, 2, 6};
  s.target = {0.2, 0.5, 0};
  s.yaw_deg = 30;
  s.pitch_deg = 20;
  s.distance = 6;
  s.fov_deg = 70;
  s.fx = 600;
  s.fy = 580;
  s.cx = 650;
  s.cy = 350;
  s.k1 = 0.3;
  s.k2 = 0.05;
  s.p1 = 0.001;
  s.p2 = -0.002;
  return s;
}

// Worst reprojection error in pixels over a grid of pixels, for points at several depths along each ray.
double worst_reprojection(const Camera& cam, int w, int h) {
  double worst = 0;
  for (int y = 0; y <= h; y += h / 8)
    for (int x = 0; x <= w; x += w / 8)
      for (double depth : {0.5, 3.7, 40.0}) {
        const Ray r = cam.ray(x, y);
        const auto back = cam.project(r.origin + r.direction * depth);
        if (!back) return INFINITY;
        worst = std::max(worst, glm::length(*back - glm::dvec2(x, y)));
      }
  return worst;
}

class EveryCamera : public ::testing::TestWithParam<std::tuple<CameraModel, CameraPose>> {};

TEST_P(EveryCamera, RaysReprojectToTheirPixel) {
  const auto [model, pose] = GetParam();
  const Camera cam(spec(model, pose), 1280, 720);
  // Newton-solved undistortion converges to ~1e-15 in normalised coordinates: 1e-6 px is generous.
  EXPECT_LT(worst_reprojection(cam, 1280, 720), 1e-6);
}

TEST_P(EveryCamera, RaysAreUnitLength) {
  const auto [model, pose] = GetParam();
  const Camera cam(spec(model, pose), 640, 360);
  for (double x : {0.0, 100.5, 639.0}) EXPECT_NEAR(glm::length(cam.ray(x, 17.5).direction), 1.0, 1e-12);
}

INSTANTIATE_TEST_SUITE_P(All, EveryCamera,
                         ::testing::Combine(::testing::Values(CameraModel::pinhole, CameraModel::intrinsics,
                                                              CameraModel::frustum, CameraModel::orthographic),
                                            ::testing::Values(CameraPose::look_at, CameraPose::orbit)));

TEST(Cameras, PinholeSpansItsDeclaredFieldOfView) {
  for (double fov : {30.0, 70.0, 90.0}) {
    CameraSpec s = spec(CameraModel::pinhole, CameraPose::look_at);
    s.fov_deg = fov;
    EXPECT_NEAR(Camera(s, 1280, 720).measured_vertical_fov_deg(), fov, 1e-9);
  }
}

TEST(Cameras, FrustumCornersEqualThePinholeWithTheSameFieldOfView) {
  const Camera pinhole(spec(CameraModel::pinhole, CameraPose::look_at), 800, 600);
  const Camera frustum(spec(CameraModel::frustum, CameraPose::look_at), 800, 600);
  for (double x : {0.0, 123.4, 800.0})
    for (double y : {0.0, 300.0, 555.5})
      EXPECT_LT(glm::length(pinhole.ray(x, y).direction - frustum.ray(x, y).direction), 1e-12);
}

TEST(Cameras, OrbitPoseLooksAtTheTargetFromItsDistance) {
  const CameraSpec s = spec(CameraModel::pinhole, CameraPose::orbit);
  const Camera cam(s, 640, 480);
  EXPECT_NEAR(glm::length(cam.eye() - s.target), 6.0, 1e-12);
  const auto centre = cam.project(s.target);
  ASSERT_TRUE(centre.has_value());
  EXPECT_NEAR(centre->x, 320, 1e-9);
  EXPECT_NEAR(centre->y, 240, 1e-9);
  EXPECT_GT(cam.eye().y, s.target.y) << "positive pitch looks down from above";
}

TEST(Cameras, ImageYGoesDownAndXGoesRight) {
  const Camera cam(spec(CameraModel::pinhole, CameraPose::look_at), 640, 480);
  const auto up = cam.project(cam.eye() + cam.forward() * 5.0 + glm::dvec3(0, 1, 0));
  ASSERT_TRUE(up.has_value());
  EXPECT_LT(up->y, 240);
}

TEST(Cameras, ReprojectionCatchesACameraThatSkipsUndistortion) {
  // The broken variant: rays built from distorted coordinates as if they were undistorted.
  const CameraSpec s = spec(CameraModel::intrinsics, CameraPose::look_at);
  CameraSpec no_distortion = s;
  no_distortion.k1 = no_distortion.k2 = no_distortion.p1 = no_distortion.p2 = 0;
  const Camera right(s, 1280, 720), broken_rays(no_distortion, 1280, 720);
  const Ray r = broken_rays.ray(1200, 700);
  const auto back = right.project(r.origin + r.direction * 3.0);
  ASSERT_TRUE(back.has_value());
  EXPECT_GT(glm::length(*back - glm::dvec2(1200, 700)), 10.0);
}

// A shader's camera: at the origin looking along +z with a shader's axes and lens, the ray through pixel centre
// (x, y) is normalize(distort(x_n, y_n), 1) with (x_n, y_n) = (x - cx, cy - y) / f (y up; cx, cy counted from the
// top-left corner, as marchcheck's pixels) and the distortion SEED-SCENES writes (tangential terms in y up).
// Projection (Newton's undistortion) brings each ray back to its pixel. Broken variants: p1 taken in the image's y-down sense; the look-at camera's mirror.
TEST(Cameras, AShadersLensAndAxesAreItsFormula) {
  CameraSpec s;
  s.model = CameraModel::intrinsics;
  s.position = {0, 0, 0};
  s.target = {0, 0, 1};
  s.axes = sdf::CameraAxes::shader;
  s.lens = sdf::LensConvention::shader;
  s.fx = s.fy = 500, s.cx = 300, s.cy = 220;
  s.k1 = 0.1, s.k2 = 0.05, s.p1 = 0.01, s.p2 = -0.02;
  const int w = 640, h = 480;
  const Camera cam(s, w, h);
  double worst = 0;
  for (double y = 0.5; y < h; y += 47)
    for (double x = 0.5; x < w; x += 61) {
      const double u = (x - 300) / 500, v = (220 - y) / 500, r2 = u * u + v * v;
      const double radial = 1 + s.k1 * r2 + s.k2 * r2 * r2;
      const glm::dvec2 d(u * radial + 2 * s.p1 * u * v + s.p2 * (r2 + 2 * u * u),
                         v * radial + 2 * s.p2 * u * v + s.p1 * (r2 + 2 * v * v));
      worst = std::max(worst, glm::length(cam.ray(x, y).direction - glm::normalize(glm::dvec3(d, 1))));
    }
  EXPECT_LT(worst, 1e-12);
  EXPECT_LT(worst_reprojection(cam, w, h), 1e-6);
}

TEST(Cameras, PointsBehindTheCameraDoNotProject) {
  const Camera cam(spec(CameraModel::pinhole, CameraPose::look_at), 640, 480);
  EXPECT_FALSE(cam.project(cam.eye() - cam.forward()).has_value());
}

}  // namespace
}  // namespace marchcheck::march

namespace marchcheck::march {
namespace {

// How many of a 97 x 61 grid of pixels (odd sizes: partial blocks) get from rays() other bits than from ray().
int batched_ray_mismatches(const Camera& batched, const Camera& one) {
  std::vector<double> xs, ys;
  for (int y = 0; y < 61; ++y)
    for (int x = 0; x < 97; ++x) {
      xs.push_back(x * 13.3 + 0.5);
      ys.push_back(y * 11.9 + 0.5);
    }
  std::vector<Ray> out(xs.size());
  batched.rays(xs.data(), ys.data(), static_cast<int>(xs.size()), out.data());
  int bad = 0;
  for (size_t i = 0; i < xs.size(); ++i) {
    const Ray r = one.ray(xs[i], ys[i]);
    bad += r.origin != out[i].origin || r.direction != out[i].direction;
  }
  return bad;
}

// A camera at the origin looking down -z with y up: the undistorted image point (x, y) is the direction
// (x, -y, -1), so expected rays and pixels can be computed by hand.
CameraSpec looking_down_minus_z(CameraModel model) {
  CameraSpec s;
  s.model = model;
  s.position = {0, 0, 0};
  s.target = {0, 0, -1};
  s.up = {0, 1, 0};
  return s;
}

// Brown-Conrady as published (x_d = x (1 + k1 r^2 + k2 r^4) + 2 p1 x y + p2 (r^2 + 2 x^2), y_d = y (1 + k1 r^2 +
// k2 r^4) + p1 (r^2 + 2 y^2) + 2 p2 x y), every parameter non-zero, fx != fy, cx != cy, on a 640x480 image.
// By hand for (x, y) = (0.2, -0.1): r^2 = 0.05, radial = 1.005125, x_d = 0.201025 - 0.0004 - 0.0026 = 0.198025,
// y_d = -0.1005125 + 0.0007 + 0.0008 = -0.0990125; pixel (500 x_d + 300, 400 y_d + 220) = (399.0125, 180.395).
// Broken variants: p1 and p2 swapped, k2 unused, fx for fy.
TEST(Cameras, BrownConradyMapsAHandComputedPointBothWays) {
  CameraSpec s = looking_down_minus_z(CameraModel::intrinsics);
  s.fx = 500, s.fy = 400, s.cx = 300, s.cy = 220;
  s.k1 = 0.1, s.k2 = 0.05, s.p1 = 0.01, s.p2 = -0.02;
  const Camera cam(s, 640, 480);
  const auto pixel = cam.project({0.2 * 3, 0.1 * 3, -3});
  ASSERT_TRUE(pixel);
  EXPECT_NEAR(pixel->x, 399.0125, 1e-9);
  EXPECT_NEAR(pixel->y, 180.395, 1e-9);
  // Undistortion (Newton, to 1e-15 in normalised units) gives the ray back to ~1e-12.
  const Ray r = cam.ray(399.0125, 180.395);
  const glm::dvec3 expected = glm::normalize(glm::dvec3(0.2, 0.1, -1));
  EXPECT_NEAR(glm::length(r.direction - expected), 0, 1e-12);
}

// The principal point defaults to the image centre, cx from the width and cy from the height: on a 640x360 image
// pixel (320, 180) looks straight ahead. Broken variant: both from one axis.
TEST(Cameras, DefaultPrincipalPointIsTheCentreOfANonSquareImage) {
  CameraSpec s = looking_down_minus_z(CameraModel::intrinsics);
  s.fx = s.fy = 500;  // cx, cy left at their default (-1)
  const Camera cam(s, 640, 360);
  EXPECT_NEAR(glm::length(cam.ray(320, 180).direction - glm::dvec3(0, 0, -1)), 0, 1e-15);
  const auto centre = cam.project({0, 0, -2});
  ASSERT_TRUE(centre);
  EXPECT_EQ(*centre, glm::dvec2(320, 180));
}

// The pinhole by field of view: f = (h / 2) / tan(fov / 2) = 311.769... for 60 degrees on 640x360, so the corner
// pixel (0, 0) looks along (-320 / f, 180 / f, -1) = (-1.0264005, 0.5773503, -1). Broken variant: f from the width.
TEST(Cameras, PinholeCornerRayIsTheHandComputedOne) {
  CameraSpec s = looking_down_minus_z(CameraModel::pinhole);
  s.fov_deg = 60;
  const Camera cam(s, 640, 360);
  const glm::dvec3 expected = glm::normalize(glm::dvec3(-320 / 311.7691453623979, 180 / 311.7691453623979, -1));
  EXPECT_NEAR(glm::length(cam.ray(0, 0).direction - expected), 0, 1e-14);
  EXPECT_NEAR(cam.footprint_slope(), 0.5 / 311.7691453623979, 1e-15);
}

TEST(Camera, BatchedRaysAreTheOneRayResultsBitForBit) {
  for (const std::string& name : sdf::builtin_scene_names()) {
    const sdf::Scene s = sdf::builtin_scene(name);
    const Camera cam(s.camera, 1280, 720);
    EXPECT_EQ(batched_ray_mismatches(cam, cam), 0) << name;
  }
}

// The comparison can fail: a lens with k1 larger by 1e-12 (directions move by ~1e-12, far above a rounding) is
// caught.
TEST(Camera, BatchedRaysOfAnotherLensAreCaught) {
  sdf::Scene s = sdf::builtin_scene("lee-flat");
  const Camera one(s.camera, 1280, 720);
  s.camera.k1 += 1e-12;
  EXPECT_GT(batched_ray_mismatches(Camera(s.camera, 1280, 720), one), 1000);
}

}  // namespace
}  // namespace marchcheck::march
