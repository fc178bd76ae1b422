// The Mandelbulb's reference: its set by membership alone, against the estimator it judges.
#include "marchcheck/sdf/builtin_scenes.hpp"
#include "marchcheck/validation/reference.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace marchcheck::validation {
namespace {

using glm::dvec3;

const sdf::Node& bulb() {
  static const sdf::Node node = sdf::builtin_scene("crum-mandelbulb").root;
  return node;
}
const dvec3 kEye(-1.1, 1.5, 2.0);  // crum-mandelbulb's camera

// The estimate is 0.25 log(|w_N|^2) |w_N| / dz: negative exactly where |w_N| < 1, so its sign and the set are
// the same thing computed by different code. (A set read as "the orbit stays within the bailout", the usual
// escape-time picture, is larger: it disagreed with the sign at 159 of these 20000 points; that broken variant
// fails here.)
TEST(EscapeTimeSet, IsWhereTheEstimateIsNegative) {
  const EscapeTimeSet set(bulb());
  const sdf::Tape tape = sdf::compile(bulb());
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  int inside = 0;
  for (int k = 0; k < 20000; ++k) {
    const dvec3 p(u(rng), u(rng), u(rng));
    const bool in = set.contains(p);
    inside += in;
    ASSERT_EQ(in, sdf::evaluate(tape, p) <= 0) << p.x << " " << p.y << " " << p.z;
  }
  EXPECT_GT(inside, 1000);  // the comparison covers both sides
}

TEST(EscapeTimeSet, EveryPointBeyondItsRadiusEscapesAtOnce) {
  const EscapeTimeSet set(bulb());
  const double r = set.radius();
  EXPECT_NEAR(std::pow(r, 8) - r, 2, 1e-6);  // power 8, bailout 2
  std::mt19937 rng(3);
  std::normal_distribution<double> g;
  for (int k = 0; k < 2000; ++k) EXPECT_FALSE(set.contains(glm::normalize(dvec3(g(rng), g(rng), g(rng))) * r));
}

// Each hit is a witness: the set starts there (within the bisection's 1e-11), and the normal points out of it,
// as central differences of |w_N|^2 say. Eight iterations of a power-8 map have derivatives near 8^8, so the
// difference's truncation error only settles at h = 1e-9 (measured: largest angle 22 degrees at 1e-6, 2.7 at
// 1e-7, 0.04 at 1e-8, 0.002 at 1e-9); rounding at 1e-9 is still below 0.001 degree. Broken variant: the ray's
// reverse as the normal fails.
TEST(EscapeTimeSet, HitsAreWitnessedAndNormalsAreTheGradientOfTheFinalRadius) {
  const EscapeTimeSet set(bulb());
  std::mt19937 rng(5);
  std::normal_distribution<double> g;
  int hits = 0;
  for (int k = 0; k < 300; ++k) {
    const dvec3 d = glm::normalize(dvec3(g(rng), g(rng), g(rng)) * 0.4 - kEye);
    const ReferenceHit h = set.first_hit(kEye, d, 10);
    if (!h.hit) continue;
    ++hits;
    EXPECT_TRUE(set.contains(kEye + d * (h.t + 1e-10)));
    EXPECT_FALSE(set.contains(kEye + d * (h.t - 1e-10)));
    const dvec3 p = kEye + d * h.t;
    dvec3 grad;
    const double step = 1e-9;
    for (int i = 0; i < 3; ++i) {
      dvec3 e(0);
      e[i] = step;
      grad[i] = (set.final_radius2(p + e) - set.final_radius2(p - e)) / (2 * step);
    }
    EXPECT_GT(glm::dot(glm::normalize(grad), h.normal), std::cos(0.01 * std::numbers::pi / 180));
  }
  EXPECT_GT(hits, 250);
}

// What its resolution costs: parts of the set thinner than the sampling step are missed, so a finer step finds
// an earlier first hit on many rays (broken variant: a resolution argument that is ignored finds none).
TEST(EscapeTimeSet, FinerSamplingFindsThinnerFilamentsFirst) {
  const EscapeTimeSet set(bulb());
  std::mt19937 rng(9);
  std::normal_distribution<double> g;
  int earlier = 0, rays = 0;
  for (int k = 0; k < 60; ++k) {
    const dvec3 d = glm::normalize(dvec3(g(rng), g(rng), g(rng)) * 0.3 - kEye);
    const ReferenceHit coarse = set.first_hit(kEye, d, 10), fine = set.first_hit(kEye, d, 10, 1e-5);
    if (!coarse.hit) continue;
    ++rays;
    ASSERT_TRUE(fine.hit);
    earlier += fine.t < coarse.t - 1e-9;
  }
  EXPECT_GT(rays, 50);
  EXPECT_GT(earlier, rays / 10);  // measured: 90 of 150 such rays at 1e-3 against 1e-5
}

}  // namespace
}  // namespace marchcheck::validation

namespace marchcheck::validation {
namespace {

// A Mandelbulb moved, turned and scaled is the same set seen through the motion: the same hit distance along
// the same ray taken into its frame, and the normal turned back out (broken variant: a normal left in the set's
// frame fails).
TEST(EscapeTimeSet, StandsInForAMovedTurnedAndScaledMandelbulb) {
  const double factor = 1.5;
  const glm::dvec3 offset(0.3, -0.2, 0.1), axis = glm::normalize(glm::dvec3(1, 2, 3));
  const double angle = 40 * std::numbers::pi / 180;
  const sdf::Node placed = sdf::make(
      sdf::Op::translate, {{"offset", {offset.x, offset.y, offset.z}}},
      {sdf::make(sdf::Op::rotate, {{"axis", {axis.x, axis.y, axis.z}}, {"angle_deg", {40}}},
                 {sdf::make(sdf::Op::scale, {{"factor", {factor}}}, {bulb()})})});
  const Reference reference(placed, 0);
  const EscapeTimeSet set(bulb());
  const glm::dmat3 turn = sdf::rotation_matrix(axis, angle);
  std::mt19937 rng(4);
  std::normal_distribution<double> g;
  int hits = 0;
  for (int k = 0; k < 100; ++k) {
    const glm::dvec3 eye = offset + glm::dvec3(3, 1, 2);
    const glm::dvec3 d = glm::normalize(offset + glm::dvec3(g(rng), g(rng), g(rng)) * 0.4 - eye);
    const ReferenceHit world = reference.first_hit(eye, d, 10);
    // In the set's frame the ray is shorter by the scale: its t is the world's t over the factor.
    const glm::dvec3 o = glm::transpose(turn) * (eye - offset) / factor, dir = glm::transpose(turn) * d;
    const ReferenceHit local = set.first_hit(o, dir, 10 / factor);
    ASSERT_EQ(world.hit, local.hit);
    if (!world.hit) continue;
    ++hits;
    EXPECT_NEAR(world.t, local.t * factor, 1e-9);
    EXPECT_GT(glm::dot(world.normal, turn * local.normal), 1 - 1e-12);
  }
  EXPECT_GT(hits, 50);
}

}  // namespace
}  // namespace marchcheck::validation

namespace marchcheck::validation {
namespace {

// A Mandelbulb on a ground plane: each part cast by its own reference, the nearer first hit wins, and a start
// inside either part is inside the union.
TEST(EscapeTimeSet, JudgesAMandelbulbBesideExactShapes) {
  const sdf::Node ground = sdf::plane({0, 1, 0}, 1.0);  // y = -1
  // The ground listed first: rays that meet the bulb and then the ground tell the nearer hit from the first part's
  // (broken variant: a union answering with its first part that hits fails here).
  const Reference both(sdf::make(sdf::Op::union_, {}, {ground, bulb()}), 0);
  const Reference plane_only(ground, 0);
  const EscapeTimeSet set(bulb());
  std::mt19937 rng(6);
  std::normal_distribution<double> g;
  int on_bulb = 0, on_ground = 0;
  for (int k = 0; k < 100; ++k) {
    const dvec3 d = glm::normalize(dvec3(g(rng), g(rng) - 1, g(rng)) * 0.6 - kEye);
    const ReferenceHit union_hit = both.first_hit(kEye, d, 100), a = set.first_hit(kEye, d, 100),
                       b = plane_only.first_hit(kEye, d, 100);
    const bool bulb_first = a.hit && (!b.hit || a.t < b.t);
    ASSERT_EQ(union_hit.hit, a.hit || b.hit);
    if (!union_hit.hit) continue;
    // The bulb's part takes the direction through its own normalisation: equal up to rounding.
    EXPECT_NEAR(union_hit.t, bulb_first ? a.t : b.t, 1e-9);
    EXPECT_GT(glm::dot(union_hit.normal, bulb_first ? a.normal : b.normal), 1 - 1e-9);
    (bulb_first ? on_bulb : on_ground)++;
  }
  EXPECT_GT(on_bulb, 10);
  EXPECT_GT(on_ground, 10);
  EXPECT_TRUE(both.first_hit({0, -2, 0}, {0, 1, 0}, 10).inside);  // under the ground
  EXPECT_TRUE(both.first_hit({0, 0, 0}, {0, 1, 0}, 10).inside);   // in the bulb
}

}  // namespace
}  // namespace marchcheck::validation
