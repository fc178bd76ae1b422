// The numbers users read, pinned on constructed data with known answers: percentiles, medians, the default
// limits and where a value passes, and Pareto dominance.
#include "marchcheck/validation/statistics.hpp"
#include "marchcheck/validation/sweep.hpp"
#include "marchcheck/validation/validate.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <string>
#include <vector>

namespace marchcheck::validation {
namespace {

std::vector<double> one_to_hundred_shuffled() {
  std::vector<double> v(100);
  std::iota(v.begin(), v.end(), 1.0);
  std::shuffle(v.begin(), v.end(), std::mt19937(7));
  return v;
}

// Broken variants: rank over n instead of n - 1 (p99 = 100), no rounding to the nearest rank (p50 = 50), the
// values not sorted first.
TEST(Statistics, PercentileIsTheNearestRankOfTheSortedValues) {
  const auto v = one_to_hundred_shuffled();
  EXPECT_EQ(percentile(v, 0.99), 99);
  EXPECT_EQ(percentile(v, 0.5), 51);  // rank 0.5 * 99 = 49.5 rounds up: the 51st value
  EXPECT_EQ(percentile(v, 0), 1);
  EXPECT_EQ(percentile(v, 1), 100);
  EXPECT_EQ(percentile({}, 0.99), 0);
  EXPECT_EQ(percentile({5}, 0.99), 5);
}

// Broken variants: the upper middle value for an even count, no sort.
TEST(Statistics, MedianOfAnEvenCountIsTheMeanOfTheMiddleTwo) {
  EXPECT_EQ(median({4, 1, 3, 2}), 2.5);
  EXPECT_EQ(median({3, 1, 2}), 2);
  EXPECT_EQ(median({}), 0);
}

// The limits the README and the table state; a limit loosened (1.001 -> 1.1) or tightened by mistake fails here.
TEST(DefaultLimits, AreTheStatedValues) {
  const std::map<std::string, double> stated = {
      {"hit.false_hit", 0},          {"hit.false_miss", 0},
      {"hit.overshoot", 0},          {"hit.undecided", 0.002},
      {"hit.surface_dist_over_eps", 1.05}, {"normal.angle_p99_deg", 2},
      {"shadow.false_shadow", 0.002}, {"shadow.false_lit", 0.002},
      {"march.over_max_steps", 0},   {"normal.length_err_max", 1e-4}, {"march.sentinel_t", 0},
      {"sdf.lipschitz_over_declared", 1.001}, {"march.safe_step_ratio", 1.001},
      {"sdf.overestimate_max", 1e-6}, {"sdf.overestimate_marched_max", 1e-6}, {"sdf.precision_gap_max", 0},
      {"image.pixels_over", 0.02},
      {"camera.fov_err_deg", 1e-6},  {"camera.ray_norm_err", 1e-6}, {"image.nan_pixels", 0},
      {"sdf.lipschitz_certified_over_declared", 1.001}, {"reference.undecidable", 0.01},
  };
  std::map<std::string, double> actual;
  for (const auto& d : default_limits()) actual[d.metric] = d.limit;
  EXPECT_EQ(actual, stated);
}

// Each default limit at its value passes, just over it fails, just under passes; a scene's own limit replaces it.
// Broken variants: pass on value < limit (fails at the limit), the scene's limit ignored.
TEST(DefaultLimits, AValueAtTheLimitPassesAndJustOverFails) {
  for (const auto& d : default_limits()) {
    for (const auto& [value, pass] : {std::pair{d.limit, true},
                                      std::pair{std::nextafter(d.limit, INFINITY), false},
                                      std::pair{std::nextafter(d.limit, -INFINITY), true}}) {
      SceneResult r;
      r.metrics[d.metric] = value;
      apply_limits({}, false, r);
      ASSERT_EQ(r.checks.size(), 1u) << d.metric;
      EXPECT_EQ(r.checks[0].pass, pass) << d.metric << " = " << value;
      EXPECT_EQ(r.checks[0].limit_source, "default");
    }
    SceneResult own;
    own.metrics[d.metric] = d.limit + 1;
    apply_limits({{d.metric, d.limit + 1}}, false, own);
    EXPECT_TRUE(own.checks.at(0).pass) << d.metric;
    EXPECT_EQ(own.checks[0].limit_source, "scene");
  }
}

// Broken variant: an estimate held to its normal and image limits (or excused from the others).
TEST(DefaultLimits, AnEstimateIsHeldOnlyToTheLimitsThatCheckEstimates) {
  SceneResult r;
  for (const auto& d : default_limits()) r.metrics[d.metric] = d.limit + 1;  // every one over
  apply_limits({}, true, r);
  size_t checked = 0;
  for (const auto& d : default_limits()) {
    const bool listed = std::count(r.not_checked.begin(), r.not_checked.end(), d.metric) == 1;
    EXPECT_EQ(listed, !d.checks_estimates) << d.metric;
    checked += d.checks_estimates;
  }
  EXPECT_EQ(r.checks.size(), checked);
  EXPECT_FALSE(r.pass());
  // A scene limit brings it back.
  SceneResult own;
  own.metrics["normal.angle_p99_deg"] = 1;
  apply_limits({{"normal.angle_p99_deg", 5}}, true, own);
  ASSERT_EQ(own.checks.size(), 1u);
  EXPECT_TRUE(own.not_checked.empty());
}

SweepPoint point(double error, double evals) {
  SweepPoint p;
  p.metrics["image.rms"] = error;
  p.metrics["cost.evals_per_pixel"] = evals;
  p.metrics["cost.seconds"] = evals;
  return p;
}

// Broken variants: strict dominance in both coordinates (equal cost and lower error would not dominate), or no
// strictness at all (two equal points would knock each other out).
TEST(Pareto, EqualCostAndLowerErrorDominatesAndEqualPointsBothStay) {
  std::vector<SweepPoint> points = {point(1, 10), point(1, 5), point(0.5, 20), point(2, 5), point(1, 5),
                                    point(NAN, 1), point(0.5, 30)};
  mark_pareto(points, "image.rms");
  const std::vector<bool> expected = {false, true, true, false, true, false, false};
  for (size_t i = 0; i < points.size(); ++i) {
    EXPECT_EQ(points[i].pareto_evals, expected[i]) << "point " << i;
    EXPECT_EQ(points[i].pareto_seconds, expected[i]) << "point " << i;
  }
}

}  // namespace
}  // namespace marchcheck::validation
