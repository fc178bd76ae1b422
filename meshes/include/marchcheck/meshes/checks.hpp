// Topology and orientation checks on plain index arrays (works on non-manifold meshes, unlike a half-edge kernel).
#pragma once

#include "marchcheck/meshes/mesh.hpp"

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace marchcheck::meshes {

struct MeshReport {
  bool closed = false;                 // no boundary edges (and at least one triangle)
  bool manifold = false;               // no edge with more than two faces, no pinched vertex
  int boundary_edges = 0;              // edges used by exactly one face
  int boundary_loops = 0;              // connected chains of boundary edges (a hole is one)
  int misoriented_edges = 0;           // edges of two or more faces that do not run along it as often each way
  int nonmanifold_edges = 0;           // edges used by three or more faces
  int nonmanifold_vertices = 0;        // vertices whose faces do not form one fan (pinched, or on such an edge)
  int degenerate_faces = 0;            // repeated index, or area <= 1e-12 · (longest edge)² (zero up to rounding);
                                       // faces with a repeated index take no part in the edge and fan counts
  int duplicate_vertices = 0;          // vertices at exactly the position of an earlier vertex
  bool consistently_oriented = false;  // faces sharing an edge run along it as often one way as the other
  bool outward = false;                // closed, consistently oriented and signed_volume > 0
  double signed_volume = 0;            // sum of signed tetrahedron volumes; meaningful for closed meshes
  // Pairs of triangles (0-based, in the mesh's order) that pass through each other, meeting anywhere but at the
  // edge or vertex they share: a closed manifold that crosses itself has no single inside (its winding number is
  // 2 or -1 in places), so no sign. Tested (CGAL, exact predicates) only when the topology is a solid's.
  std::vector<std::array<std::size_t, 2>> crossing_triangles;
  // Where the first few (kReportExamples) of each problem lie: edges and vertices by position, which every format
  // holds (an STL's vertices have no numbers, and welding renumbers them); faces by index into the triangles.
  std::vector<std::array<glm::dvec3, 2>> boundary_edges_at, nonmanifold_edges_at, misoriented_edges_at;
  std::vector<glm::dvec3> pinched_vertices_at;
  std::vector<std::size_t> degenerate_faces_at;
};
inline constexpr std::size_t kReportExamples = 3;

// Throws MeshError if a triangle indexes past the vertex array.
MeshReport inspect(const Mesh& mesh);

// The one rule for taking a mesh as a solid (a sign for its distance, an inside for its reference): closed,
// manifold at every edge and vertex, consistently oriented, no degenerate face, and not passing through itself.
// "" when it holds, otherwise every problem found, each with its count and where its first few lie, joined by
// "; " (faces numbered from 1 in the file's order, a polygon counted as the triangles of its fan). Orientation is
// separate: an inward solid is still a solid (see MeshReport::outward).
std::string solid_problem(const MeshReport& report);

}  // namespace marchcheck::meshes
