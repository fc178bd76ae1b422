// Every operator, from the list of all of them, through every evaluator: its example compiles and derives; the
// Dual gradients equal central differences; the declared kind holds against the zero set the field itself
// draws; the batched tape matches the one-point tape bit for bit; a scene file round-trips it. An operator added
// without rules, example or kernel fails here. Each check is also shown failing on a broken variant below.
#include "batch_compare.hpp"
#include "zero_set.hpp"

#include "marchcheck/sdf/node.hpp"
#include "marchcheck/sdf/scene_file.hpp"
#include "marchcheck/sdf/tape.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>

namespace marchcheck::sdf {
namespace {

// Examples are compiled at a time where the animated operators (animate, warp) are not the identity.
constexpr double kTime = 0.7;

glm::dvec3 dual_gradient(const Tape& tape, glm::dvec3 p) {
  using D = Dual<double>;
  return evaluate(tape, glm::vec<3, D>(D(p.x, {1, 0, 0}), D(p.y, {0, 1, 0}), D(p.z, {0, 0, 1}))).d;
}

glm::dvec3 difference(const Tape& tape, glm::dvec3 p, double ahead, double behind) {
  glm::dvec3 g;
  for (int i = 0; i < 3; ++i) {
    glm::dvec3 e(0);
    e[i] = 1;
    g[i] = (evaluate(tape, p + ahead * e) - evaluate(tape, p - behind * e)) / (ahead + behind);
  }
  return g;
}

// Where the field is examined: its bounds grown by 0.3, within [-2.5, 2.5]^3 (unbounded fields: that cube).
Box3 region(const FieldInfo& info) {
  const Box3 grown{info.bounds.lo - 0.3, info.bounds.hi + 0.3};
  return {glm::max(grown.lo, glm::dvec3(-2.5)), glm::min(grown.hi, glm::dvec3(2.5))};
}

struct GradientCheck {
  int compared = 0;
  double worst = 0;  // largest |Dual gradient - central difference| / (1 + |gradient|)
};

// dual_tape's gradients against central differences of fd_tape (the same tape unless a test breaks it), at
// random points of the region. Points on a crease (one-sided differences at 1e-6 apart by more than 1e-4) are
// skipped: there the gradient is one side's.
GradientCheck check_gradients(const Tape& dual_tape, const Tape& fd_tape, const Box3& box) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  GradientCheck c;
  constexpr double h = 1e-6;
  for (int i = 0; i < 200; ++i) {
    const glm::dvec3 p = box.lo + box.size() * glm::dvec3(u(rng), u(rng), u(rng));
    if (glm::length(difference(fd_tape, p, h, 0) - difference(fd_tape, p, 0, h)) > 1e-4) continue;
    const glm::dvec3 g = dual_gradient(dual_tape, p);
    c.worst = std::max(c.worst, glm::length(g - difference(fd_tape, p, h, h)) / (1 + glm::length(g)));
    ++c.compared;
  }
  return c;
}

// The declared kind against the zero set the field's own sign draws (grid 0.025, bisected): an exact field's
// |f| is the distance to it within the grid's sampling error, a bound's never exceeds it, a Lipschitz field's
// never exceeds L times it. Returns "" or what failed.
std::string kind_problem(const Tape& tape, const FieldInfo& info, const Box3& box) {
  constexpr double kGrid = 0.025;
  // Double rounding at these magnitudes is ~1e-15; the bisection places surface points within 1e-9 grid.
  constexpr double kRounding = 1e-9;
  const testing::Inside inside = [&](glm::dvec3 p) { return evaluate(tape, p) < 0; };
  const testing::ZeroSet zs(inside, box.lo - 0.3, box.hi + 0.3, kGrid);
  if (zs.points.size() < 50) return "zero set not found (" + std::to_string(zs.points.size()) + " points)";
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  const double scale = info.kind == Kind::lipschitz ? info.lipschitz : 1.0;
  for (int i = 0; i < 300; ++i) {
    const glm::dvec3 p = box.lo + box.size() * glm::dvec3(u(rng), u(rng), u(rng));
    const double f = std::abs(evaluate(tape, p)), d = zs.distance(p);
    if (f > scale * d + kRounding)
      return "|f| " + std::to_string(f) + " exceeds " + std::to_string(scale) + " x distance " + std::to_string(d);
    // Surface beyond the sampled box can be nearer than any sampled point: only distances under its margin count.
    if (info.kind == Kind::exact && f < 0.3 && d - f > testing::ZeroSet::sampling_error(kGrid))
      return "|f| " + std::to_string(f) + " is short of the distance " + std::to_string(d) + " (not exact)";
  }
  return "";
}

Scene scene_of(Node root) {
  Scene s;
  s.root = std::move(root);
  s.time = kTime;
  return s;
}

// "" when the scene file gives back the tree: the same text when written again, and a tape that evaluates to
// the same bits.
std::string round_trip_problem(const Scene& written, const Scene& expected) {
  const std::string text = scene_to_json(written);
  const Scene back = scene_from_json(text, "every_operator.json");
  if (scene_to_json(back) != scene_to_json(expected)) return "the text differs";
  if (testing::mismatches<double>(compile(back.root, back.time), compile(expected.root, expected.time)) != 0)
    return "the values differ";
  return "";
}

class EveryOperator : public ::testing::TestWithParam<Op> {};

TEST_P(EveryOperator, CompilesDerivesDifferentiatesKeepsItsKindBatchesAndRoundTrips) {
  const Node node = example(GetParam());
  // 2D shapes are examined extruded: a field of the plane has no 3D zero set of its own.
  const Node field = op_info(node.op).dimension == 2 ? make(Op::extrude, {{"half_depth", {0.3}}}, {node}) : node;
  ASSERT_EQ(validate_tree(field), "");
  const Tape tape = compile(field, kTime);
  const FieldInfo info = derive_info(field, kTime);
  EXPECT_GT(info.lipschitz, 0);
  EXPECT_TRUE(std::isfinite(info.lipschitz));
  EXPECT_FALSE(info.reason.empty());

  const GradientCheck g = check_gradients(tape, tape, region(info));
  EXPECT_GE(g.compared, 100) << "too few points off creases";
  // Central differences at h = 1e-6 carry ~1e-10 rounding and O(h^2) truncation (third derivatives here are
  // below ~1e3): 1e-6 relative is ample and far below any wrong derivative.
  EXPECT_LT(g.worst, 1e-6);

  if (info.kind == Kind::estimate) {
    EXPECT_EQ(node.op, Op::mandelbulb) << "only the fractal declares no distance property";
  } else {
    EXPECT_EQ(kind_problem(tape, info, region(info)), "") << to_string(info.kind) << ": " << info.reason;
  }

  EXPECT_EQ(testing::mismatches<float>(tape, tape), 0);
  EXPECT_EQ(testing::mismatches<double>(tape, tape), 0);

  EXPECT_EQ(round_trip_problem(scene_of(field), scene_of(field)), "");
}

INSTANTIATE_TEST_SUITE_P(All, EveryOperator, ::testing::ValuesIn(all_ops()),
                         [](const auto& param) { return std::string(op_info(param.param).name); });

// Broken variants: each check fails on a field or a declaration that is wrong.

// A twist of another rate differentiates to other gradients.
TEST(EveryOperatorChecks, GradientsOfAnotherFieldAreCaught) {
  const Node a = make(Op::twist, {{"rate", {1.5}}}, {box({0.5, 0.4, 0.3})});
  const Node b = make(Op::twist, {{"rate", {1.51}}}, {box({0.5, 0.4, 0.3})});
  EXPECT_GT(check_gradients(compile(a), compile(b), region(derive_info(a))).worst, 1e-3);
}

// The ellipsoid (a bound) declared exact; the displaced torus (Lipschitz 1 + a w) declared a bound; a steep
// height field declared with L = 1.
TEST(EveryOperatorChecks, AWrongKindOrLipschitzConstantIsCaught) {
  const Node ellipsoid = example(Op::ellipsoid);
  FieldInfo info = derive_info(ellipsoid);
  info.kind = Kind::exact;
  EXPECT_NE(kind_problem(compile(ellipsoid), info, region(info)), "");

  const Node displaced = make(Op::displace, {{"amplitude", {0.2}}, {"frequency", {8}}}, {torus(0.7, 0.25)});
  info = derive_info(displaced);
  info.kind = Kind::bound;
  EXPECT_NE(kind_problem(compile(displaced), info, region(info)), "");

  const Node steep = make(Op::heightfield, {{"octaves", {0.6, 3}}});
  info = derive_info(steep);
  info.lipschitz = 1;
  EXPECT_NE(kind_problem(compile(steep), info, region(info)), "");
}

// A scene file that loses a parameter's last bits, or the tree, is caught.
TEST(EveryOperatorChecks, ARoundTripThatChangesTheTreeIsCaught) {
  const Node written = make(Op::rotate, {{"axis", {1, 2, 3}}, {"angle_deg", {40}}}, {box({0.5, 0.4, 0.3})});
  const Node other = make(Op::rotate, {{"axis", {1, 2, 3}}, {"angle_deg", {std::nextafter(40.0, 41.0)}}},
                          {box({0.5, 0.4, 0.3})});
  EXPECT_NE(round_trip_problem(scene_of(written), scene_of(other)), "");
}

}  // namespace
}  // namespace marchcheck::sdf
