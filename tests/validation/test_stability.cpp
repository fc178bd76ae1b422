// The hard-case battery: every case stable on the marchers as they are, unstable on its naive variant, and each
// clause of its criterion failing alone on a variant of its own (so no clause can stop checking unseen); a few
// cases' numbers checked against their closed forms.
#include "marchcheck/validation/stability.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

namespace marchcheck::validation {
namespace {

class Battery : public ::testing::TestWithParam<std::string> {};

StabilityOptions variant(const std::string& name) {
  StabilityOptions o;
  o.variant = name;
  return o;
}

// One test per case (one process each under ctest): stable as the marchers are, unstable on its naive variant,
// and every clause failing alone on its own variant, which fails no other clause and no precondition.
TEST_P(Battery, StableAndEachClauseFailsAloneOnItsVariant) {
  const auto c = run_stability_case(GetParam());
  EXPECT_TRUE(c.stable) << c.detail;
  EXPECT_TRUE(c.failed.empty());
  EXPECT_FALSE(c.metrics.empty()) << "a case without numbers";
  for (const auto& [name, value] : c.metrics) EXPECT_FALSE(std::isnan(value)) << name;
  ASSERT_FALSE(c.clauses.empty());
  ASSERT_FALSE(c.variants.empty());
  EXPECT_EQ(c.variants.front().name, "naive");
  const auto naive = run_stability_case(GetParam(), variant("naive"));
  EXPECT_FALSE(naive.stable) << "the naive variant (" << c.variants.front().what << ") passed: the criterion cannot fail";
  EXPECT_FALSE(naive.detail.empty());
  for (const std::string& clause : c.clauses)
    EXPECT_TRUE(std::any_of(c.variants.begin(), c.variants.end(), [&](const auto& v) { return v.breaks == clause; }))
        << "no variant fails clause " << clause << " alone";
  for (const StabilityVariant& v : c.variants) {
    if (v.breaks.empty()) continue;  // a naive variant that fails several clauses
    EXPECT_NE(std::find(c.clauses.begin(), c.clauses.end(), v.breaks), c.clauses.end()) << v.name << ": no such clause";
    const auto broken = run_stability_case(GetParam(), variant(v.name));
    EXPECT_EQ(broken.failed, std::vector<std::string>{v.breaks}) << v.name << " (" << v.what << "): " << broken.detail;
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, Battery, ::testing::ValuesIn(stability_case_names()),
                         [](const ::testing::TestParamInfo<std::string>& param) {
                           std::string name = param.param;
                           for (char& ch : name)
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           return name;
                         });

TEST(Stability, HasAtLeastFortyUniqueDottedCasesEachStatingItsCriterion) {
  const auto names = stability_case_names();
  EXPECT_GE(names.size(), 40u);
  EXPECT_EQ(std::set<std::string>(names.begin(), names.end()).size(), names.size());
  for (const auto& name : names) {
    EXPECT_NE(name.find('.'), std::string::npos) << name;
    const auto c = run_stability_case(name);
    EXPECT_FALSE(c.checks.empty() || c.criterion.empty() || c.variants.front().what.empty()) << name;
  }
  EXPECT_THROW(run_stability_case("no.such.case"), std::invalid_argument);
  EXPECT_THROW(run_stability_case("start.on", variant("no_such_variant")), std::invalid_argument);
}

TEST(Stability, GrazingStepsFollowTheLawAndTheNaiveBudgetEndsUndecided) {
  for (int k = 1; k <= 7; ++k) {
    const auto c = run_stability_case("grazing.b1e-" + std::to_string(k));
    // The law counts steps near the sphere: within 10% once b is small (approach and exit add a few steps).
    EXPECT_NEAR(c.metrics.at("steps_over_law"), 1.0, k >= 2 ? 0.1 : 0.2) << k;
  }
  const auto c = run_stability_case("grazing.b1e-5", variant("naive"));
  EXPECT_LT(c.metrics.at("steps"), c.metrics.at("law"));
  EXPECT_NE(c.detail.find("undecided"), std::string::npos) << c.detail;
}

TEST(Stability, ShallowPlaneStepsMatchTheGeometricLaw) {
  const auto c = run_stability_case("plane.incidence_0p01deg");
  // The height shrinks by 1 - sin(0.01 deg) per step: 52767 steps to fall from 1 to 1e-4, plus the last look.
  EXPECT_NEAR(c.metrics.at("steps"), 52767, 2);
  EXPECT_LE(c.metrics.at("t_err"), c.metrics.at("t_err_bound"));
}

TEST(Stability, OnlyTheScaleAwareShadowBiasSurvivesAFarScene) {
  const auto c = run_stability_case("shadow.self_hits.scaled_far");
  EXPECT_EQ(c.metrics.at("self_hits"), 0);
  // At radius 1e5 float spacing (8e-3) passes the seed's 10 hit_eps offset (1e-2): its shadow rays re-hit.
  EXPECT_GT(c.metrics.at("seed_offset.self_hits"), 0);
}

TEST(Stability, FloatBreaksDownAtTheFirstDecadeWhoseSpacingPassesHitEps) {
  const auto c = run_stability_case("far.double");
  EXPECT_EQ(c.metrics.at("float_world.breakdown_offset"), c.metrics.at("float_world.breakdown_predicted"));
  EXPECT_EQ(c.metrics.at("float_world.breakdown_offset"), 1e4);
  // Camera-relative float holds where world float has long broken down.
  const auto rel = run_stability_case("far.camera_relative");
  EXPECT_EQ(rel.metrics.at("1e7.float_camera_relative.wrong"), 0);
  EXPECT_GT(c.metrics.at("1e7.float_world.wrong"), 0);
}

TEST(Stability, PlainTracingOvershootsEveryNonLipschitzFieldAndTheMeasuredLRemovesIt) {
  for (const char* name : {"lipschitz.warp", "lipschitz.lattice_displacement", "lipschitz.terrain", "lipschitz.twist"}) {
    const auto c = run_stability_case(name);
    EXPECT_GT(c.metrics.at("plain.overshoots"), 0) << name;
    EXPECT_EQ(c.metrics.at("scaled.overshoots"), 0) << name;
    // The measurement is a lower bound on the true constant: never above the declared bound.
    EXPECT_LE(c.metrics.at("lipschitz.measured"), c.metrics.at("lipschitz.declared")) << name;
    EXPECT_GT(c.metrics.at("scaled.evals_per_ray"), c.metrics.at("plain.evals_per_ray")) << "safety costs steps";
  }
}

TEST(Stability, BadRaysCostNothingAndTheNaiveLoopSpendsEveryStepOnThem) {
  const auto c = run_stability_case("input.batch_cost");
  EXPECT_LE(c.metrics.at("evals_ratio"), 1.0) << "rejected up front, bad rays cost no evaluation";
  EXPECT_GT(run_stability_case("input.batch_cost", variant("naive")).metrics.at("evals_ratio"), 2.5);
}

}  // namespace
}  // namespace marchcheck::validation
