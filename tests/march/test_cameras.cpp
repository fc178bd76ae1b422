// Every camera model and pose reprojects: the ray through pixel (x, y) projects back to (x, y).
#include "marchcheck/march/camera.hpp"
#include "marchcheck/sdf/builtin_scenes.hpp"
#include "marchcheck/validation/mesh_loader.hpp"

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

TEST(Camera, BatchedRaysAreTheOneRayResultsBitForBit) {
  for (const std::string& name : sdf::builtin_scene_names()) {
    const sdf::Scene s = sdf::builtin_scene(name, validation::mesh_loader());
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
