// Normal estimators against analytic normals: error order of the finite differences, exactness of AD.
#include "marchcheck/march/normals.hpp"
#include "marchcheck/march/render.hpp"
#include "marchcheck/sdf/node.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <type_traits>

namespace marchcheck::march {
namespace {

double angle(glm::dvec3 a, glm::dvec3 b) { return std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0)); }

// A point on the unit sphere away from the axes, and its analytic normal.
const glm::dvec3 kPoint = glm::normalize(glm::dvec3(1, 2, 3));

double error_at(NormalMethod method, double eps) {
  const sdf::Tape tape = sdf::compile(sdf::sphere(1));
  return angle(estimate_normal(TapeField{&tape}, kPoint, method, eps).n, kPoint);
}

TEST(Normals, CentralDifferencesAreSecondOrder) {
  // Halving eps shrinks the error about 4x (O(eps^2)); measured in double so rounding stays out of it.
  for (double eps : {2e-2, 1e-2, 5e-3}) {
    const double ratio = error_at(NormalMethod::central, eps) / error_at(NormalMethod::central, eps / 2);
    EXPECT_NEAR(ratio, 4.0, 0.2) << eps;
  }
}

TEST(Normals, ForwardDifferencesAreFirstOrder) {
  for (double eps : {2e-2, 1e-2, 5e-3}) {
    const double ratio = error_at(NormalMethod::forward, eps) / error_at(NormalMethod::forward, eps / 2);
    EXPECT_NEAR(ratio, 2.0, 0.1) << eps;
  }
}

TEST(Normals, TetrahedralDifferencesAreFirstOrderWhereTheHessianIsNotDiagonal) {
  // The four tetrahedron offsets cancel the eps^2 terms of the diagonal Hessian but not the off-diagonal
  // ones (their third moments sum to 4), so away from the axes the error halves with eps.
  for (double eps : {2e-2, 1e-2}) {
    const double ratio = error_at(NormalMethod::tetra, eps) / error_at(NormalMethod::tetra, eps / 2);
    EXPECT_NEAR(ratio, 2.0, 0.1) << eps;
  }
}

TEST(Normals, EvaluationCountsAreTheDocumentedOnes) {
  const sdf::Tape tape = sdf::compile(sdf::sphere(1));
  const TapeField f{&tape};
  EXPECT_EQ(estimate_normal(f, kPoint, NormalMethod::central, 1e-3).evals, 6);
  EXPECT_EQ(estimate_normal(f, kPoint, NormalMethod::forward, 1e-3).evals, 4);
  EXPECT_EQ(estimate_normal(f, kPoint, NormalMethod::tetra, 1e-3).evals, 4);
  EXPECT_EQ(estimate_normal(f, kPoint, NormalMethod::analytic, 1e-3).evals, 1);
}

TEST(Normals, AutomaticDifferentiationEqualsAnalyticNormalsToFloatPrecision) {
  struct Case {
    const char* name;
    sdf::Node node;
    glm::dvec3 p;
    glm::dvec3 expected;
  };
  const double r = 1.3, big = 1.0, small = 0.25;
  const glm::dvec3 tp = glm::dvec3(std::cos(0.7) * (big + small * std::cos(0.4)), small * std::sin(0.4),
                                   std::sin(0.7) * (big + small * std::cos(0.4)));
  const Case cases[] = {
      {"sphere", sdf::sphere(r), r * kPoint, kPoint},
      {"plane", sdf::plane({1, 2, 2}, 0.5), {0.3, -0.4, 0.1}, glm::dvec3(1, 2, 2) / 3.0},
      {"box face", sdf::box({1, 0.5, 0.7}), {0.2, 0.5, -0.3}, {0, 1, 0}},
      {"torus", sdf::torus(big, small), tp, glm::normalize(tp - big * glm::normalize(glm::dvec3(tp.x, 0, tp.z)))},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const sdf::Tape tape = sdf::compile(c.node);
    const auto n = estimate_normal(TapeField{&tape}, glm::vec3(c.p), NormalMethod::analytic, 0.0f);
    // float: the angle is a few ulps of 1 (1.2e-7 each); 1e-6 rad leaves room for the rounding of p itself.
    EXPECT_LT(angle(glm::dvec3(n.n), c.expected), 1e-6);
  }
}

TEST(Normals, ACheckOnErrorOrderCatchesADroppedHalf) {
  // A central difference that forgets one side is a forward difference: its error ratio is 2, not 4.
  const double broken_ratio = error_at(NormalMethod::forward, 1e-2) / error_at(NormalMethod::forward, 5e-3);
  EXPECT_GT(std::abs(broken_ratio - 4.0), 1.0);
}

TEST(Normals, VanishingGradientGivesAZeroNormalNotNaN) {
  const sdf::Tape tape = sdf::compile(sdf::sphere(1));
  for (auto m : {NormalMethod::central, NormalMethod::forward, NormalMethod::tetra, NormalMethod::analytic}) {
    const auto n = estimate_normal(TapeField{&tape}, glm::dvec3(0), m, 1e-3);
    EXPECT_FALSE(std::isnan(n.n.x) || std::isnan(n.n.y) || std::isnan(n.n.z));
  }
}

// A field times a constant: the same surface and normals, a gradient of length k.
struct Scaled {
  const sdf::Tape* tape;
  double k;
  template <class V>
  auto operator()(V q) const {
    using T = std::decay_t<decltype(q.x)>;
    return T(k) * sdf::evaluate(*tape, q);
  }
};

// The quadric x^2/a^2 + y^2/b^2 + z^2/c^2 - 1: smooth, its gradient 2 p / r^2 neither unit nor constant in length,
// its normal normalize(p / r^2) everywhere.
struct Quadric {
  glm::dvec3 r;
  template <class V>
  auto operator()(V q) const {
    using T = std::decay_t<decltype(q.x)>;
    return q.x * q.x / T(r.x * r.x) + q.y * q.y / T(r.y * r.y) + q.z * q.z / T(r.z * r.z) - T(1);
  }
};

// Every estimator on fields whose gradient is not unit length (a sphere scaled by 2.5; the quadric) against the
// analytic normal: unit length, and the angle within its order's error at eps = 1e-4 (central: eps^2 times
// third-derivative terms, < 1e-6; forward and tetrahedral: eps times the curvature over |grad| (at most 4 here),
// < 2e-3; AD: rounding, < 1e-9). Broken variants: a normalisation dropped (length 2.5 or |grad|), a probe with
// the wrong weight.
TEST(Normals, EveryEstimatorIsUnitAndRightWhereTheGradientIsNotUnit) {
  const sdf::Tape sphere = sdf::compile(sdf::sphere(1));
  const Quadric quadric{{1, 0.5, 0.75}};
  const glm::dvec3 q = 1.2 * quadric.r * kPoint;  // just outside the quadric's zero set
  const std::pair<NormalMethod, double> methods[] = {{NormalMethod::central, 1e-6},
                                                     {NormalMethod::forward, 2e-3},
                                                     {NormalMethod::tetra, 2e-3},
                                                     {NormalMethod::analytic, 1e-9}};
  for (const auto& [method, tolerance] : methods) {
    SCOPED_TRACE("method " + std::to_string(static_cast<int>(method)));
    const glm::dvec3 on_sphere = estimate_normal(Scaled{&sphere, 2.5}, kPoint, method, 1e-4).n;
    EXPECT_NEAR(glm::length(on_sphere), 1, 1e-12);
    EXPECT_LT(angle(on_sphere, kPoint), tolerance);
    const glm::dvec3 on_quadric = estimate_normal(quadric, q, method, 1e-4).n;
    EXPECT_NEAR(glm::length(on_quadric), 1, 1e-12);
    EXPECT_LT(angle(on_quadric, glm::normalize(q / (quadric.r * quadric.r))), tolerance);
  }
}

}  // namespace
}  // namespace marchcheck::march
