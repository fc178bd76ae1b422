// GoogleTest assertions for users' own SDFs and marchers, in their own test suites:
//   EXPECT_TRUE(LipschitzAtMost(my_sdf, 1.0));
//   EXPECT_TRUE(IsBoundOf(my_sdf, sdf::box({1, 1, 1})));
//   EXPECT_TRUE(PassesValidate(scene, my_sdf, my_march, {sdf::Kind::exact, 1}));
// A field is any callable from glm::dvec3 to a number: written as a template (`auto p`) it runs in double; one
// that takes glm::vec3 is called with the point rounded to float. A marcher is a callable from a TestRay to a
// MarchedRay, or from (field, TestRay) to a MarchedRay: given the field, marchcheck counts its evaluations itself.
// Every failure names the first ray or point that failed (or the worst one) with its numbers.
// Needs GLM and GoogleTest only: no header here includes CGAL, OpenMesh or OpenImageIO.
#pragma once

#include "marchcheck/march/camera.hpp"
#include "marchcheck/march/normals.hpp"
#include "marchcheck/sdf/lipschitz.hpp"
#include "marchcheck/validation/mesh_reference.hpp"
#include "marchcheck/validation/reference.hpp"
#include "marchcheck/validation/validate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <concepts>
#include <optional>
#include <random>
#include <sstream>
#include <type_traits>
#include <vector>

namespace marchcheck::validation {

struct TestRay {
  glm::dvec3 origin, direction;  // direction unit length
};

// The box the field checks sample, [-2, 2]^3 unless a test says otherwise.
struct Region {
  glm::dvec3 lo{-2}, hi{2};
};

// The primary rays of a scene's camera through an nx x ny grid of pixel centres (as validate samples them).
inline std::vector<TestRay> camera_rays(const sdf::Scene& scene, int nx = 64, int ny = 36) {
  const march::Camera camera(scene.camera, scene.width, scene.height);
  std::vector<TestRay> rays;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const march::Ray r = camera.ray((i + 0.5) * scene.width / nx, (j + 0.5) * scene.height / ny);
      rays.push_back({r.origin, r.direction});
    }
  return rays;
}

namespace detail {

inline std::string number_text(double x) {
  std::ostringstream out;
  out.precision(9);
  out << x;
  return out.str();
}

inline std::string point_text(glm::dvec3 p) {
  std::ostringstream out;
  out.precision(9);
  out << "(" << p.x << ", " << p.y << ", " << p.z << ")";
  return out.str();
}

inline std::string ray_text(size_t i, const TestRay& ray) {
  return "ray " + std::to_string(i) + " (origin " + point_text(ray.origin) + ", direction " +
         point_text(ray.direction) + ")";
}

template <class Field>
double value_at(const Field& f, glm::dvec3 p) {
  return static_cast<double>(f(p));
}

// The field with a count of its evaluations, for a marcher that takes the field.
template <class Field>
struct CountedField {
  const Field* field;
  int* count;
  template <class P>
  auto operator()(const P& p) const {
    ++*count;
    return (*field)(p);
  }
};

// One random sample point of a region per call (fixed seed).
struct RegionSampler {
  Region region;
  std::mt19937 rng;
  std::uniform_real_distribution<double> u{0, 1};
  glm::dvec3 next() { return region.lo + (region.hi - region.lo) * glm::dvec3(u(rng), u(rng), u(rng)); }
};

// |f| against the distance to a reference's surface (upper bound from casts along f's gradient and 26 more
// directions, tight where the gradient points at the nearest point, as an exact field's does) and f's sign
// against the reference's inside. exact: also |f| may not fall short of that distance.
template <class Field>
::testing::AssertionResult against_reference(const Field& f, const Reference& ref, Region region, bool exact,
                                             double tolerance, int samples, unsigned seed) {
  RegionSampler sampler{region, std::mt19937(seed)};
  for (int i = 0; i < samples; ++i) {
    const glm::dvec3 p = sampler.next();
    const double value = value_at(f, p);
    const glm::dvec3 grad =
        march::central_normal([&f](glm::dvec3 q) { return value_at(f, q); }, p, 1e-6 * (1 + glm::length(p))).n;
    NearestSurface near;
    probe_nearest(ref, p, {value > 0 ? -grad : grad}, near);
    if (near.inside != (value < 0) && std::abs(value) > tolerance && near.distance > tolerance)
      return ::testing::AssertionFailure() << "f = " << value << " at " << point_text(p) << " says "
                                           << (value < 0 ? "inside" : "outside") << ", the reference "
                                           << (near.inside ? "inside" : "outside");
    if (near.inside || !std::isfinite(near.distance)) continue;  // distances are compared outside the solid
    if (std::abs(value) > near.distance + tolerance)
      return ::testing::AssertionFailure() << "|f| = " << std::abs(value) << " at " << point_text(p)
                                           << " exceeds the distance to the surface, at most " << near.distance
                                           << " (along " << point_text(near.toward) << "): not a bound";
    if (exact && std::abs(value) < near.distance - tolerance)
      return ::testing::AssertionFailure() << "|f| = " << std::abs(value) << " at " << point_text(p)
                                           << " falls short of the distance to the surface, " << near.distance
                                           << " (along " << point_text(near.toward) << "): not exact";
  }
  return ::testing::AssertionSuccess();
}

// |f| against the distance to a mesh and its sign; exact: |f - signed distance| too.
template <class Field>
::testing::AssertionResult against_mesh(const Field& f, const meshes::Mesh& mesh, bool exact, Region region,
                                       double tolerance, int samples, unsigned seed) {
  const MeshReference ref(mesh);
  RegionSampler sampler{region, std::mt19937(seed)};
  for (int i = 0; i < samples; ++i) {
    const glm::dvec3 p = sampler.next();
    const double value = value_at(f, p), distance = ref.unsigned_distance(p);
    if (std::abs(value) > distance + tolerance)
      return ::testing::AssertionFailure() << "|f| = " << std::abs(value) << " exceeds the distance " << distance
                                           << " to the mesh at " << point_text(p);
    const auto signed_d = ref.signed_distance(p);
    if (signed_d && distance > tolerance && (value < 0) != (*signed_d < 0))
      return ::testing::AssertionFailure() << "f = " << value << " has the wrong sign at " << point_text(p)
                                           << " (signed distance " << *signed_d << ")";
    if (exact && signed_d && std::abs(value - *signed_d) > tolerance)
      return ::testing::AssertionFailure() << "f = " << value << " at " << point_text(p)
                                           << " differs from the signed distance " << *signed_d << " by more than "
                                           << tolerance;
  }
  return ::testing::AssertionSuccess();
}


}  // namespace detail

// Finite differences over random nearby pairs in the region never exceed L (1e-6 relative for the rounding of
// the differences); a failure names the steepest pair.
template <class Field>
::testing::AssertionResult LipschitzAtMost(const Field& f, double lipschitz, Region region = {}, int pairs = 20000,
                                           double step = 1e-5, unsigned seed = 2) {
  const sdf::SteepestPair worst =
      sdf::steepest_pair([&f](glm::dvec3 p) { return detail::value_at(f, p); }, region.lo, region.hi, pairs, step, seed);
  if (worst.slope > lipschitz * (1 + 1e-6))
    return ::testing::AssertionFailure() << "measured slope " << detail::number_text(worst.slope)
                                         << " exceeds the bound " << lipschitz << ": from "
                                         << detail::point_text(worst.from) << " along "
                                         << detail::point_text(worst.direction) << " over "
                                         << detail::number_text(step);
  return ::testing::AssertionSuccess() << "measured slope " << detail::number_text(worst.slope);
}

// f is a bound of a closed-form shape (any tree the references cast exactly, e.g. sdf::sphere(1)): |f| never
// exceeds the distance to its surface (within tolerance) outside it, and f's sign says inside/outside as it does.
template <class Field>
::testing::AssertionResult IsBoundOf(const Field& f, const sdf::Node& shape, Region region = {},
                                     double tolerance = 1e-9, int samples = 2000, unsigned seed = 1) {
  return detail::against_reference(f, Reference(shape, 0), region, false, tolerance, samples, seed);
}

// f is the exact signed distance of a closed-form shape: a bound whose |f| also reaches the distance.
template <class Field>
::testing::AssertionResult IsExactOf(const Field& f, const sdf::Node& shape, Region region = {},
                                     double tolerance = 1e-9, int samples = 2000, unsigned seed = 1) {
  return detail::against_reference(f, Reference(shape, 0), region, true, tolerance, samples, seed);
}

// |f| never exceeds the distance to the mesh (within tolerance, e.g. the mesh's chord error), and for a closed
// mesh f's sign says inside/outside as the mesh does; exact: |f - signed distance| within tolerance.
template <class Field>
::testing::AssertionResult IsBoundOfMesh(const Field& f, const meshes::Mesh& mesh, Region region = {},
                                         double tolerance = 1e-9, int samples = 2000, unsigned seed = 1) {
  return detail::against_mesh(f, mesh, false, region, tolerance, samples, seed);
}

template <class Field>
::testing::AssertionResult IsExactOfMesh(const Field& f, const meshes::Mesh& mesh, Region region = {},
                                         double tolerance = 1e-9, int samples = 2000, unsigned seed = 1) {
  return detail::against_mesh(f, mesh, true, region, tolerance, samples, seed);
}

// What a user's field declares, and the arithmetic of their march.
struct Declaration {
  sdf::Kind kind = sdf::Kind::exact;
  double lipschitz = 1;
  bool float_march = true;  // the march runs in float: its hit points may be rounded by float's epsilon
};

// No normal function: the marcher's own normals (MarchedRay::normal) are judged, if it gives any.
struct NoNormal {};

// A user's field, marcher and normal function (callable from the hit point as glm::dvec3, like a shader's
// calcNormal(p)) as validate judges them; all must outlive the result. max_steps is held against the field
// evaluations counted during the march, so a marcher that also estimates its normal counts those too: give the
// normal as its own function. Shadows are judged once the subject's visibility is set.
template <class Field, class Marcher, class Normal = NoNormal>
Subject user_subject(const Field& field, const Marcher& marcher, const Declaration& declared = {},
                     const Normal& normal = {}) {
  Subject s;
  if constexpr (!std::is_same_v<Normal, NoNormal>)
    s.normal = [&normal](glm::dvec3 p, double) { return glm::dvec3(normal(p)); };
  s.field = [&field](glm::dvec3 p) { return detail::value_at(field, p); };
  s.march = [&field, &marcher](glm::dvec3 origin, glm::dvec3 direction) {
    const TestRay ray{origin, direction};
    if constexpr (std::invocable<const Marcher&, const detail::CountedField<Field>&, const TestRay&>) {
      int count = 0;
      MarchedRay r = marcher(detail::CountedField<Field>{&field, &count}, ray);
      r.evals = count;
      return r;
    } else {
      return MarchedRay(marcher(ray));
    }
  };
  s.declared.kind = declared.kind;
  s.declared.lipschitz = declared.lipschitz;
  s.exact_outside = declared.kind == sdf::Kind::exact;
  s.unit_roundoff = declared.float_march ? 0x1p-23 : 0x1p-52;
  return s;
}

// Every check passes; a failure prints validate's table, each failed check with the ray that failed it first.
inline ::testing::AssertionResult PassesChecks(const SceneResult& result) {
  if (result.pass()) return ::testing::AssertionSuccess();
  std::ostringstream table;
  print_checks(result, table);
  return ::testing::AssertionFailure() << table.str();
}

// A user's field and marcher pass validate's checks against the scene's references (scene.root, or
// scene.intended: what the field should draw), through its camera, with its march settings (hit_eps, max_steps,
// max_dist: what the marcher claims to use) and its limits.
template <class Field, class Marcher, class Normal = NoNormal>
::testing::AssertionResult PassesValidate(const sdf::Scene& scene, const Field& field, const Marcher& marcher,
                                          const Declaration& declared = {}, const Normal& normal = {},
                                          const ValidateOptions& options = {}) {
  return PassesChecks(validate_subject(scene, user_subject(field, marcher, declared, normal), options));
}

// A marcher (callable std::optional<double>(const TestRay&): hit distance or nothing) agrees with a reference on
// every ray: same hit/miss, and hit distances within tolerance (e.g. hit_eps over the cosine of incidence).
template <class Marcher, class Ref>
::testing::AssertionResult MarcherMatchesReference(const Marcher& march, const Ref& reference,
                                                   const std::vector<TestRay>& rays, double tolerance,
                                                   double t_max = 1e9) {
  for (size_t i = 0; i < rays.size(); ++i) {
    const std::optional<double> marched = march(rays[i]);
    const ReferenceHit expected = reference.first_hit(rays[i].origin, rays[i].direction, t_max);
    if (marched.has_value() != expected.hit)
      return ::testing::AssertionFailure() << detail::ray_text(i, rays[i]) << ": marched "
                                           << (marched ? "hit at t = " + std::to_string(*marched) : "miss")
                                           << ", reference "
                                           << (expected.hit ? "hit at t = " + std::to_string(expected.t) : "miss");
    if (marched && std::abs(*marched - expected.t) > tolerance)
      return ::testing::AssertionFailure() << detail::ray_text(i, rays[i]) << ": marched t = " << *marched
                                           << ", reference " << expected.t << ", error "
                                           << std::abs(*marched - expected.t) << " over the tolerance " << tolerance;
  }
  return ::testing::AssertionSuccess();
}

}  // namespace marchcheck::validation
