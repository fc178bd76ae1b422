// The sampled grid node: trilinear interpolation of a 1-Lipschitz field has per-axis slope <= 1, so |grad| <=
// sqrt(3); it stays within sqrt(3)/2 of a cell of an exact child. Both measured, and a declared L = 1 caught.
#include "marchcheck/meshes/procedural.hpp"
#include "marchcheck/sdf/mesh_distance.hpp"
#include "marchcheck/sdf/tape.hpp"
#include "marchcheck/validation/gtest_helpers.hpp"

#include <gtest/gtest.h>

#include <random>

namespace marchcheck::sdf {
namespace {

using glm::dvec3;

Node grid(Node child, double resolution, double padding = 0.1) {
  return make(Op::grid, {{"resolution", {resolution}}, {"padding", {padding}}}, {std::move(child)});
}

TEST(GridNode, DeclaresUnboundedWithLipschitzSqrt3AndTheGridAsBounds) {
  const Node g = grid(sphere(1), 33);
  const FieldInfo info = derive_info(g);
  EXPECT_EQ(info.kind, Kind::lipschitz);
  EXPECT_DOUBLE_EQ(info.lipschitz, std::sqrt(3.0));
  const GridLayout layout = grid_layout(g, derive_info(sphere(1)).bounds);
  EXPECT_DOUBLE_EQ(layout.cell, 2.2 / 32);  // the sphere's bounds grown by 0.1 each side, 33 samples along
  EXPECT_EQ(layout.count, glm::ivec3(33));
  EXPECT_DOUBLE_EQ(info.bounds.lo.x, -1.1);
}

TEST(GridNode, MeasuredSlopeExceedsOneAndStaysWithinSqrt3) {
  // Inside a box the field is max(|x|, |y|, |z|) - h: where samples on the diagonal planes meet, the interpolant
  // rises along all three axes at once (at the centre, gradient (1, 1, 1)).
  const Tape tape = compile(grid(box(dvec3(0.5)), 17));
  auto f = [&](dvec3 p) { return evaluate(tape, p); };
  const double slope = measured_slope(f, dvec3(-0.7), dvec3(0.7), 40000, 1e-6);
  std::printf("grid of a box: measured slope %.6f (sqrt(3) = %.6f)\n", slope, std::sqrt(3.0));
  EXPECT_TRUE(validation::LipschitzAtMost(f, std::sqrt(3.0), {dvec3(-0.7), dvec3(0.7)}, 40000, 1e-6));
  // The broken declaration: a grid of an exact field called exact (L = 1) is contradicted.
  EXPECT_FALSE(validation::LipschitzAtMost(f, 1.0, {dvec3(-0.7), dvec3(0.7)}, 40000, 1e-6));
  EXPECT_GT(slope, 1.3);  // random pairs rarely land at the centre, where it reaches sqrt(3)
  // Outside the grid the value grows by the distance to it: slope at most sqrt(3) there too.
  EXPECT_TRUE(validation::LipschitzAtMost(f, std::sqrt(3.0), {dvec3(-3), dvec3(3)}, 20000, 1e-6));
}

TEST(GridNode, WithinHalfACellDiagonalOfAnExactChild) {
  // |interp - d| <= sum_c w_c |d(c) - d(p)| <= sum_c w_c |c - p| <= sqrt(sum_c w_c |c - p|^2) = sqrt(sum over
  // axes of t (1 - t)) cell <= sqrt(3) / 2 cell.
  struct Case {
    const char* name;
    Node child;
  };
  Node notched = mesh("procedural:notched_box(1,0.7,0.6)");
  notched.mesh = std::make_shared<const MeshDistance>(meshes::notched_box({1, 0.7, 0.6}).mesh);
  const Case cases[] = {{"sphere", sphere(1)}, {"torus", torus(1, 0.3)}, {"notched box mesh", notched}};
  for (const auto& c : cases) {
    const Node g = grid(c.child, 24);
    const GridLayout layout = grid_layout(g, derive_info(c.child).bounds);
    const Tape exact = compile(c.child), sampled = compile(g);
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> u(0, 1);
    double worst = 0;
    for (int i = 0; i < 20000; ++i) {
      const dvec3 p = layout.lo + dvec3(layout.count - 1) * layout.cell * dvec3(u(rng), u(rng), u(rng));
      worst = std::max(worst, std::abs(evaluate(sampled, p) - evaluate(exact, p)));
    }
    const double bound = std::sqrt(3.0) / 2 * layout.cell;
    std::printf("%s: largest error %.5f, bound %.5f (cell %.5f)\n", c.name, worst, bound, layout.cell);
    EXPECT_LE(worst, bound * (1 + 1e-12)) << c.name;
    // Not vacuous: curved or creased surfaces use a good part of it.
    EXPECT_GT(worst, 0.05 * bound) << c.name;
  }
}

TEST(GridNode, FloatDoubleAndDualAgreeAndTheGradientIsTheInterpolants) {
  const Tape tape = compile(grid(torus(1, 0.3), 20));
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1.6, 1.6);
  using D = Dual<double>;
  for (int i = 0; i < 200; ++i) {
    const dvec3 p(u(rng), u(rng) * 0.3, u(rng));
    const double d = evaluate(tape, p);
    // Float: samples and arithmetic rounded to float, values of order 1.
    EXPECT_NEAR(evaluate(tape, glm::vec3(p)), d, 1e-5);
    const D dual = evaluate(tape, glm::vec<3, D>(D(p.x, {1, 0, 0}), D(p.y, {0, 1, 0}), D(p.z, {0, 0, 1})));
    EXPECT_EQ(dual.v, d);
    const double h = 1e-7;  // within one cell almost surely: the interpolant is a polynomial there
    for (int k = 0; k < 3; ++k) {
      dvec3 e(0);
      e[k] = h;
      EXPECT_NEAR(dual.d[k], (evaluate(tape, p + e) - evaluate(tape, p - e)) / (2 * h), 1e-6);
    }
  }
}

TEST(GridNode, NeedsAChildWithFiniteBounds) {
  const std::string error = validate_tree(grid(plane({0, 1, 0}, 0), 8));
  EXPECT_EQ(error, "/child: a grid needs a child with finite bounds");
  EXPECT_EQ(validate_tree(grid(sphere(1), 8)), "");
}

}  // namespace
}  // namespace marchcheck::sdf
