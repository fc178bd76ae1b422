// GoogleTest expectations for users' own SDFs, in their own test suites:
//   EXPECT_TRUE(marchcheck::validation::IsBoundOfMesh(my_sdf, mesh, lo, hi));
//   EXPECT_TRUE(marchcheck::validation::LipschitzAtMost(my_sdf, 1.0, lo, hi));
//   EXPECT_TRUE(marchcheck::validation::MarcherMatchesReference(my_march, reference, rays, hit_eps));
// A field is any callable double(glm::dvec3).
#pragma once

#include "marchcheck/validation/lipschitz.hpp"
#include "marchcheck/validation/mesh_reference.hpp"
#include "marchcheck/validation/reference.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace marchcheck::validation {

struct TestRay {
  glm::dvec3 origin, direction;  // direction unit length
};

// |f| never exceeds the distance to the mesh (within tolerance, e.g. the mesh's chord error), and for a closed
// mesh f's sign says inside/outside as the mesh does. Samples uniformly in [lo, hi], fixed seed.
template <class Field>
::testing::AssertionResult IsBoundOfMesh(const Field& f, const meshes::Mesh& mesh, glm::dvec3 lo, glm::dvec3 hi,
                                         double tolerance = 1e-9, int samples = 2000, unsigned seed = 1) {
  const MeshReference ref(mesh);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < samples; ++i) {
    const glm::dvec3 p = lo + (hi - lo) * glm::dvec3(u(rng), u(rng), u(rng));
    const double value = f(p), distance = ref.unsigned_distance(p);
    if (std::abs(value) > distance + tolerance)
      return ::testing::AssertionFailure() << "|f| = " << std::abs(value) << " exceeds the distance " << distance
                                           << " to the mesh at (" << p.x << ", " << p.y << ", " << p.z << ")";
    const auto signed_d = ref.signed_distance(p);
    if (signed_d && distance > tolerance && (value < 0) != (*signed_d < 0))
      return ::testing::AssertionFailure() << "f has the wrong sign at (" << p.x << ", " << p.y << ", " << p.z << ")";
  }
  return ::testing::AssertionSuccess();
}

// Finite differences over random nearby pairs never exceed L (plus tolerance for rounding).
template <class Field>
::testing::AssertionResult LipschitzAtMost(const Field& f, double lipschitz, glm::dvec3 lo, glm::dvec3 hi,
                                           int pairs = 20000, double step = 1e-5, unsigned seed = 2) {
  const double worst = measured_slope(f, lo, hi, pairs, step, seed);
  if (worst > lipschitz * (1 + 1e-6))
    return ::testing::AssertionFailure() << "measured slope " << worst << " exceeds the bound " << lipschitz;
  return ::testing::AssertionSuccess() << "measured slope " << worst;
}

// A marcher (callable std::optional<double>(const TestRay&): hit distance or nothing) agrees with a reference on
// every ray: same hit/miss, and hit distances within tolerance (e.g. hit_eps over the cosine of incidence).
template <class Marcher, class Ref>
::testing::AssertionResult MarcherMatchesReference(const Marcher& march, const Ref& reference,
                                                   const std::vector<TestRay>& rays, double tolerance,
                                                   double t_max = 1e9) {
  for (size_t i = 0; i < rays.size(); ++i) {
    const auto marched = march(rays[i]);
    const ReferenceHit expected = reference.first_hit(rays[i].origin, rays[i].direction, t_max);
    if (marched.has_value() != expected.hit)
      return ::testing::AssertionFailure() << "ray " << i << ": marched " << (marched ? "hit" : "miss")
                                           << ", reference " << (expected.hit ? "hit" : "miss");
    if (marched && std::abs(*marched - expected.t) > tolerance)
      return ::testing::AssertionFailure() << "ray " << i << ": marched t = " << *marched << ", reference "
                                           << expected.t;
  }
  return ::testing::AssertionSuccess();
}

}  // namespace marchcheck::validation
