// References that share no approximation with the marchers: exact CSG ray casting over interval lists built
// from closed-form primitive intersections, and, for fields with no closed form, a double-precision numerical
// root finder with a stated error bound.
#pragma once

#include "marchcheck/sdf/node.hpp"
#include "marchcheck/sdf/tape.hpp"

#include <glm/glm.hpp>

#include <cmath>
#include <initializer_list>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace marchcheck::validation {

// A stretch of the ray inside the solid: entered at t0 through a surface with outward normal n0, left at t1
// through n1. Infinite ends are +-inf.
struct Span {
  double t0, t1;
  glm::dvec3 n0, n1;
};
using Spans = std::vector<Span>;  // sorted by t0, disjoint

class MeshReference;
// The CGAL reference of each mesh node's triangles, for casting rays through mesh nodes.
using MeshReferences = std::map<const sdf::MeshDistance*, std::shared_ptr<const MeshReference>>;
MeshReferences mesh_references(const sdf::Node& node);

// Whether a tree is made only of shapes and operators the exact caster knows (sphere, plane, box, torus,
// capsule, capped cylinder, loaded meshes; union, intersection, subtraction; translate, rotate, uniform scale,
// rigid affine/animate). time feeds animate.
bool exact_supported(const sdf::Node& node, double time = 0);

// The solid's spans along origin + t direction (direction unit length). Requires exact_supported; meshes are
// mesh_references(node).
Spans cast_exact(const sdf::Node& node, glm::dvec3 origin, glm::dvec3 direction, double time = 0,
                 const MeshReferences& meshes = {});

// The first surface along a ray, from either reference.
struct ReferenceHit {
  bool hit = false;
  bool inside = false;  // the origin is inside the solid
  bool unknown = false;  // the numerical reference ran out of steps: no verdict
  // The certified reference could not decide this ray at its width (certified.hpp): the answer is the numerical
  // reference's, which trusts the declared Lipschitz constant. Judges leave such rays out and count them.
  bool undecided = false;
  double t = 0;
  glm::dvec3 normal{0};  // outward
};

// The Mandelbulb as the set its distance estimate approximates the distance to, by membership alone: the
// points whose orbit under w -> w^power + p (the spherical power the estimator iterates) ends, after all its
// iterations, within the unit ball, i.e. where the potential log|w_N| the estimator linearises is <= 0 (orbits
// past the bailout only grow: outside). No distance, no linearisation, no running derivative: nothing the
// estimator approximates.
class EscapeTimeSet {
 public:
  explicit EscapeTimeSet(const sdf::Node& mandelbulb);
  // |w_N|^2, infinite for an orbit past the bailout.
  double final_radius2(glm::dvec3 p) const;
  bool contains(glm::dvec3 p) const { return final_radius2(p) <= 1; }
  // Every point at least this far from the origin escapes at the first iteration: |w1| >= |p|^power - |p|.
  double radius() const { return radius_; }
  // Membership sampled along the ray every min(resolution, 1% of t) (finer near the origin, so a probe from a
  // point near the surface resolves it), each change bisected to 1e-11; a part of the set thinner than the
  // sampling step along the ray can be missed (at 8 iterations the set has filaments far thinner than 1e-3).
  // Every hit it reports is a point of the set, so false hits and misses judged by it are sound; a march
  // through a filament it missed is an overshoot it cannot see. The normal is the gradient of |w_N|^2 by
  // forward-mode differentiation through the orbit.
  ReferenceHit first_hit(glm::dvec3 origin, glm::dvec3 direction, double t_max, double resolution = 1e-3) const;

 private:
  double power_, bailout2_, radius_;
  int iterations_;
};

// Which reference judges a field.
enum class ReferenceKind { exact, escape_time, certified, numerical, parts };

class Reference {
 public:
  // Exact casting when the tree allows it; a Mandelbulb (moved rigidly, scaled uniformly) by its escape-time
  // set, also as a part of a union whose other parts cast exactly; else the certified first hit by interval
  // arithmetic (certified.hpp), with the numerical root finder (steps f / L on the compiled field in double, L
  // the declared bound, every sign change bisected to 1e-9) where it cannot decide and for fields without
  // interval rules (GLSL).
  Reference(const sdf::Node& node, double time);
  // The same, with the numerical root finder stepping by the constant a subject declares (a user's own field
  // or marcher may claim another than the tree's rules derive): what it trusts, the certified reference does not.
  Reference(const sdf::Node& node, double time, double declared_lipschitz);
  ReferenceHit first_hit(glm::dvec3 origin, glm::dvec3 direction, double t_max) const;
  // The numerical root finder alone, the cheap cross-check of the certified reference (the whole first_hit
  // where the reference is not certified).
  ReferenceHit numerical_first_hit(glm::dvec3 origin, glm::dvec3 direction, double t_max) const;
  bool exact() const { return exact_; }
  ReferenceKind kind() const;
  // What judged the field, in words: "exact", "escape-time set", "certified", "numerical", or a union's parts'
  // joined by " + ".
  std::string judged_by() const;
  // Error bound on t where the reference finds a surface at t (0 for the exact one).
  double t_error_bound(double t) const;

 private:
  sdf::Node node_;
  double time_;
  MeshReferences meshes_;
  bool exact_;
  std::optional<EscapeTimeSet> escape_set_;
  std::vector<Reference> parts_;
  sdf::Tape tape_;
  double lipschitz_;
  bool certified_;  // the numerical case, with interval rules for every instruction
};

// The nearest reference surface found from a point so far: an upper bound on its distance to the surface.
struct NearestSurface {
  double distance = INFINITY;
  glm::dvec3 toward{0};  // from the point to the nearest surface point found
  bool inside = false;   // the point is inside the reference solid
};

// Casts from p along the directions where the nearest point is likely (zero ones are skipped), then the 26 of
// the cube's neighbours, and keeps the nearest surface in near.
void probe_nearest(const Reference& ref, glm::dvec3 p, std::initializer_list<glm::dvec3> likely,
                   NearestSurface& near);

}  // namespace marchcheck::validation
