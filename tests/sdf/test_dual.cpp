// Forward-mode differentiation through the field code gives analytic gradients.
#include "marchcheck/sdf/node.hpp"
#include "marchcheck/sdf/tape.hpp"

#include <gtest/gtest.h>

namespace marchcheck::sdf {
namespace {

glm::dvec3 gradient(const Tape& tape, glm::dvec3 p) {
  using D = Dual<double>;
  const glm::vec<3, D> q(D(p.x, {1, 0, 0}), D(p.y, {0, 1, 0}), D(p.z, {0, 0, 1}));
  return sdf::evaluate(tape, q).d;
}

TEST(Dual, GradientsMatchCentralDifferencesOnEveryKindOfNode) {
  const Node scene = unite({translate({0, 1.2, 0}, sphere(1)), plane({0, 1, 0}, 0),
                            make(Op::twist, {{"rate", {1.5}}}, {translate({2, 0, 0}, box({0.4, 0.6, 0.3}))}),
                            make(Op::displace, {{"amplitude", {0.1}}, {"frequency", {5}}}, {torus(1, 0.3)}),
                            make(Op::heightfield, {{"octaves", {-0.5, 0.5}}})});
  const Tape tape = compile(scene);
  for (const glm::dvec3 p : {glm::dvec3(0.3, 2.1, 0.2), glm::dvec3(2.2, 0.3, 0.1), glm::dvec3(0.9, 0.1, 0.4),
                             glm::dvec3(-3.3, 0.2, 1.7)}) {
    const double h = 1e-6;
    const glm::dvec3 fd((sdf::evaluate(tape, p + glm::dvec3(h, 0, 0)) - sdf::evaluate(tape, p - glm::dvec3(h, 0, 0))) / (2 * h),
                        (sdf::evaluate(tape, p + glm::dvec3(0, h, 0)) - sdf::evaluate(tape, p - glm::dvec3(0, h, 0))) / (2 * h),
                        (sdf::evaluate(tape, p + glm::dvec3(0, 0, h)) - sdf::evaluate(tape, p - glm::dvec3(0, 0, h))) / (2 * h));
    // Central differences at h = 1e-6 carry ~1e-10 rounding and O(h^2) truncation: 1e-7 is ample.
    EXPECT_NEAR(glm::length(gradient(tape, p) - fd), 0.0, 1e-7) << p.x << " " << p.y << " " << p.z;
  }
}

}  // namespace
}  // namespace marchcheck::sdf
