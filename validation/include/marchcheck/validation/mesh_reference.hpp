// Triangle-mesh references with CGAL: exact closest points and distances (AABB tree, exact predicates), sign by
// Side_of_triangle_mesh for closed meshes, first ray hits with their face normals, shadow visibility.
#pragma once

#include "marchcheck/meshes/checks.hpp"
#include "marchcheck/meshes/mesh.hpp"
#include "marchcheck/validation/reference.hpp"

#include <glm/glm.hpp>

#include <memory>
#include <optional>

namespace marchcheck::validation {

class MeshReference {
 public:
  explicit MeshReference(const meshes::Mesh& mesh);
  // With the mesh's report (meshes::inspect(mesh)) already made: a mesh node's, whose CGAL crossing test is the
  // costliest part of inspecting a large mesh.
  MeshReference(const meshes::Mesh& mesh, const meshes::MeshReport& report);
  ~MeshReference();
  MeshReference(const MeshReference&) = delete;
  MeshReference& operator=(const MeshReference&) = delete;

  // Only solids (meshes::solid_problem: closed, manifold, oriented, not passing through themselves) have an inside,
  // built from every face (meshes::cgal::surface_mesh refuses otherwise): only they give signed distances.
  // Distances and ray hits of any mesh use every triangle as a soup.
  bool closed() const;
  double unsigned_distance(glm::dvec3 p) const;
  glm::dvec3 closest_point(glm::dvec3 p) const;
  // Negative inside; nullopt for a mesh that is no solid (unsigned distance only).
  std::optional<double> signed_distance(glm::dvec3 p) const;
  // The first face along origin + t direction (unit) within t_max, with its outward face normal.
  ReferenceHit first_hit(glm::dvec3 origin, glm::dvec3 direction, double t_max) const;
  // The solid's spans along the whole line origin + t direction, for the exact CSG caster: entered and left
  // through the faces the line crosses (outward face normals). Closed meshes only; an open mesh has no spans.
  Spans spans(glm::dvec3 origin, glm::dvec3 direction) const;
  // Whether the open segment a-b crosses no face (shadow visibility from a to a light at b).
  bool visible(glm::dvec3 a, glm::dvec3 b) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace marchcheck::validation
