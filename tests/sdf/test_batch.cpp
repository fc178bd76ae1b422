// Batched evaluation gives the one-point tape's values bit for bit, on every built-in scene and on a tree that
// runs every vectorised instruction, in float and double; the comparison catches a field that differs by one
// rounding.
#include "batch_compare.hpp"

#include "marchcheck/sdf/builtin_scenes.hpp"
#include "marchcheck/sdf/node.hpp"
#include "marchcheck/sdf/noise.hpp"
#include "marchcheck/sdf/tape.hpp"

#include <gtest/gtest.h>


namespace marchcheck::sdf {
namespace {

using testing::mismatches;

TEST(Batch, EveryBuiltinMatchesTheOnePointTapeBitForBit) {
  for (const std::string& name : builtin_scene_names()) {
    const Scene scene = builtin_scene(name);
    const Tape tape = compile(scene);  // fogerty-defect-mediump's in binary16
    EXPECT_EQ(mismatches<float>(tape, tape), 0) << name;
    EXPECT_EQ(mismatches<double>(tape, tape), 0) << name;
  }
}

// Every instruction with a vectorised loop, those through SLEEF's clones (twist, warp, displace: sin and cos;
// repeat: floor) and the height field octave by octave with each hash: each part alone, so that no union hides
// a part that differs, and all in one tree.
std::vector<Node> every_vectorised_part() {
  const Node rounded = make(Op::round_box, {{"half_size", {0.5, 0.3, 0.4}}, {"radius", {0.1}}});
  const Node scaled = make(Op::scale, {{"factor", {1.7}}}, {torus(0.8, 0.2)});
  const Node turned = make(Op::rotate, {{"axis", {1, 2, 3}}, {"angle_deg", {40}}}, {box({0.6, 0.2, 0.9})});
  const Node swollen = make(Op::round, {{"radius", {0.05}}}, {turned});
  const Node twisted = make(Op::twist, {{"rate", {0.7}}}, {box({0.3, 1, 0.3})});
  auto terrain = [](NoiseHash hash) {
    return make(Op::heightfield, {{"hash", {static_cast<double>(hash)}}, {"octaves", {-0.5, 0.5, -0.05, 2, 0.01, 40}}});
  };
  return {intersect(subtract(translate({0.3, 1, 0}, sphere(1.1)), rounded), plane({0.1, 1, 0.2}, 0.3)),
          translate({2, 0.5, -1}, make(Op::warp, {}, {sphere(0.6)})),
          make(Op::displace, {{"amplitude", {0.1}}, {"frequency", {15}}},
               {make(Op::repeat, {{"period", {3, 0, 3}}}, {translate({0, 1, 0}, box({0.4, 0.4, 0.4}))})}),
          translate({0, -1, 0}, terrain(NoiseHash::splitmix)),
          translate({0, -1.3, 0}, terrain(NoiseHash::seed_sin)),
          make(Op::smooth_intersection, {{"k", {0.3}}}, {scaled, swollen}),
          make(Op::smooth_subtraction, {{"k", {0.2}}}, {twisted, sphere(0.5)}),
          smooth_union(0.4, {translate({-2, 0, 1}, sphere(0.7)), translate({-1.5, 0.5, 1}, box({0.3, 0.3, 0.3}))})};
}
Node every_vectorised_op() { return unite(every_vectorised_part()); }

TEST(Batch, EveryVectorisedInstructionMatchesTheOnePointTapeBitForBit) {
  std::vector<Node> trees = every_vectorised_part();
  trees.push_back(every_vectorised_op());
  for (size_t i = 0; i < trees.size(); ++i) {
    const Tape tape = compile(trees[i]);
    EXPECT_EQ(mismatches<float>(tape, tape), 0) << "part " << i;
    EXPECT_EQ(mismatches<double>(tape, tape), 0) << "part " << i;
  }
}

// A half tape (GLSL's mediump) gives its one-point binary16 values in batches too, and they are not float's: most
// points differ (binary16 keeps 11 bits of float's 24). Broken variant: the batch ignoring the half flag
// (sdf-half-batch-in-float).
TEST(Batch, AHalfTapeMatchesItsOnePointValuesAndNotFloats) {
  const Tape in_float = compile(every_vectorised_op());
  Tape half = in_float;
  half.half = true;
  EXPECT_EQ(mismatches<float>(half, half), 0);
  EXPECT_GT(mismatches<float>(half, in_float), 50);
}

// The check can fail: a sphere larger by one float rounding (1 + 2^-23 instead of 1) is caught on most points.
TEST(Batch, AFieldOneRoundingApartIsCaught) {
  const Tape one = compile(translate({0, 1.2, 0}, sphere(1))), wider = compile(translate({0, 1.2, 0}, sphere(1 + 0x1p-23)));
  EXPECT_GT(mismatches<float>(wider, one), 50);
}

// The material comparison can fail too: the same shapes with the sphere's material changed are caught.
TEST(Batch, AnotherMaterialIsCaught) {
  const Tape one = compile(unite({translate({0, 1.2, 0}, sphere(1, 0)), plane({0, 1, 0}, 0, 1)}));
  const Tape other = compile(unite({translate({0, 1.2, 0}, sphere(1, 2)), plane({0, 1, 0}, 0, 1)}));
  EXPECT_GT(mismatches<float>(other, one), 0);
}

}  // namespace
}  // namespace marchcheck::sdf
