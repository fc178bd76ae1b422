// Each marcher's record on rays whose answer is known in closed form.
#include "marchcheck/march/marcher.hpp"
#include "marchcheck/march/render.hpp"
#include "marchcheck/sdf/node.hpp"
#include "marchcheck/sdf/tape.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace marchcheck::march {
namespace {

using V = glm::dvec3;

const sdf::Tape kUnitSphere = sdf::compile(sdf::sphere(1));
const TapeField kSphere{&kUnitSphere};

MarchSettings settings(Marcher m, int steps = 200, double eps = 1e-4) {
  MarchSettings s;
  s.marcher = m;
  s.max_steps = steps;
  s.hit_eps = eps;
  s.max_dist = 100;
  s.fixed_step = 0.01;
  return s;
}

// Ray from (0, b, -5) along +z: the closed-form hit is at t = 5 - sqrt(1 - b^2) when |b| < 1.
double closed_form_t(double b) { return 5 - std::sqrt(1 - b * b); }

class EveryMarcher : public ::testing::TestWithParam<Marcher> {};

TEST_P(EveryMarcher, HitsAtTheClosedFormDistanceWithinEps) {
  const double eps = 1e-4;
  for (double b : {0.0, 0.3, 0.7}) {
    const auto r = march<double>(kSphere, V(0, b, -5), V(0, 0, 1), settings(GetParam(), 2000, eps), {});
    ASSERT_EQ(r.outcome, Outcome::hit) << b;
    // The hit point is within eps of the surface; along the ray that is eps / cos(incidence) at most.
    const double cos_incidence = std::sqrt(1 - b * b);
    EXPECT_NEAR(r.t, closed_form_t(b), eps / cos_incidence + 1e-12) << b;
    EXPECT_EQ(r.evals, r.steps) << "every step is exactly one evaluation";
    EXPECT_LE(r.last_abs_f, eps);
  }
}

TEST_P(EveryMarcher, MissesFarAndRecordsTheClosestApproach) {
  const auto r = march<double>(kSphere, V(0, 1.5, -5), V(0, 0, 1), settings(GetParam(), 20000), {});
  EXPECT_EQ(r.outcome, Outcome::miss_far);
  EXPECT_GT(r.t, 100.0);
  // Closest approach of the ray to the sphere is 0.5 at z = 0 (t = 5). Samples lie at most half a step
  // (< 0.5 / 2 * relaxation) from it, where |f| = sqrt(1.5^2 + dt^2) - 1 exceeds 0.5 by at most 0.05.
  EXPECT_GE(r.min_abs_f, 0.5 - 1e-12);
  EXPECT_LE(r.min_abs_f, GetParam() == Marcher::fixed ? 0.5 + 1e-4 : 0.55);
  EXPECT_NEAR(r.t_at_min, 5.0, GetParam() == Marcher::fixed ? 0.01 : 1.0);  // samples are one step apart
}

TEST_P(EveryMarcher, StartsInside) {
  const auto r = march<double>(kSphere, V(0.1, 0.2, 0), V(0, 0, 1), settings(GetParam()), {});
  EXPECT_EQ(r.outcome, Outcome::inside);
  EXPECT_EQ(r.evals, 1);
}

TEST_P(EveryMarcher, NonFiniteOrZeroInputIsInvalidWithoutEvaluating) {
  const double nan = std::nan(""), inf = INFINITY;
  for (const auto& [o, d] : {std::pair{V(0, 0, -5), V(nan, 0, 1)}, std::pair{V(0, 0, -5), V(0, 0, 0)},
                             std::pair{V(inf, 0, -5), V(0, 0, 1)}, std::pair{V(0, nan, -5), V(0, 0, 1)}}) {
    const auto r = march<double>(kSphere, o, d, settings(GetParam()), {});
    EXPECT_EQ(r.outcome, Outcome::invalid);
    EXPECT_EQ(r.evals, 0);
  }
  MarchSettings bad = settings(GetParam());
  bad.hit_eps = std::nan("");
  EXPECT_EQ(march<double>(kSphere, V(0, 0, -5), V(0, 0, 1), bad, {}).outcome, Outcome::invalid);
  // A perturbation that cannot bound a step (a smooth part of L 0: steps of infinity; a negative band: steps past
  // f), where the marcher steps by it; ignored by the others. Broken variant: the check left out
  // (march-invalid-perturbation-accepted).
  MarchSettings perturbed = settings(GetParam());
  perturbed.step_bound = sdf::StepBound::perturbed;
  for (const sdf::Perturbation p : {sdf::Perturbation{0, 0.1}, sdf::Perturbation{1, -0.1}}) {
    MarchContext c;
    c.perturbation = p;
    const Outcome o = march<double>(kSphere, V(0, 0, -5), V(0, 0, 1), perturbed, c).outcome;
    EXPECT_EQ(o == Outcome::invalid, sdf::honours_lipschitz(GetParam())) << p.lipschitz << " " << p.width;
  }
}

TEST_P(EveryMarcher, ZeroStepsIsAnUndecidedMissWithNoWork) {
  const auto r = march<double>(kSphere, V(0, 0, -5), V(0, 0, 1), settings(GetParam(), 0), {});
  EXPECT_EQ(r.outcome, Outcome::miss_steps);
  EXPECT_EQ(r.evals, 0);
}

std::string marcher_name(const ::testing::TestParamInfo<Marcher>& p) {
  static const char* const names[] = {"sphere", "relaxed", "fixed", "scaled"};
  return names[static_cast<int>(p.param)];
}

INSTANTIATE_TEST_SUITE_P(All, EveryMarcher,
                         ::testing::Values(Marcher::sphere, Marcher::relaxed, Marcher::scaled, Marcher::fixed),
                         marcher_name);

TEST(SphereTracing, StepLimitIsExactNotOffByOne) {
  const auto full = march<double>(kSphere, V(0, 0.5, -5), V(0, 0, 1), settings(Marcher::sphere), {});
  ASSERT_EQ(full.outcome, Outcome::hit);
  const int needed = full.steps;
  EXPECT_EQ(march<double>(kSphere, V(0, 0.5, -5), V(0, 0, 1), settings(Marcher::sphere, needed), {}).outcome,
            Outcome::hit);
  const auto short_of_one = march<double>(kSphere, V(0, 0.5, -5), V(0, 0, 1), settings(Marcher::sphere, needed - 1), {});
  EXPECT_EQ(short_of_one.outcome, Outcome::miss_steps);
  EXPECT_EQ(short_of_one.evals, needed - 1);
}

TEST(SphereTracing, GrazingRaysFollowTheSquareRootLawAndNeverHitFalsely) {
  // A ray passing the unit sphere at clearance b needs about pi sqrt(2R / b) steps to get past it.
  for (double b : {1e-1, 1e-2, 1e-3, 1e-4}) {
    const auto r = march<double>(kSphere, V(0, 1 + b, -5), V(0, 0, 1), settings(Marcher::sphere, 100000, 1e-6), {});
    EXPECT_EQ(r.outcome, Outcome::miss_far) << b;
    const double law = std::numbers::pi * std::sqrt(2 / b);
    EXPECT_GT(r.steps, 0.5 * law) << b;
    EXPECT_LT(r.steps, 1.5 * law + 20) << b;  // + steps to leave the far side and reach max_dist
  }
  // With a seed-like 32-step limit, a ray at b = 1e-4 ends undecided: reported as such, not as hit or miss.
  const auto r = march<double>(kSphere, V(0, 1 + 1e-4, -5), V(0, 0, 1), settings(Marcher::sphere, 32, 1e-6), {});
  EXPECT_EQ(r.outcome, Outcome::miss_steps);
  EXPECT_FALSE(r.decided());
}

TEST(RelaxedTracing, SavesEvaluationsAndFallsBackSafely) {
  // A ray at 5 degrees to a plane: sphere tracing crawls, over-relaxation strides.
  const sdf::Tape plane = sdf::compile(sdf::plane({0, 1, 0}, 0));
  const TapeField field{&plane};
  const V dir = glm::normalize(V(std::cos(0.0873), -std::sin(0.0873), 0));
  const auto plain = march<double>(field, V(0, 1, 0), dir, settings(Marcher::sphere, 1000), {});
  const auto relaxed = march<double>(field, V(0, 1, 0), dir, settings(Marcher::relaxed, 1000), {});
  ASSERT_EQ(plain.outcome, Outcome::hit);
  ASSERT_EQ(relaxed.outcome, Outcome::hit);
  EXPECT_LT(relaxed.evals, plain.evals * 0.7);
  const double exact_t = 1 / std::sin(0.0873);
  EXPECT_NEAR(relaxed.t, exact_t, 1e-4 / std::sin(0.0873));
  // On a sphere hit head-on the relaxed step overshoots; the fallback must still end on the surface.
  const auto head_on = march<double>(kSphere, V(0, 0, -5), V(0, 0, 1), settings(Marcher::relaxed), {});
  EXPECT_EQ(head_on.outcome, Outcome::hit);
  EXPECT_NEAR(head_on.t, 4.0, 1e-4);
}

// clip=bounds on the unit sphere (its box [-1, 1]^3), every marcher: a ray that misses the box ends as a miss after
// no evaluation; one that crosses the box and misses the sphere ends where it leaves the box (within the span's
// widening), after fewer evaluations than the whole ray to max_dist 100; one that hits does so as the whole ray does
// (t within the hit threshold along the ray, 1e-4 / cos 0 here, plus the fixed marcher's step of 0.01). Broken variants: a
// missed box still marched (march-clip-miss-marched), the box's far side ignored (march-clip-exit-ignored).
TEST_P(EveryMarcher, ClippedToTheBoundsARayMarchesOnlyWhereItCrossesTheBox) {
  MarchSettings whole = settings(GetParam(), 2000);
  MarchSettings clipped = whole;
  clipped.clip = sdf::Clip::bounds;
  MarchContext c;
  c.clip_boxes[0] = {V(-1), V(1)};
  const auto outside = march<double>(kSphere, V(0, 1.5, -5), V(0, 0, 1), clipped, c);
  EXPECT_EQ(outside.outcome, Outcome::miss_far);
  EXPECT_EQ(outside.evals, 0);
  const V corner_origin(-5, 0.9, 0.9);  // 1.27 from the centre: inside the box's slab, outside the sphere
  const auto crossing = march<double>(kSphere, corner_origin, V(1, 0, 0), clipped, c);
  const auto crossing_whole = march<double>(kSphere, corner_origin, V(1, 0, 0), whole, c);
  EXPECT_EQ(crossing.outcome, Outcome::miss_far);
  // Leaves the box at t = 6 (widened by 1e-4 + 7e-5, and the fixed marcher's step): at most one step past that, of
  // f <= 0.62 there (|(1, 0.9, 0.9)| - 1).
  EXPECT_LT(crossing.t, 6 + 2e-4 + whole.fixed_step + 0.62);
  EXPECT_LT(crossing.evals, crossing_whole.evals);
  const auto hit = march<double>(kSphere, V(0, 0.3, -5), V(0, 0, 1), clipped, c);
  ASSERT_EQ(hit.outcome, Outcome::hit);
  EXPECT_NEAR(hit.t, closed_form_t(0.3), 1e-4 + whole.fixed_step);
}

// The relaxed marcher's first step toward a plane at 37 degrees (surface at t = 12.5 from f = 10) goes to t = 16,
// past max_dist 13; a plain step would reach 10, so the ray is not ended there but stepped back, and hits.
// Broken variant: a miss decided on the over-relaxed step (march-relaxed-miss-on-relaxed-step).
// clip=bounds on a sphere over a ground plane, y = -3: the boxes of the union's children (the sphere's, the half
// space below the plane) rather than their hull (everything below y = 1). A ray down at 45 degrees beside the sphere
// starts where it enters the ground's box, within the span's widening of the plane, and hits in at most 3
// evaluations (the relaxed marcher steps past and back; the fixed one steps once and bisects to 1e-4: 8), where
// from the hull's top (y = 1) it takes more; a ray through the sphere's box and on toward the
// ground hits the sphere as the whole ray does. Broken variants: the hull alone (sdf-bounding-boxes-hull), the
// span from the last box's entry (march-clip-boxes-last-entry: it starts past the sphere).
TEST_P(EveryMarcher, ClippedToTheBoxesOfAUnionsChildren) {
  const sdf::Node scene = sdf::unite({sdf::sphere(1), sdf::plane({0, 1, 0}, 3)});
  const sdf::Tape tape = sdf::compile(scene);
  const TapeField field{&tape};
  const std::vector<sdf::Box3> boxes = sdf::bounding_boxes(scene, 0, MarchContext::kMaxClipBoxes);
  ASSERT_EQ(boxes.size(), 2u);
  MarchContext c;
  c.clip_box_count = 2;
  std::copy(boxes.begin(), boxes.end(), c.clip_boxes.begin());
  MarchContext hull;
  hull.clip_boxes[0] = sdf::derive_info(scene).bounds;
  MarchSettings whole = settings(GetParam(), 2000);
  MarchSettings clipped = whole;
  clipped.clip = sdf::Clip::bounds;
  const V down = glm::normalize(V(0, -1, 1));
  const auto ground = march<double>(field, V(4, 2, -10), down, clipped, c);
  ASSERT_EQ(ground.outcome, Outcome::hit);
  EXPECT_NEAR(ground.t, 5 * std::sqrt(2.0), 2e-4 + whole.fixed_step);
  EXPECT_LE(ground.evals, GetParam() == Marcher::fixed ? 8 : 3);
  EXPECT_GT(march<double>(field, V(4, 2, -10), down, clipped, hull).evals, ground.evals);
  const V toward = glm::normalize(V(0, -0.2, 1));
  const auto sphere = march<double>(field, V(0, 0.5, -5), toward, clipped, c);
  const auto sphere_whole = march<double>(field, V(0, 0.5, -5), toward, whole, c);
  ASSERT_EQ(sphere_whole.outcome, Outcome::hit);
  ASSERT_LT(sphere_whole.t, 6);  // the sphere, not the ground
  EXPECT_EQ(sphere.outcome, Outcome::hit);
  EXPECT_NEAR(sphere.t, sphere_whole.t, 2e-4 + whole.fixed_step);
}

// The perturbed step bound on a plane displaced by 0.1 sin(60x) sin(60y) sin(60z) (L = 7, a smooth part of L 1 and a
// band 0.2 wide), rays straight down from y = 10 onto it: the scaled and relaxed marchers stepping by max(f / 7,
// f - 0.2) hit where stepping by f / 7 does (within the hit threshold along the ray, both), with at least 5
// evaluations fewer a ray: the crawl from y = 10 to the bumps at f / 7 (about 23 steps of 1 - 1/7, 13 relaxed of
// 1 - 1.6/7) becomes one or two steps; near the bumps both step by f / 7. The check can fail: a band understated as 0 (steps of f on a field of slope 7) passes the surface on
// some rays. Broken variant: the perturbed term dropped (march-perturbed-step-dropped: as many evaluations as f / 7).
TEST(PerturbedBound, StepsFarFromADisplacedSurfaceAndHitsWhereTheLipschitzBoundDoes) {
  const sdf::Node bumpy = sdf::make(sdf::Op::displace, {{"amplitude", {0.1}}, {"frequency", {60}}}, {sdf::plane({0, 1, 0}, 0)});
  const sdf::Tape tape = sdf::compile(bumpy);
  const TapeField field{&tape};
  const sdf::FieldInfo info = sdf::derive_info(bumpy);
  ASSERT_NEAR(info.lipschitz, 7, 1e-12);
  MarchContext c;
  c.lipschitz = info.lipschitz;
  c.perturbation = info.perturbation_or_plain();
  ASSERT_NEAR(c.perturbation.width, 0.2, 1e-12);
  MarchContext understated = c;
  understated.perturbation.width = 0;
  for (const Marcher m : {Marcher::scaled, Marcher::relaxed}) {
    SCOPED_TRACE(m == Marcher::scaled ? "scaled" : "relaxed");
    MarchSettings lipschitz = settings(m, 5000, 1e-4), perturbed = lipschitz;
    perturbed.step_bound = sdf::StepBound::perturbed;
    int lipschitz_evals = 0, perturbed_evals = 0, passed = 0;
    for (int i = 0; i < 100; ++i) {
      const V origin(0.0137 * i, 10, 0.0291 * i + 0.005);
      const auto plain = march<double>(field, origin, V(0, -1, 0), lipschitz, c);
      const auto fast = march<double>(field, origin, V(0, -1, 0), perturbed, c);
      ASSERT_EQ(plain.outcome, Outcome::hit) << i;
      ASSERT_EQ(fast.outcome, Outcome::hit) << i;
      EXPECT_NEAR(fast.t, plain.t, 2e-4) << i;  // each within 1e-4 / (1 - 0.6) of the surface at worst
      lipschitz_evals += plain.evals;
      perturbed_evals += fast.evals;
      passed += std::abs(march<double>(field, origin, V(0, -1, 0), perturbed, understated).t - plain.t) > 0.01;
    }
    EXPECT_LT(perturbed_evals, lipschitz_evals - 5 * 100);
    EXPECT_GT(passed, 0) << "an understated band steps through the bumps";
  }
}

// StepRule's arithmetic on a field of L 7 with a smooth part of L 1 and a band 0.2 wide (the displaced plane
// above), relaxed at 1.6: far from the surface a step is omega (f - 0.2), near it omega f / 7, whichever is longer;
// two unbounding spheres each lose the band (3 + 4 - 2 * 0.2), and without the perturbed bound the band is
// infinite and the rule is f / 7's alone. Broken variants: the spheres' sum losing the band once
// (march-perturbed-radii-once), the perturbed term dropped (march-perturbed-step-dropped).
TEST(PerturbedBound, AStepIsTheLongerOfTheTwoBoundsAndEachSphereLosesTheBand) {
  MarchContext c;
  c.lipschitz = 7;
  c.perturbation = {1, 0.2};
  MarchSettings s = settings(Marcher::relaxed);
  s.step_bound = sdf::StepBound::perturbed;
  const StepRule<double> rule(s, c);
  EXPECT_DOUBLE_EQ(rule.step(10, 1.6), 1.6 * 9.8);
  EXPECT_DOUBLE_EQ(rule.step(0.1, 1), 0.1 / 7);
  EXPECT_DOUBLE_EQ(rule.radii(3, 4), 6.6);
  EXPECT_DOUBLE_EQ(rule.radii(0.1, 0.1), 0.2 / 7);
  s.step_bound = sdf::StepBound::lipschitz;
  const StepRule<double> plain(s, c);
  EXPECT_EQ(plain.step(10, 1.6), 10 * 1.6 * (1 / 7.0));
  EXPECT_EQ(plain.radii(3, 4), 7 * (1 / 7.0));
}

TEST(RelaxedTracing, AnOverRelaxedStepPastMaxDistIsSteppedBackNotAMiss) {
  const sdf::Tape plane = sdf::compile(sdf::plane({0, 1, 0}, 0));
  const TapeField field{&plane};
  MarchSettings s = settings(Marcher::relaxed);
  s.max_dist = 13;
  const auto r = march<double>(field, V(0, 10, 0), V(0.6, -0.8, 0), s, {});
  ASSERT_EQ(r.outcome, Outcome::hit);
  EXPECT_NEAR(r.t, 12.5, 1e-4 / 0.8);
}


// The secant refinement: on a plane at 5 degrees the march stops up to eps / sin(5 deg) = 0.11 short at eps 0.01;
// the secant through the last two samples is exact on a plane (f is linear along the ray) up to rounding, and
// its one extra evaluation is counted. On a sphere the line's root is O(eps^2) off: within 1e-4 here. A ray
// passing the sphere 0.0095 above it stops where f = 0.0099 (t = 4.9716) and keeps that point: f turns back up
// before the line's root, where |f| is larger (measured).
// Broken variants: the root taken without its evaluation (march-secant-unchecked), the refinement ignored
// (march-secant-ignored).
TEST(SecantRefinement, LandsOnThePlaneAndTheSphereAndKeepsAPassingRayWhereItStopped) {
  const sdf::Tape plane = sdf::compile(sdf::plane({0, 1, 0}, 0));
  const TapeField field{&plane};
  const double angle = 5 * std::numbers::pi / 180;
  const V dir = glm::normalize(V(std::cos(angle), -std::sin(angle), 0));
  for (Marcher m : {Marcher::sphere, Marcher::relaxed}) {
    MarchSettings s = settings(m, 1000, 0.01);
    const auto stopped = march<double>(field, V(0, 1, 0), dir, s, {});
    s.refine = sdf::HitRefine::secant;
    const auto refined = march<double>(field, V(0, 1, 0), dir, s, {});
    ASSERT_EQ(refined.outcome, Outcome::hit);
    const double exact = 1 / std::sin(angle);
    EXPECT_GT(std::abs(stopped.t - exact), 0.01);
    EXPECT_NEAR(refined.t, exact, 1e-12);
    EXPECT_EQ(refined.evals, stopped.evals + 1);
  }
  MarchSettings s = settings(Marcher::sphere, 1000, 0.01);
  s.refine = sdf::HitRefine::secant;
  const auto oblique = march<double>(kSphere, V(0, 0.6, -5), V(0, 0, 1), s, {});
  ASSERT_EQ(oblique.outcome, Outcome::hit);
  EXPECT_NEAR(oblique.t, closed_form_t(0.6), 1e-4);
  const auto passing = march<double>(kSphere, V(0, 1.0095, -5), V(0, 0, 1), s, {});
  s.refine = sdf::HitRefine::none;
  const auto unrefined = march<double>(kSphere, V(0, 1.0095, -5), V(0, 0, 1), s, {});
  ASSERT_EQ(passing.outcome, Outcome::hit);
  EXPECT_EQ(passing.t, unrefined.t);
  EXPECT_EQ(passing.evals, unrefined.evals + 1);
}

TEST(ScaledTracing, StepsSafelyThroughAFieldWithLipschitzAboveOne) {
  // A sphere evaluated at diag(4, 1, 1) p: an ellipsoid-like field with slope 4 along x.
  const sdf::Node squashed =
      sdf::make(sdf::Op::affine, {{"model", {0.25, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}}}, {sdf::sphere(1)});
  const sdf::Tape tape = sdf::compile(squashed);
  const TapeField field{&tape};
  const double lipschitz = sdf::derive_info(squashed).lipschitz;
  ASSERT_NEAR(lipschitz, 4.0, 1e-9);
  // Along +x through the thin axis: the surface is at x = -0.25.
  const V origin(-3, 0, 0), dir(1, 0, 0);
  MarchSettings s = settings(Marcher::sphere, 1000, 1e-4);
  const auto plain = march<double>(field, origin, dir, s, {});
  s.marcher = Marcher::scaled;
  const auto scaled = march<double>(field, origin, dir, s, {lipschitz, 0, 0});
  ASSERT_EQ(scaled.outcome, Outcome::hit);
  EXPECT_NEAR(scaled.t, 2.75, 1e-4);
  // Plain sphere tracing steps by f = 4 x distance: it lands inside, far past the surface.
  EXPECT_GT(std::abs(plain.t - 2.75), 0.1);
}

// The relaxed marcher on a field of declared L = 4 (the squashed sphere above, surface at t = 2.75 from f = 11):
// its first step, 1.6 * 11 / 4 = 4.4, passes the surface to x = 1.4 (f = 4.6 beyond it); the unbounding spheres,
// of radius f / L (11 / 4 and 4.6 / 4), do not reach each other, so it steps back to 11 / 4 and hits exactly there.
// Broken variants: L ignored, the seed's steps of 1.6 f (march-relaxed-ignores-lipschitz: steps to x = 14.6 and
// misses), spheres of radius f (march-relaxed-radius-unscaled: they overlap, so it marches on from x = 1.4, past
// the surface, and misses).
TEST(RelaxedTracing, StepsByTheDeclaredLipschitzBoundAndStepsBackByIt) {
  const sdf::Node squashed =
      sdf::make(sdf::Op::affine, {{"model", {0.25, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}}}, {sdf::sphere(1)});
  const sdf::Tape tape = sdf::compile(squashed);
  const TapeField field{&tape};
  const MarchContext c{sdf::derive_info(squashed).lipschitz, 0, 0};
  ASSERT_NEAR(c.lipschitz, 4.0, 1e-9);
  const auto r = march<double>(field, V(-3, 0, 0), V(1, 0, 0), settings(Marcher::relaxed, 1000, 1e-4), c);
  ASSERT_EQ(r.outcome, Outcome::hit);
  EXPECT_NEAR(r.t, 2.75, 1e-12);
  EXPECT_EQ(r.evals, 3);  // x = -3, 1.4, then -0.25
}

TEST(FixedStep, BisectsTheCrossingToEps) {
  MarchSettings s = settings(Marcher::fixed, 10000, 1e-9);
  s.fixed_step = 0.3;
  const auto r = march<double>(kSphere, V(0, 0.2, -5), V(0, 0, 1), s, {});
  ASSERT_EQ(r.outcome, Outcome::hit);
  EXPECT_NEAR(r.t, closed_form_t(0.2), 1e-8);
}

TEST(EpsModes, RelativeAndPixelThresholdsGrowWithDistance) {
  MarchSettings s = settings(Marcher::sphere);
  s.eps_mode = EpsMode::relative;
  s.hit_eps = 1e-3;
  EXPECT_DOUBLE_EQ(hit_threshold<double>(s, {}, 50.0), 0.05);
  s.eps_mode = EpsMode::pixel;
  EXPECT_DOUBLE_EQ(hit_threshold<double>(s, {1, 0.001, 0.002}, 50.0), 0.101);
}

TEST(FloatMarch, AgreesWithDoubleWithinFloatPrecision) {
  const auto d = march<double>(kSphere, V(0, 0.3, -5), V(0, 0, 1), settings(Marcher::sphere, 200, 1e-3), {});
  const auto f = march<float>(kSphere, glm::vec3(0, 0.3f, -5), glm::vec3(0, 0, 1), settings(Marcher::sphere, 200, 1e-3), {});
  ASSERT_EQ(f.outcome, Outcome::hit);
  // Both stop within eps of the surface: they differ by at most 2 eps / cos(incidence).
  EXPECT_NEAR(static_cast<double>(f.t), d.t, 2e-3 / std::sqrt(1 - 0.09));
}

}  // namespace
}  // namespace marchcheck::march
