// The users' helpers beyond tests/consumer's example: each assertion fails on the broken variant it names, and
// the ray or point a failure names is the one that failed.
#include "marchcheck/meshes/procedural.hpp"
#include "marchcheck/validation/gtest_helpers.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

namespace marchcheck::validation {
namespace {

using glm::dvec3;

auto unit_sphere = [](auto p) { return glm::length(p) - 1; };

TEST(UserHelpers, LipschitzAtMostCatchesAFieldOnePercentSteeperThanDeclared) {
  // The allowance is 1e-6 relative (rounding of the differences over a step of 1e-5 is ~1e-11): 1% is far out.
  EXPECT_TRUE(LipschitzAtMost(unit_sphere, 1));
  EXPECT_FALSE(LipschitzAtMost([](dvec3 p) { return 1.01 * unit_sphere(p); }, 1)) << "broken variant: 1% steeper";
  EXPECT_TRUE(LipschitzAtMost([](dvec3 p) { return 1.01 * unit_sphere(p); }, 1.01));
}

TEST(UserHelpers, IsBoundOfCatchesAnOverestimateAndAFlippedSign) {
  const sdf::Node shape = sdf::sphere(1);
  EXPECT_TRUE(IsExactOf(unit_sphere, shape));
  // 1% short of the distance is a bound, not exact (the tolerance is 1e-9).
  EXPECT_TRUE(IsBoundOf([](dvec3 p) { return 0.99 * unit_sphere(p); }, shape));
  EXPECT_FALSE(IsExactOf([](dvec3 p) { return 0.99 * unit_sphere(p); }, shape)) << "broken variant: 1% short";
  const auto over = IsBoundOf([](dvec3 p) { return 1.5 * unit_sphere(p); }, shape);
  EXPECT_FALSE(over) << "broken variant: 1.5 times the distance";
  EXPECT_NE(std::string(over.message()).find("not a bound"), std::string::npos) << over.message();
  const auto flipped = IsBoundOf([](dvec3 p) { return -unit_sphere(p); }, shape);
  EXPECT_FALSE(flipped) << "broken variant: inside and outside swapped";
  EXPECT_NE(std::string(flipped.message()).find("the reference"), std::string::npos) << flipped.message();
}

TEST(UserHelpers, IsExactOfMeshHoldsTheFieldToTheSignedDistance) {
  const auto sphere = meshes::icosphere(1.0, 3);
  const Region region{dvec3(-2), dvec3(2)};
  // The mesh's own signed distance, from the reference: exact to rounding.
  const MeshReference ref(sphere.mesh);
  const auto mesh_distance = [&ref](dvec3 p) { return *ref.signed_distance(p); };
  EXPECT_TRUE(IsExactOfMesh(mesh_distance, sphere.mesh, region, 1e-9));
  // The analytic sphere differs from its icosphere by up to the chord error: a bound within it, not exact.
  EXPECT_TRUE(IsBoundOfMesh([](dvec3 p) { return 0.9 * unit_sphere(p); }, sphere.mesh, region, sphere.max_error));
  EXPECT_FALSE(IsExactOfMesh([](dvec3 p) { return 0.9 * unit_sphere(p); }, sphere.mesh, region, sphere.max_error))
      << "broken variant: 0.9 times the distance declared exact";
}

// A user's float sphere tracer over the unit sphere seen from z = 4, with the hit test it is given.
MarchedRay trace(const auto& f, const TestRay& ray, float hit_test) {
  const glm::vec3 ro(ray.origin), rd(ray.direction);
  float t = 0;
  for (int i = 0; i < 200; ++i) {
    const float d = f(ro + rd * t);
    if (d < hit_test) return MarchedRay::hit(t);
    if ((t += d) > 20) return MarchedRay::miss(t);
  }
  return MarchedRay::out_of_steps(t);
}

sdf::Scene sphere_scene() {
  sdf::Scene scene;
  scene.name = "sphere";
  scene.root = sdf::sphere(1);
  scene.camera.position = {0, 0, 4};
  scene.march.hit_eps = 1e-3;
  scene.march.max_steps = 200;
  scene.march.max_dist = 20;
  return scene;
}

glm::vec3 unit_normal(glm::vec3 p) { return glm::normalize(p); }

TEST(UserHelpers, AFieldDeclaredExactIsHeldToItsHitThreshold) {
  const auto honest = [](const auto& f, const TestRay& r) { return trace(f, r, 1e-3f); };
  EXPECT_TRUE(PassesValidate(sphere_scene(), unit_sphere, honest, {}, unit_normal));
  // Stops at three times the threshold it claims: an exact field promises hits within it.
  const auto loose = [](const auto& f, const TestRay& r) { return trace(f, r, 3e-3f); };
  const SceneResult result = validate_subject(sphere_scene(), user_subject(unit_sphere, loose, {}, unit_normal));
  EXPECT_GT(metric_value(result.metrics, "hit.surface_dist_over_eps"), 2.5) << "broken variant: hit test 3 eps";
  EXPECT_FALSE(result.pass());
}

TEST(UserHelpers, TheWorstOffenderIsTheOneWithTheLargestValue) {
  // Normals too long by 1e-3 (x + 2) at the hit: the worst is the hit with the largest x, and the offender named
  // for normal.length_err_max must be the one whose length gives the metric's value.
  const auto growing = [](glm::dvec3 p) { return glm::normalize(p) * (1 + 1e-3 * (p.x + 2)); };
  const auto honest = [](const auto& f, const TestRay& r) { return trace(f, r, 1e-3f); };
  const SceneResult result = validate_subject(sphere_scene(), user_subject(unit_sphere, honest, {}, growing));
  const double worst = metric_value(result.metrics, "normal.length_err_max");
  EXPECT_GT(worst, 2e-3);
  const std::string text = result.offenders.at("normal.length_err_max");
  // The text ends "; normal (x, y, z)". (No std::regex: GCC 12 warns falsely inside it under the sanitizers.)
  const size_t at = text.rfind("; normal (");
  ASSERT_NE(at, std::string::npos) << text;
  dvec3 n;
  ASSERT_EQ(std::sscanf(text.c_str() + at, "; normal (%lf, %lf, %lf)", &n.x, &n.y, &n.z), 3) << text;
  const double length = glm::length(n);
  // The text has 6 significant digits: its length is the metric's to ~1e-6.
  EXPECT_NEAR(length - 1, worst, 2e-6) << text;
}

TEST(UserHelpers, AMarcherThatReportsItsOwnEvaluationsIsTrustedWithThem) {
  // Without the field, marchcheck cannot count: the marcher's own count is what march.over_max_steps sees.
  const auto counted_by_marcher = [](const TestRay& r) {
    MarchedRay m = trace(unit_sphere, r, 1e-3f);
    m.evals = 201;  // one more than max_steps: a marcher that says so is caught
    return m;
  };
  const SceneResult result = validate_subject(sphere_scene(), user_subject(unit_sphere, counted_by_marcher));
  EXPECT_EQ(metric_value(result.metrics, "march.over_max_steps"), metric_value(result.metrics, "hit.rays"));
  EXPECT_FALSE(result.pass());
  // Every ray counts against it: the one named is the first sampled, through pixel (5, 5) of 640x360 on a 64x36
  // grid. Broken variant: the last offender kept instead of the first.
  EXPECT_EQ(result.offenders.at("march.over_max_steps").rfind("first: ray through pixel (5, 5),", 0), 0u)
      << result.offenders.at("march.over_max_steps");
  // And with neither a normal function nor the marcher's own normals, normals are not judged.
  EXPECT_TRUE(std::isnan(metric_value(result.metrics, "normal.length_err_max")));
}

}  // namespace
}  // namespace marchcheck::validation
