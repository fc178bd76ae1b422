// The references themselves: exact CSG casting against closed forms, the numerical root finder against both.
#include "marchcheck/validation/reference.hpp"

#include "marchcheck/march/tolerances.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace marchcheck::validation {
namespace {

using glm::dvec3;

TEST(ExactCaster, PrimitivesMatchTheirClosedForms) {
  // Sphere r = 2 from z = -5: in at 3, out at 7.
  auto s = cast_exact(sdf::sphere(2), {0, 0, -5}, {0, 0, 1});
  ASSERT_EQ(s.size(), 1u);
  EXPECT_DOUBLE_EQ(s[0].t0, 3);
  EXPECT_DOUBLE_EQ(s[0].t1, 7);
  EXPECT_EQ(s[0].n0, dvec3(0, 0, -1));
  // Box half-size (1, 2, 3) along +x from x = -4, at y = 1.5 (inside the y slab).
  s = cast_exact(sdf::box({1, 2, 3}), {-4, 1.5, 0}, {1, 0, 0});
  ASSERT_EQ(s.size(), 1u);
  EXPECT_DOUBLE_EQ(s[0].t0, 3);
  EXPECT_DOUBLE_EQ(s[0].t1, 5);
  // Torus (1, 0.25) along x through its centre plane: two tubes, [-1.25, -0.75] and [0.75, 1.25].
  s = cast_exact(sdf::torus(1, 0.25), {-3, 0, 0}, {1, 0, 0});
  ASSERT_EQ(s.size(), 2u);
  EXPECT_NEAR(s[0].t0, 1.75, 1e-12);
  EXPECT_NEAR(s[0].t1, 2.25, 1e-12);
  EXPECT_NEAR(s[1].t0, 3.75, 1e-12);
  EXPECT_NEAR(s[1].t1, 4.25, 1e-12);
  EXPECT_NEAR(glm::length(s[1].n0 - dvec3(-1, 0, 0)), 0, 1e-9);
}

TEST(ExactCaster, CsgCombinesIntervalLists) {
  const sdf::Node a = sdf::translate({-0.5, 0, 0}, sdf::box(dvec3(1))), b = sdf::translate({0.5, 0, 0}, sdf::box(dvec3(1)));
  const dvec3 o(-5, 0.2, 0.3), d(1, 0, 0);
  auto u = cast_exact(sdf::unite({a, b}), o, d);
  ASSERT_EQ(u.size(), 1u);
  EXPECT_DOUBLE_EQ(u[0].t0, 3.5);
  EXPECT_DOUBLE_EQ(u[0].t1, 6.5);
  auto i = cast_exact(sdf::intersect(a, b), o, d);
  ASSERT_EQ(i.size(), 1u);
  EXPECT_DOUBLE_EQ(i[0].t0, 4.5);
  EXPECT_DOUBLE_EQ(i[0].t1, 5.5);
  auto m = cast_exact(sdf::subtract(a, b), o, d);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_DOUBLE_EQ(m[0].t1, 4.5);
  EXPECT_EQ(m[0].n1, dvec3(1, 0, 0)) << "the cut face of a minus b faces out of a, into b";
}

TEST(ExactCaster, KnowsWhichTreesItCanCast) {
  EXPECT_TRUE(exact_supported(sdf::unite({sdf::sphere(1), sdf::translate({1, 0, 0}, sdf::box(dvec3(1)))})));
  EXPECT_FALSE(exact_supported(sdf::smooth_union(0.2, {sdf::sphere(1), sdf::box(dvec3(1))})));
  EXPECT_FALSE(exact_supported(sdf::make(sdf::Op::affine, {{"model", {2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}}}, {sdf::sphere(1)})));
}

// The reference is the judge: on a field four times steeper than the distance (a slab squashed to a quarter of
// its thickness, 0.05 across), steps of f / L land on the slab; steps of f (the broken variant) jump it.
TEST(NumericalReference, StepsByFOverLAcrossAThinFeatureOfASteepField) {
  const sdf::Node slab = sdf::make(sdf::Op::affine, {{"model", {1, 0, 0, 0, 0, 0.25, 0, 0, 0, 0, 1, 0}}},
                                   {sdf::box({2, 0.1, 2})});
  ASSERT_NEAR(sdf::derive_info(slab, 0).lipschitz, 4, 1e-12);
  const Reference ref(slab, 0);
  ASSERT_FALSE(ref.exact());
  const ReferenceHit h = ref.numerical_first_hit({0.3, -1, 0.2}, {0, 1, 0}, 10);
  EXPECT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 0.975, 10 * march::tolerance::kReferenceBisection);  // the slab's near face, y = -0.025
}

TEST(NumericalReference, AgreesWithTheExactOneToItsStatedBound) {
  // The same torus through a node the exact caster does not take (a smooth union with a far-away sphere).
  const sdf::Node torus = sdf::torus(1, 0.25);
  const sdf::Node wrapped = sdf::smooth_union(1e-6, {torus, sdf::translate({100, 0, 0}, sdf::sphere(0.1))});
  const Reference exact(torus, 0), numerical(wrapped, 0);
  ASSERT_TRUE(exact.exact());
  ASSERT_FALSE(numerical.exact());
  for (const dvec3 dir : {glm::normalize(dvec3(1, -0.1, 0.05)), glm::normalize(dvec3(0.3, -1, 0.2))}) {
    const dvec3 o = dvec3(-3, 1, 0.1) - dir * 0.0;
    const auto a = exact.first_hit(o, dir, 100), b = numerical.first_hit(o, dir, 100);
    ASSERT_EQ(a.hit, b.hit);
    if (a.hit) {
      EXPECT_NEAR(a.t, b.t, 2 * numerical.t_error_bound(a.t));
      EXPECT_NEAR(glm::length(a.normal - b.normal), 0, 1e-6);
    }
  }
}

}  // namespace
}  // namespace marchcheck::validation
