// Convergence: error falls and cost rises with the step limit and the hit threshold; grazing rays follow the law.
#include "marchcheck/sdf/builtin_scenes.hpp"
#include "marchcheck/validation/convergence.hpp"

#include <gtest/gtest.h>

namespace marchcheck::validation {
namespace {

TEST(Convergence, MoreStepsDecideMoreRaysAtMoreCost) {
  const auto rows = steps_study(sdf::builtin_scene("lee-flat"), {8, 16, 32, 64, 128, 256});
  for (size_t i = 1; i < rows.size(); ++i) {
    EXPECT_GE(rows[i].decided, rows[i - 1].decided) << rows[i].parameter;
    EXPECT_GE(rows[i].evals_per_ray, rows[i - 1].evals_per_ray) << rows[i].parameter;
  }
  EXPECT_LT(rows.front().decided, 0.9) << "8 steps leave many rays undecided";
  EXPECT_GT(rows.back().decided, 0.99);
}

TEST(Convergence, SmallerEpsGivesSmallerHitErrorAtMoreCost) {
  const auto rows = eps_study(sdf::builtin_scene("crum-torus"), {1e-1, 1e-2, 1e-3, 1e-4});
  for (size_t i = 1; i < rows.size(); ++i) {
    EXPECT_LT(rows[i].t_err_p99, rows[i - 1].t_err_p99) << rows[i].parameter;
    EXPECT_GT(rows[i].evals_per_ray, rows[i - 1].evals_per_ray) << rows[i].parameter;
  }
}

TEST(Convergence, GrazingRaysFollowTheSquareRootLaw) {
  for (const auto& row : grazing_study({1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6})) {
    // The law counts the steps spent near the sphere; approach and exit add a few more.
    EXPECT_GT(row.steps, 0.5 * row.law) << row.clearance;
    EXPECT_LT(row.steps, 1.5 * row.law + 20) << row.clearance;
    EXPECT_EQ(row.outcome, march::Outcome::miss_far) << row.clearance;
  }
  // The fogerty seed's 32 steps are under the law from b = 1e-2 on: the ray ends undecided, not hit.
  EXPECT_EQ(grazing_study({1e-2}, 32).front().outcome, march::Outcome::miss_steps);
}

}  // namespace
}  // namespace marchcheck::validation
