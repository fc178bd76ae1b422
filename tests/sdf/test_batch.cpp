// Batched evaluation gives the one-point tape's values bit for bit, on every built-in scene and on a tree that
// runs every vectorised instruction, in float and double; the comparison catches a field that differs by one
// rounding.
#include "marchcheck/sdf/builtin_scenes.hpp"
#include "marchcheck/sdf/node.hpp"
#include "marchcheck/sdf/tape.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <random>
#include <vector>

namespace marchcheck::sdf {
namespace {

// Points of the box the scenes live in, with a few batch lengths that leave partial vector registers.
template <class T>
std::vector<glm::vec<3, T>> points(int count) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-4, 4);
  std::vector<glm::vec<3, T>> v(static_cast<size_t>(count));
  for (auto& p : v) p = glm::vec<3, T>(glm::dvec3(u(rng), u(rng) * 0.5 + 1, u(rng)));
  return v;
}

bool same_bits(float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); }
bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

// How many points evaluate_batch / sample_batch (batch_tape) and evaluate / sample (point_tape) disagree on
// (values or materials; NaN equal to NaN only when the bits match), over batches of kBatch, 37 and 1 points.
template <class T>
int mismatches(const Tape& batch_tape, const Tape& point_tape) {
  const auto pts = points<T>(kBatch + 37 + 1);
  int bad = 0;
  size_t at = 0;
  for (int n : {kBatch, 37, 1}) {
    T x[kBatch], y[kBatch], z[kBatch], f[kBatch];
    for (int i = 0; i < n; ++i) {
      x[i] = pts[at + static_cast<size_t>(i)].x;
      y[i] = pts[at + static_cast<size_t>(i)].y;
      z[i] = pts[at + static_cast<size_t>(i)].z;
    }
    int material[kBatch];
    evaluate_batch(batch_tape, x, y, z, f, n);
    for (int i = 0; i < n; ++i) bad += !same_bits(f[i], evaluate(point_tape, pts[at + static_cast<size_t>(i)]));
    sample_batch(batch_tape, x, y, z, f, material, n);
    for (int i = 0; i < n; ++i) {
      const Sample<T> one = sample(point_tape, pts[at + static_cast<size_t>(i)]);
      bad += !same_bits(f[i], one.distance) || material[i] != one.material;
    }
    at += static_cast<size_t>(n);
  }
  return bad;
}

TEST(Batch, EveryBuiltinMatchesTheOnePointTapeBitForBit) {
  for (const std::string& name : builtin_scene_names()) {
    const Scene scene = builtin_scene(name);
    const Tape tape = compile(scene.root, scene.time);
    EXPECT_EQ(mismatches<float>(tape, tape), 0) << name;
    EXPECT_EQ(mismatches<double>(tape, tape), 0) << name;
  }
}

// Every instruction with a vectorised loop, and one that runs lane by lane (twist), in one tree.
Node every_vectorised_op() {
  const Node rounded = make(Op::round_box, {{"half_size", {0.5, 0.3, 0.4}}, {"radius", {0.1}}});
  const Node scaled = make(Op::scale, {{"factor", {1.7}}}, {torus(0.8, 0.2)});
  const Node turned = make(Op::rotate, {{"axis", {1, 2, 3}}, {"angle_deg", {40}}}, {box({0.6, 0.2, 0.9})});
  const Node swollen = make(Op::round, {{"radius", {0.05}}}, {turned});
  const Node twisted = make(Op::twist, {{"rate", {0.7}}}, {box({0.3, 1, 0.3})});
  return unite({intersect(subtract(translate({0.3, 1, 0}, sphere(1.1)), rounded), plane({0.1, 1, 0.2}, 0.3)),
                make(Op::smooth_intersection, {{"k", {0.3}}}, {scaled, swollen}),
                make(Op::smooth_subtraction, {{"k", {0.2}}}, {twisted, sphere(0.5)}),
                smooth_union(0.4, {translate({-2, 0, 1}, sphere(0.7)), translate({-1.5, 0.5, 1}, box({0.3, 0.3, 0.3}))})});
}

TEST(Batch, EveryVectorisedInstructionMatchesTheOnePointTapeBitForBit) {
  const Tape tape = compile(every_vectorised_op());
  EXPECT_EQ(mismatches<float>(tape, tape), 0);
  EXPECT_EQ(mismatches<double>(tape, tape), 0);
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
