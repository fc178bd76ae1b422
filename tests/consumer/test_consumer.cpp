// A user's own test suite with an installed marchcheck (tests/consumer/CMakeLists.txt): their sphere-on-a-floor
// SDF and their float sphere tracer, judged against marchcheck's exact references. The same file runs in
// marchcheck's own suite (test_validation), so the README's example is tested both ways.
#include <marchcheck/validation/gtest_helpers.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <vector>

namespace {

using marchcheck::march::Outcome;
using marchcheck::validation::MarchedRay;
using marchcheck::validation::TestRay;
namespace mc = marchcheck;

// The user's field, written once for float and double: a unit sphere resting on the floor y = -1.
auto sphere_on_floor = [](auto p) { return std::min(glm::length(p) - 1, p.y + 1); };

constexpr int kMaxSteps = 100;
constexpr float kHitEps = 1e-3f, kMaxDist = 100;

// The deliberate bugs the checks must catch.
enum class Bug { none, one_step_too_many, normal_not_normalised };

// The user's sphere tracer, in float.
template <Bug bug = Bug::none>
MarchedRay trace(const auto& sdf, const TestRay& ray) {
  const glm::vec3 ro(ray.origin), rd(ray.direction);
  float t = 0;
  const int limit = bug == Bug::one_step_too_many ? kMaxSteps + 1 : kMaxSteps;  // `i <= MAX_STEPS`
  for (int i = 0; i < limit; ++i) {
    const float d = sdf(ro + rd * t);
    if (d < kHitEps) return MarchedRay::hit(t);
    t += d;
    if (t > kMaxDist) return MarchedRay::miss(t);
  }
  return MarchedRay::out_of_steps(t);
}

// The user's normal, by central differences in float.
template <Bug bug = Bug::none>
glm::vec3 normal_at(const glm::vec3 p) {
  const float e = 1e-3f;
  const auto& f = sphere_on_floor;
  const glm::vec3 g(f(p + glm::vec3(e, 0, 0)) - f(p - glm::vec3(e, 0, 0)), f(p + glm::vec3(0, e, 0)) - f(p - glm::vec3(0, e, 0)),
                    f(p + glm::vec3(0, 0, e)) - f(p - glm::vec3(0, 0, e)));
  return bug == Bug::normal_not_normalised ? g : glm::normalize(g);
}

// What the field should draw and how the tracer claims to march it: marchcheck's scene, its references exact.
mc::sdf::Scene reference_scene() {
  mc::sdf::Scene scene;
  scene.name = "sphere-on-floor";
  scene.root = mc::sdf::unite({mc::sdf::sphere(1), mc::sdf::plane({0, 1, 0}, 1)});
  scene.camera.position = {0, 1, 5};
  scene.march.hit_eps = kHitEps;
  scene.march.max_steps = kMaxSteps;
  scene.march.max_dist = kMaxDist;
  // Toward the horizon the floor is met at grazing angles, where sphere tracing needs more than 100 steps: ~6% of
  // the rays run out of steps, and this tracer accepts up to 10% (validate's default limit is 0.2%).
  scene.limits["hit.undecided"] = 0.1;
  return scene;
}

TEST(UserField, SphereIsOneLipschitzAndThreeTimesItIsNot) {
  EXPECT_TRUE(mc::validation::LipschitzAtMost([](glm::dvec3 p) { return glm::length(p) - 1; }, 1));
  const auto steep = mc::validation::LipschitzAtMost([](glm::dvec3 p) { return 3 * (glm::length(p) - 1); }, 1);
  EXPECT_FALSE(steep);
  EXPECT_NE(std::string(steep.message()).find("exceeds the bound 1"), std::string::npos) << steep.message();
}

TEST(UserField, IsTheExactDistanceOfTheSphereOnTheFloor) {
  const mc::sdf::Node shape = reference_scene().root;
  EXPECT_TRUE(mc::validation::IsExactOf(sphere_on_floor, shape));
  // Half of it is still a bound, but no longer exact.
  const auto half = [](glm::dvec3 p) { return 0.5 * sphere_on_floor(p); };
  EXPECT_TRUE(mc::validation::IsBoundOf(half, shape));
  EXPECT_FALSE(mc::validation::IsExactOf(half, shape));
}

TEST(UserMarcher, PassesEveryCheckOfValidate) {
  EXPECT_TRUE(mc::validation::PassesValidate(
      reference_scene(), sphere_on_floor, [](const auto& sdf, const TestRay& ray) { return trace(sdf, ray); }, {},
      [](glm::dvec3 p) { return normal_at(p); }));
}

TEST(UserMarcher, OneStepPastItsLimitIsCaughtAndTheRayNamed) {
  const auto result = mc::validation::PassesValidate(
      reference_scene(), sphere_on_floor,
      [](const auto& sdf, const TestRay& ray) { return trace<Bug::one_step_too_many>(sdf, ray); }, {},
      [](glm::dvec3 p) { return normal_at(p); });
  EXPECT_FALSE(result);
  const std::string message = result.message();
  EXPECT_NE(message.find("march.over_max_steps"), std::string::npos) << message;
  EXPECT_NE(message.find("first: ray through pixel"), std::string::npos) << message;
}

TEST(UserMarcher, ANormalNotNormalisedIsCaughtAndTheRayNamed) {
  const auto result = mc::validation::PassesValidate(
      reference_scene(), sphere_on_floor,
      [](const auto& sdf, const TestRay& ray) { return trace(sdf, ray); }, {},
      [](glm::dvec3 p) { return normal_at<Bug::normal_not_normalised>(p); });
  EXPECT_FALSE(result);
  const std::string message = result.message();
  EXPECT_NE(message.find("normal.length_err_max"), std::string::npos) << message;
  EXPECT_NE(message.find("worst: ray through pixel"), std::string::npos) << message;
}

TEST(UserMarcher, HitsTheReferenceWithinTheHitThresholdOnARayList) {
  const mc::validation::Reference reference(reference_scene().root, 0);
  std::vector<TestRay> rays;  // across the sphere, level with the floor: hits at incidence cos >= 0.57, and misses
  for (double x = -1.2; x < 1.3; x += 0.4) rays.push_back({{x, 0.2, 5}, {0, 0, -1}});
  const auto hit_distance = [](const TestRay& ray) -> std::optional<double> {
    const MarchedRay r = trace(sphere_on_floor, ray);
    if (r.outcome != Outcome::hit) return std::nullopt;
    return r.t;
  };
  // Tolerance: the hit threshold over the cosine of the steepest incidence (1.75e-3), and float rounding of t.
  EXPECT_TRUE(mc::validation::MarcherMatchesReference(hit_distance, reference, rays, 2 * kHitEps, kMaxDist));
  // A tracer stopping 5% of the tolerance further short is caught: its errors are 2.1e-3 to 3.85e-3, over the
  // tolerance and under twice it (so a tolerance loosened to 2x would pass it).
  const auto early = [&](const TestRay& ray) {
    const auto t = hit_distance(ray);
    return t ? std::optional<double>(*t - 1.05 * 2 * kHitEps) : std::nullopt;
  };
  EXPECT_FALSE(mc::validation::MarcherMatchesReference(early, reference, rays, 2 * kHitEps, kMaxDist));
}

}  // namespace
