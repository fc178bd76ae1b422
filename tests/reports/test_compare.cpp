// Regression comparison of result files: what counts as worse, tolerances, and bad files.
#include "marchcheck/reports/compare.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace marchcheck::reports {
namespace {

// A validate result as `marchcheck validate --json` writes it, with the numbers the tests vary.
std::string validate_file(double false_hit, double psnr, double seconds, bool pass, const char* extra_scene = "") {
  return R"({"kind": "validate", "results": [{"scene": "lee-flat", "defects": [], "pass": )" +
         std::string(pass ? "true" : "false") + R"(, "checks": [{"name": "hit.false_hit", "value": )" +
         std::to_string(false_hit) + R"(, "limit": 0, "pass": )" + (pass ? "true" : "false") +
         R"(, "limit_source": "default", "why": ""}], "metrics": {"hit.false_hit": )" + std::to_string(false_hit) +
         R"(, "image.psnr": )" + std::to_string(psnr) + R"(, "cost.seconds": )" + std::to_string(seconds) +
         R"(, "hit.rays": 2304, "hit.t_err_max": null}})" + extra_scene + "]}";
}

Comparison compare(const std::string& a, const std::string& b, const std::vector<Tolerance>& t = {}) {
  return compare_results(flatten_results(a, "base.json"), flatten_results(b, "cur.json"), t);
}

const MetricChange& change(const Comparison& c, const std::string& key) {
  for (const auto& m : c.changes)
    if (m.key == key) return m;
  throw std::runtime_error("no change for " + key);
}

TEST(Compare, TheSameFileHasNoRegression) {
  const auto c = compare(validate_file(0, 40, 1, true), validate_file(0, 40, 1, true));
  EXPECT_FALSE(c.regression());
  EXPECT_EQ(c.count(Verdict::same), c.changes.size());
  EXPECT_EQ(c.changes.size(), 6u);  // 5 metrics (one null) and 1 check verdict
}

// Broken variant it catches: an allowance that ignores the tolerance (worse_by > allowed + 1 lets 0 -> 3 pass).
TEST(Compare, AMetricThatGotWorseIsARegression) {
  const auto c = compare(validate_file(0, 40, 1, true), validate_file(3, 40, 1, false));
  EXPECT_TRUE(c.regression());
  EXPECT_EQ(change(c, "lee-flat: hit.false_hit").verdict, Verdict::regression);
  EXPECT_EQ(change(c, "lee-flat: check hit.false_hit").verdict, Verdict::regression);
  // The other way round is an improvement.
  const auto back = compare(validate_file(3, 40, 1, false), validate_file(0, 40, 1, true));
  EXPECT_FALSE(back.regression());
  EXPECT_EQ(change(back, "lee-flat: hit.false_hit").verdict, Verdict::better);
}

// Broken variant it catches: image.psnr judged lower-is-better (its drop from 40 to 39 would pass).
TEST(Compare, PsnrIsBetterHigherAndTolerancesAreRelative) {
  const auto lower = compare(validate_file(0, 40, 1, true), validate_file(0, 39, 1, true));
  EXPECT_EQ(change(lower, "lee-flat: image.psnr").verdict, Verdict::regression);
  // 39 is 2.5% below 40: a 5% tolerance accepts it, 1% does not; the longer pattern wins over "*".
  const auto within = compare(validate_file(0, 40, 1, true), validate_file(0, 39, 1, true),
                              {parse_tolerance("*=0.01"), parse_tolerance("image.*=0.05")});
  EXPECT_EQ(change(within, "lee-flat: image.psnr").verdict, Verdict::worse_within_tolerance);
  EXPECT_FALSE(within.regression());
  const auto outside = compare(validate_file(0, 40, 1, true), validate_file(0, 39, 1, true),
                               {parse_tolerance("image.psnr=0.01")});
  EXPECT_TRUE(outside.regression());
  EXPECT_EQ(compare(validate_file(0, 40, 1, true), validate_file(0, 41, 1, true)).count(Verdict::better), 1u);
}

TEST(Compare, WallTimeOnlyCountsWhenAToleranceNamesIt) {
  const auto slower = compare(validate_file(0, 40, 1, true), validate_file(0, 40, 2, true));
  EXPECT_EQ(change(slower, "lee-flat: cost.seconds").verdict, Verdict::informational);
  EXPECT_FALSE(slower.regression());
  const auto gated = compare(validate_file(0, 40, 1, true), validate_file(0, 40, 2, true), {parse_tolerance("cost.seconds=0.5")});
  EXPECT_EQ(change(gated, "lee-flat: cost.seconds").verdict, Verdict::regression);
}

TEST(Compare, AScenePresentOnlyInTheBaselineIsMissingAndFails) {
  const std::string second = R"(, {"scene": "crum-torus", "defects": [], "pass": true, "checks": [], "metrics": {"hit.false_hit": 0}})";
  const auto dropped = compare(validate_file(0, 40, 1, true, second.c_str()), validate_file(0, 40, 1, true));
  EXPECT_EQ(change(dropped, "crum-torus: hit.false_hit").verdict, Verdict::missing);
  EXPECT_TRUE(dropped.regression());
  const auto added = compare(validate_file(0, 40, 1, true), validate_file(0, 40, 1, true, second.c_str()));
  EXPECT_EQ(change(added, "crum-torus: hit.false_hit").verdict, Verdict::added);
  EXPECT_FALSE(added.regression());
}

TEST(Compare, SweepPointsAreKeyedByTheirSettings) {
  const std::string a = R"({"kind": "sweep", "scene": "lee-flat", "points": [
      {"settings": {"max_steps": "8"}, "metrics": {"image.rms": 0.2, "cost.evals_per_pixel": 11}},
      {"settings": {"max_steps": "64"}, "metrics": {"image.rms": 0.02, "cost.evals_per_pixel": 35}}]})";
  const std::string b = R"({"kind": "sweep", "scene": "lee-flat", "points": [
      {"settings": {"max_steps": "8"}, "metrics": {"image.rms": 0.2, "cost.evals_per_pixel": 11}},
      {"settings": {"max_steps": "64"}, "metrics": {"image.rms": 0.02, "cost.evals_per_pixel": 40}}]})";
  const auto c = compare(a, b);
  EXPECT_EQ(change(c, "lee-flat [max_steps=64]: cost.evals_per_pixel").verdict, Verdict::regression);
  EXPECT_EQ(change(c, "lee-flat [max_steps=8]: cost.evals_per_pixel").verdict, Verdict::same);
  EXPECT_THROW(compare(a, validate_file(0, 40, 1, true)), ResultFileError);  // different kinds
}

TEST(Compare, BadFilesAndTolerancesNameTheProblem) {
  const auto message = [](const std::string& text) {
    try {
      flatten_results(text, "r.json");
    } catch (const ResultFileError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("{not json").find("r.json: not JSON"), std::string::npos);
  EXPECT_NE(message(R"({"kind": "render"})").find("\"kind\" must be"), std::string::npos);
  EXPECT_NE(message(R"({"kind": "validate", "results": [{"scene": "a", "metrics": {"x": "high"}, "checks": []}]})")
                .find("r.json: results[0].metrics.x: expected a number"),
            std::string::npos);
  EXPECT_THROW(parse_tolerance("cost.seconds"), ResultFileError);
  EXPECT_THROW(parse_tolerance("cost.seconds=-1"), ResultFileError);
}

// The gate's semantics as a table: one metric of one scene, its baseline and current value (NaN: null in the file,
// absent: the key is missing), the tolerances given, and the verdict. Each row names the broken variant it catches.
struct GateCase {
  const char* why;
  std::string metric;
  std::optional<double> baseline, current;
  std::vector<std::string> tolerances;
  Verdict verdict;
};

TEST(Compare, GateTable) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<GateCase> cases = {
      {"default 1e-6 relative: half of it is within", "hit.t_err_max", 1, 1 + 5e-7, {}, Verdict::worse_within_tolerance},
      {"default 1e-6 relative: twice it is a regression", "hit.t_err_max", 1, 1 + 2e-6, {}, Verdict::regression},
      {"a zero baseline tolerates rounding (1e-12) only", "hit.false_hit", 0, 1e-13, {}, Verdict::worse_within_tolerance},
      {"a zero baseline: 2e-12 is a regression", "hit.false_hit", 0, 2e-12, {}, Verdict::regression},
      {"lower is better", "hit.t_err_max", 1, 0.5, {}, Verdict::better},
      {"worse exactly by the allowance is within it (not > )", "hit.t_err_max", 1024, 1536, {"hit.t_err_max=0.5"},
       Verdict::worse_within_tolerance},
      {"just past the allowance is a regression", "hit.t_err_max", 1024, 1536.001, {"hit.t_err_max=0.5"},
       Verdict::regression},
      {"the allowance is relative to |baseline| (a negative baseline too)", "sdf.overestimate_max", -2, -1.9,
       {"sdf.*=0.1"}, Verdict::worse_within_tolerance},
      {"a check that went from pass to fail is a regression whatever the tolerance", "check hit.false_hit", 1, 0,
       {"*=1"}, Verdict::regression},
      {"a check that went from fail to pass is better", "check hit.false_hit", 0, 1, {}, Verdict::better},
      {"a number that became null (no longer measurable) is a regression", "hit.t_err_max", 1, nan, {"*=1"},
       Verdict::regression},
      {"null that became a number is better", "hit.t_err_max", nan, 1, {}, Verdict::better},
      {"null stays null: same", "hit.t_err_max", nan, nan, {}, Verdict::same},
      {"sample counts are informational", "hit.rays", 2304, 100, {}, Verdict::informational},
      {"an informational metric becoming null stays informational", "hit.rays", 2304, nan, {}, Verdict::informational},
      {"wall time without a tolerance is informational", "cost.seconds", 1, 5, {}, Verdict::informational},
      {"wall time named by a tolerance is compared: within", "cost.seconds", 1, 1.1, {"cost.seconds=0.2"},
       Verdict::worse_within_tolerance},
      {"wall time named by a tolerance is compared: beyond", "cost.seconds", 1, 1.3, {"cost.seconds=0.2"},
       Verdict::regression},
      {"a pattern naming wall time makes it compared", "cost.seconds", 1, 1.3, {"cost.*=0.2"}, Verdict::regression},
      {"PSNR is better higher", "image.psnr", 40, 39, {}, Verdict::regression},
      {"the exact name (the longest pattern) wins", "hit.t_err_max", 1, 1.05,
       {"*=1", "hit.*=0.1", "hit.t_err_max=0"}, Verdict::regression},
      {"the longest pattern wins, whatever the order", "hit.t_err_max", 1, 1.05,
       {"hit.t_err_max=0", "hit.*=0.1", "*=1"}, Verdict::regression},
      {"a prefix pattern beats *", "hit.t_err_p99", 1, 1.05, {"*=0", "hit.*=0.1"}, Verdict::worse_within_tolerance},
      {"a prefix pattern beats * either way round", "hit.t_err_p99", 1, 1.2, {"hit.*=0.1", "*=1"}, Verdict::regression},
      {"* covers what nothing longer names", "normal.angle_max_deg", 1, 1.5, {"hit.*=0", "*=1"},
       Verdict::worse_within_tolerance},
      {"a prefix pattern matches at the start only", "shadow.hit.t", 1, 1.5, {"hit.*=1"}, Verdict::regression},
      {"a metric missing from current is a regression", "hit.t_err_max", 1, std::nullopt, {}, Verdict::missing},
      {"a metric new in current is not", "hit.t_err_max", std::nullopt, 1, {}, Verdict::added},
  };
  for (const auto& c : cases) {
    FlatResults base{"validate", {}}, cur{"validate", {}};
    const std::string key = "s: " + c.metric;
    if (c.baseline) base.values[key] = *c.baseline;
    if (c.current) cur.values[key] = *c.current;
    std::vector<Tolerance> tolerances;
    for (const auto& t : c.tolerances) tolerances.push_back(parse_tolerance(t));
    const Comparison result = compare_results(base, cur, tolerances);
    ASSERT_EQ(result.changes.size(), 1u) << c.why;
    EXPECT_EQ(result.changes[0].verdict, c.verdict) << c.why << ": got " << to_string(result.changes[0].verdict);
    const bool fails = c.verdict == Verdict::regression || c.verdict == Verdict::missing;
    EXPECT_EQ(result.regression(), fails) << c.why;
  }
}

}  // namespace
}  // namespace marchcheck::reports
