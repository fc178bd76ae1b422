// Each operator's derived kind and Lipschitz bound, checked by measurement.
#include "zero_set.hpp"

#include "marchcheck/sdf/node.hpp"
#include "marchcheck/sdf/tape.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace marchcheck::sdf {
namespace {

using testing::Inside;
using testing::ZeroSet;

constexpr double kGrid = 0.01;
constexpr double kRounding = 1e-9;

testing::KindMeasurement measure(const Node& node, const Inside& inside, double margin = 0.4) {
  const FieldInfo info = derive_info(node);
  const ZeroSet zs(inside, info.bounds.lo - 0.05, info.bounds.hi + 0.05, kGrid);
  return testing::measure_kind(compile(node), zs, inside, info.bounds.lo - margin, info.bounds.hi + margin, 400);
}

double lipschitz_of(const Node& node, glm::dvec3 lo, glm::dvec3 hi, double time = 0) {
  const Tape tape = compile(node, time);
  return testing::measure_lipschitz([&](glm::dvec3 p) { return sdf::evaluate(tape, p); }, lo, hi, 200000);
}

bool in_ball(glm::dvec3 p, glm::dvec3 c, double r) { return glm::dot(p - c, p - c) < r * r; }

const Node kA = translate({-0.3, 0, 0}, sphere(0.6));
const Node kB = translate({0.4, 0.1, 0}, sphere(0.5));
const Inside kInA = [](glm::dvec3 p) { return in_ball(p, {-0.3, 0, 0}, 0.6); };
const Inside kInB = [](glm::dvec3 p) { return in_ball(p, {0.4, 0.1, 0}, 0.5); };

TEST(Csg, UnionOfExactFieldsIsABoundAndNotExact) {
  const Node u = unite({kA, kB});
  EXPECT_EQ(derive_info(u).kind, Kind::bound);
  const auto m = measure(u, [](glm::dvec3 p) { return kInA(p) || kInB(p); });
  EXPECT_EQ(m.sign_errors, 0);
  EXPECT_LE(m.max_over, kRounding);
  // Inside the overlap min() understates the distance: declaring it exact would be wrong.
  EXPECT_GT(m.max_under, ZeroSet::sampling_error(kGrid));
}

TEST(Csg, IntersectionAndSubtractionAreBounds) {
  const Node i = intersect(kA, kB);
  const Node s = subtract(kA, kB);
  EXPECT_EQ(derive_info(i).kind, Kind::bound);
  EXPECT_EQ(derive_info(s).kind, Kind::bound);
  const auto mi = measure(i, [](glm::dvec3 p) { return kInA(p) && kInB(p); });
  const auto ms = measure(s, [](glm::dvec3 p) { return kInA(p) && !kInB(p); });
  EXPECT_EQ(mi.sign_errors + ms.sign_errors, 0);
  EXPECT_LE(mi.max_over, kRounding);
  EXPECT_LE(ms.max_over, kRounding);
  EXPECT_GT(ms.max_under, ZeroSet::sampling_error(kGrid));
}

TEST(Csg, TheSeedsBrokenIntersectionIsCaught) {
  // crum's intersection returns max(d2, d2): it ignores the first shape, so it overestimates inside b \ a.
  const Node broken = intersect(kB, kB);
  const auto m = measure(broken, [](glm::dvec3 p) { return kInA(p) && kInB(p); });
  EXPECT_GT(m.sign_errors, 0);
}

TEST(SmoothCsg, SmoothOperatorsStayOneLipschitzBounds) {
  for (const Node& n : {smooth_union(0.3, {kA, kB}), make(Op::smooth_intersection, {{"k", {0.3}}}, {kA, kB}),
                        make(Op::smooth_subtraction, {{"k", {0.3}}}, {kA, kB})}) {
    SCOPED_TRACE(op_info(n.op).name);
    const FieldInfo info = derive_info(n);
    EXPECT_EQ(info.kind, Kind::bound);
    EXPECT_EQ(info.lipschitz, 1.0);
    // A 1-Lipschitz field that vanishes on its zero set never exceeds the distance to it.
    EXPECT_LE(lipschitz_of(n, {-1.5, -1, -1}, {1.5, 1, 1}), 1.0 + 1e-6);
  }
}

TEST(SmoothCsg, SmoothUnionAddsMaterialBetweenTheShapes) {
  const Tape hard = compile(unite({kA, kB})), smooth = compile(smooth_union(0.3, {kA, kB}));
  const glm::dvec3 crease(0.1, 0.5, 0);
  EXPECT_LT(sdf::evaluate(smooth, crease), sdf::evaluate(hard, crease) - 0.01);
  // Far from both the blend vanishes: |a - b| > k.
  const glm::dvec3 far(-2, 0, 0);
  EXPECT_EQ(sdf::evaluate(smooth, far), sdf::evaluate(hard, far));
}

TEST(Modifiers, RoundAndOnionAreBounds) {
  const Node rounded = make(Op::round, {{"radius", {0.1}}}, {box({0.5, 0.4, 0.3})});
  EXPECT_EQ(derive_info(rounded).kind, Kind::bound);
  const auto mr = measure(rounded, [](glm::dvec3 p) {
    const glm::dvec3 b(0.5, 0.4, 0.3);
    return glm::length(p - glm::clamp(p, -b, b)) < 0.1;
  });
  EXPECT_EQ(mr.sign_errors, 0);
  EXPECT_LE(mr.max_over, kRounding);

  const Node shell = make(Op::onion, {{"thickness", {0.05}}}, {sphere(0.6)});
  EXPECT_EQ(derive_info(shell).kind, Kind::bound);
  const auto mo = measure(shell, [](glm::dvec3 p) { return std::abs(glm::length(p) - 0.6) < 0.05; });
  EXPECT_EQ(mo.sign_errors, 0);
  EXPECT_LE(mo.max_over, kRounding);
}

TEST(Domain, RigidMotionsAndUniformScaleKeepExactness) {
  const Inside in_box = [](glm::dvec3 p) { return std::abs(p.x) < 0.5 && std::abs(p.y) < 0.3 && std::abs(p.z) < 0.2; };
  const glm::dvec3 axis = glm::normalize(glm::dvec3(1, 2, 0.5));
  const double angle = 37.0;
  const glm::dmat3 r = rotation_matrix(axis, angle * std::numbers::pi / 180);
  const Node rotated = translate({0.2, -0.1, 0.3}, make(Op::rotate, {{"axis", {axis.x, axis.y, axis.z}}, {"angle_deg", {angle}}},
                                                        {box({0.5, 0.3, 0.2})}));
  EXPECT_EQ(derive_info(rotated).kind, Kind::exact);
  const auto m = measure(rotated, [&](glm::dvec3 p) { return in_box(glm::transpose(r) * (p - glm::dvec3(0.2, -0.1, 0.3))); });
  EXPECT_EQ(m.sign_errors, 0);
  EXPECT_LE(m.max_over, kRounding);
  EXPECT_LE(m.max_under, ZeroSet::sampling_error(kGrid));

  const Node scaled = make(Op::scale, {{"factor", {1.7}}}, {box({0.5, 0.3, 0.2})});
  EXPECT_EQ(derive_info(scaled).kind, Kind::exact);
  const auto ms = measure(scaled, [&](glm::dvec3 p) { return in_box(p / 1.7); });
  EXPECT_LE(ms.max_over, kRounding);
  EXPECT_LE(ms.max_under, ZeroSet::sampling_error(kGrid));
}

TEST(Domain, AffineMapsDeclareTheirStretch) {
  // model = diag(0.5, 1, 1): the field is evaluated at diag(2, 1, 1) p, which doubles slopes along x.
  const Node squash = make(Op::affine, {{"model", {0.5, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}}}, {sphere(0.5)});
  const FieldInfo si = derive_info(squash);
  EXPECT_EQ(si.kind, Kind::lipschitz);
  EXPECT_NEAR(si.lipschitz, 2.0, 1e-9);
  const double measured = lipschitz_of(squash, {-1, -1, -1}, {1, 1, 1});
  EXPECT_LE(measured, si.lipschitz + 1e-6);
  EXPECT_GT(measured, 1.9);
  // model = diag(2, 1, 1) only shrinks distances: a bound.
  const Node stretch = make(Op::affine, {{"model", {2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}}}, {sphere(0.5)});
  EXPECT_EQ(derive_info(stretch).kind, Kind::bound);
  EXPECT_LE(lipschitz_of(stretch, {-2, -1, -1}, {2, 1, 1}), 1.0 + 1e-6);
  // The animated model matrix is rigid: the torus stays exact.
  const Node spin = make(Op::animate, {{"translate_sin", {5, 0, 0}}, {"spin_axis", {0, 0, 1}}, {"spin_deg_per_s", {200}}},
                         {torus(1, 0.2)});
  EXPECT_EQ(derive_info(spin, 1.0).kind, Kind::exact);
}

TEST(Domain, RepetitionDeclaresWhetherTheShapeCrossesItsCell) {
  const Node inside_cell = make(Op::repeat, {{"period", {2, 2, 2}}}, {sphere(0.5)});
  EXPECT_EQ(derive_info(inside_cell).kind, Kind::bound);
  EXPECT_LE(lipschitz_of(inside_cell, {-3, -3, -3}, {3, 3, 3}), 1.0 + 1e-6);
  const Node crossing = make(Op::repeat, {{"period", {2, 2, 2}}}, {translate({0.8, 0, 0}, sphere(0.5))});
  EXPECT_EQ(derive_info(crossing).kind, Kind::lipschitz);
  // Inside its cell but off centre, the copy in the next cell can be the nearer: at x = -0.95 the own copy
  // (centred at 0.3) is 0.75 away, the neighbour's (centred at -1.7) 0.25, so f = 0.75 overestimates the
  // distance. It was declared a bound.
  const Node off_centre = make(Op::repeat, {{"period", {2, 2, 2}}}, {translate({0.3, 0, 0}, sphere(0.5))});
  EXPECT_EQ(derive_info(off_centre).kind, Kind::lipschitz);
  EXPECT_NEAR(sdf::evaluate(compile(off_centre), glm::dvec3(-0.95, 0, 0)), 0.75, 1e-12) << "the own copy's distance";
  // The field jumps at cell faces: finite differences across a face see a slope far above 1.
  EXPECT_GT(lipschitz_of(crossing, {-3, -3, -3}, {3, 3, 3}), 10.0);
  const Node limited = make(Op::repeat_limited, {{"period", {2, 0, 0}}, {"count", {2, 0, 0}}}, {sphere(0.5)});
  const FieldInfo li = derive_info(limited);
  EXPECT_NEAR(li.bounds.hi.x, 4.5, 1e-12);
  const Tape t = compile(limited);
  EXPECT_NEAR(sdf::evaluate(t, glm::dvec3(4, 0, 0)), -0.5, 1e-12) << "centre of the last copy";
  EXPECT_NEAR(sdf::evaluate(t, glm::dvec3(8, 0, 0)), 3.5, 1e-12) << "no copies beyond count";
}

TEST(Domain, MirrorOfAShapeInTheKeptHalfIsExact) {
  const Node m = make(Op::mirror, {{"axes", {1, 0, 0}}}, {translate({0.6, 0, 0}, sphere(0.4))});
  EXPECT_EQ(derive_info(m).kind, Kind::exact);
  const auto r = measure(m, [](glm::dvec3 p) { return in_ball(p, {0.6, 0, 0}, 0.4) || in_ball(p, {-0.6, 0, 0}, 0.4); });
  EXPECT_EQ(r.sign_errors, 0);
  EXPECT_LE(r.max_over, kRounding);
  EXPECT_LE(r.max_under, ZeroSet::sampling_error(kGrid));
  const Node crossing = make(Op::mirror, {{"axes", {1, 0, 0}}}, {translate({0.2, 0, 0}, sphere(0.4))});
  EXPECT_EQ(derive_info(crossing).kind, Kind::bound);
}

TEST(Deformations, DeclaredLipschitzBoundsHoldAndAreTight) {
  struct Case {
    const char* name;
    Node node;
    double time;
  };
  const Case cases[] = {
      {"displace", make(Op::displace, {{"amplitude", {0.1}}, {"frequency", {15}}}, {sphere(0.8)}), 0},
      {"twist", make(Op::twist, {{"rate", {2}}}, {box({0.5, 0.8, 0.3})}), 0},
      {"warp", make(Op::warp, {}, {sphere(2)}), 1.0},
      // Broken variants: a rule that adds the signed amplitude or rate (a negative one lowers the bound).
      {"displace, negative amplitude", make(Op::displace, {{"amplitude", {-0.1}}, {"frequency", {15}}}, {sphere(0.8)}), 0},
      {"twist, negative rate", make(Op::twist, {{"rate", {-2}}}, {box({0.5, 0.8, 0.3})}), 0},
      // A child reaching further in z than in x. Broken variant: the bounding radius taken from x alone.
      {"twist, deep in z", make(Op::twist, {{"rate", {2}}}, {box({0.2, 0.8, 0.9})}), 0},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const FieldInfo info = derive_info(c.node, c.time);
    EXPECT_EQ(info.kind, Kind::lipschitz);
    const glm::dvec3 lo = glm::max(info.bounds.lo, glm::dvec3(-3)), hi = glm::min(info.bounds.hi, glm::dvec3(3));
    const double measured = lipschitz_of(c.node, lo, hi, c.time);
    EXPECT_LE(measured, info.lipschitz * (1 + 1e-6));
    EXPECT_GT(measured, 1.2) << "these deformations are steeper than 1 somewhere";
    EXPECT_GT(measured, 0.5 * info.lipschitz) << "the declared bound should not be wildly loose";
  }
  // The seed's numbers: displacement 0.1 sin(15x)... adds 1.5; the warp at t = 1 reaches 1 + 3.49.
  EXPECT_NEAR(derive_info(cases[0].node).lipschitz, 2.5, 1e-12);
  EXPECT_NEAR(derive_info(cases[2].node, 1.0).lipschitz, 1 + 20 * std::abs(std::sin(2.0)) * 0.2 * std::abs(std::sin(5.0)), 1e-12);
}

// The band a field needs beside its smooth part's Lipschitz bound: the largest |f(q) - f(p)| - lipschitz |q - p|
// over random pairs in [lo, hi], q a random direction from p at distances from 1e-3 to 3.
double measured_band(const Node& node, double lipschitz, glm::dvec3 lo, glm::dvec3 hi) {
  const Tape tape = compile(node);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> g;
  double band = -INFINITY;
  for (int i = 0; i < 200000; ++i) {
    const glm::dvec3 p = lo + (hi - lo) * glm::dvec3(u(rng), u(rng), u(rng));
    const glm::dvec3 q = p + glm::normalize(glm::dvec3(g(rng), g(rng), g(rng))) * (1e-3 * std::pow(3e3, u(rng)));
    band = std::max(band, std::abs(evaluate(tape, q) - evaluate(tape, p)) - lipschitz * glm::length(q - p));
  }
  return band;
}

// A declared perturbation (a smooth part's Lipschitz bound and a band) holds by measurement and is not loose where the
// perturbation is steep: pairs find at least half the band. Broken variants: a height field's band summing signed
// amplitudes (sdf-heightfield-band-signed), a displacement adding its amplitude once (sdf-displace-band-once), a
// union keeping the narrowest band (sdf-union-band-narrowest), a scale that keeps the band
// (sdf-scale-band-unscaled), a stretch that keeps the smooth part's bound (sdf-affine-perturbation-unstretched).
TEST(Perturbation, DeclaredBandsHoldAndAreTightWhereTheFieldIsSteep) {
  const Node steep_terrain = make(Op::heightfield, {{"octaves", {0.3, 20, -0.1, 7}}});
  const auto displaced = [](double a, double f, Node child) {
    return make(Op::displace, {{"amplitude", {a}}, {"frequency", {f}}}, {std::move(child)});
  };
  struct Case {
    const char* name;
    Node node;
    Perturbation declared;
  };
  const Case cases[] = {
      {"steep height field", steep_terrain, {1, 0.4}},
      {"steep displacement", displaced(0.1, 60, sphere(0.8)), {1, 0.2}},
      {"displaced height field", displaced(0.05, 40, steep_terrain), {1, 0.5}},
      {"union with a sphere", unite({sphere(0.5), translate({0, -1, 0}, displaced(0.1, 60, sphere(0.8)))}), {1, 0.2}},
      {"scaled by 2", make(Op::scale, {{"factor", {2}}}, {displaced(0.1, 60, sphere(0.8))}), {1, 0.4}},
      {"squashed in x", make(Op::affine, {{"model", {0.5, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}}}, {displaced(0.1, 60, sphere(0.8))}),
       {2, 0.2}},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const FieldInfo info = derive_info(c.node);
    ASSERT_TRUE(info.perturbation.has_value());
    EXPECT_NEAR(info.perturbation->lipschitz, c.declared.lipschitz, 1e-12);
    EXPECT_NEAR(info.perturbation->width, c.declared.width, 1e-12);
    const double band = measured_band(c.node, info.perturbation->lipschitz, glm::dvec3(-2), glm::dvec3(2));
    EXPECT_LE(band, info.perturbation->width + 1e-12);
    EXPECT_GT(band, 0.5 * info.perturbation->width);
  }
}

// Fields without a perturbation declare none: exact shapes and their unions, and a repetition, whose copy in the
// next cell is no perturbation of the own one. Broken variant: repetition keeping its child's band
// (sdf-repeat-keeps-perturbation).
TEST(Perturbation, DeclaredOnlyWhereThereIsOne) {
  EXPECT_FALSE(derive_info(unite({kA, kB})).perturbation.has_value());
  const Node displaced_box = make(Op::displace, {{"amplitude", {0.1}}, {"frequency", {15}}}, {box({1, 1, 1})});
  EXPECT_TRUE(derive_info(displaced_box).perturbation.has_value());
  EXPECT_FALSE(derive_info(make(Op::repeat, {{"period", {4, 4, 4}}}, {displaced_box})).perturbation.has_value());
  EXPECT_FALSE(derive_info(make(Op::heightfield, {{"octaves", {0.5, 0}}})).perturbation.has_value()) << "a plane";
}

// A union's boxes are its children's, nested unions' in turn; anything else, or more boxes than asked for, gives the
// derived bounds alone. Broken variant: the hull alone (sdf-bounding-boxes-hull).
TEST(BoundingBoxes, AUnionsAreItsChildrensWhileTheyAreFew) {
  const Node nested = unite({kA, unite({kB, translate({3, 0, 0}, sphere(0.5))})});
  const std::vector<Box3> boxes = bounding_boxes(nested, 0, 4);
  ASSERT_EQ(boxes.size(), 3u);
  EXPECT_EQ(boxes[0].lo, derive_info(kA).bounds.lo);
  EXPECT_EQ(boxes[1].hi, derive_info(kB).bounds.hi);
  EXPECT_EQ(boxes[2].lo, glm::dvec3(2.5, -0.5, -0.5));
  const std::vector<Box3> few = bounding_boxes(nested, 0, 2);
  ASSERT_EQ(few.size(), 1u);
  EXPECT_EQ(few[0].hi, derive_info(nested).bounds.hi);
  EXPECT_EQ(bounding_boxes(kA, 0, 4).size(), 1u);
}

// The displacement's value against its closed form, a sin(f x) sin(f y) sin(f z) on top of the child, at a point
// whose three coordinates differ (rounding: a few ulps of 1). Broken variant: one axis used twice.
TEST(Deformations, DisplacementIsTheProductOfThreeSines) {
  const double a = 0.1, f = 15;
  const Tape tape = compile(make(Op::displace, {{"amplitude", {a}}, {"frequency", {f}}}, {sphere(0.8)}));
  const glm::dvec3 p(0.3, 0.2, 0.7);
  const double expected = glm::length(p) - 0.8 + a * std::sin(f * p.x) * std::sin(f * p.y) * std::sin(f * p.z);
  EXPECT_NEAR(evaluate(tape, p), expected, 1e-15);
}

TEST(Tree, StructuralErrorsNameThePath) {
  Node bad = unite({sphere(1), make(Op::revolve, {}, {sphere(0.2)})});
  EXPECT_EQ(validate_tree(bad), "/children/1/child: revolve needs a 2D child, sphere is 3D");
  Node negative = sphere(1);
  negative.params[0] = -1;
  EXPECT_EQ(validate_tree(negative), "/radius: value -1 is out of range [1e-12, 1e+300]");
  EXPECT_THROW(compile(bad), CompileError);
}

TEST(Tape, DeepTreesAreRejectedNotOverflowed) {
  Node n = sphere(1);
  for (int i = 0; i < 40; ++i) n = unite({sphere(1), translate({0.1, 0, 0}, std::move(n))});
  EXPECT_THROW(compile(n), CompileError);
}

TEST(Materials, UnionCarriesTheClosestChildsMaterial) {
  const Tape t = compile(unite({translate({-1, 0, 0}, sphere(0.5, 3)), translate({1, 0, 0}, sphere(0.5, 7))}));
  EXPECT_EQ(sdf::sample(t, glm::dvec3(-1.2, 0, 0)).material, 3);
  EXPECT_EQ(sdf::sample(t, glm::dvec3(0.9, 0.2, 0)).material, 7);
  // Subtraction: the cut face belongs to the subtracted shape.
  const Tape s = compile(subtract(box(glm::dvec3(1), 1), translate({1, 0, 0}, sphere(0.5, 2))));
  EXPECT_EQ(sdf::sample(s, glm::dvec3(0.45, 0, 0)).material, 2);
  EXPECT_EQ(sdf::sample(s, glm::dvec3(-0.95, 0, 0)).material, 1);
}

}  // namespace
}  // namespace marchcheck::sdf
