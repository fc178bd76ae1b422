// Topology and orientation checks on plain index arrays (works on non-manifold meshes, unlike a half-edge kernel).
#pragma once

#include "marchcheck/meshes/mesh.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
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
  // Boundary vertices with another boundary vertex within kSeamReach of the bounding diagonal (equal positions
  // included): an exporter's split seam, which a weld of seam_gap or more may close. seam_gap is the largest
  // distance from such a vertex to its nearest partner.
  int seam_vertices = 0;
  double seam_gap = 0;
  bool consistently_oriented = false;  // faces sharing an edge run along it as often one way as the other
  bool outward = false;                // closed, consistently oriented and signed_volume > 0
  double signed_volume = 0;            // sum of signed tetrahedron volumes; meaningful for closed meshes
  // Pairs of triangles (0-based, in the mesh's order) that pass through each other, meeting anywhere but at the
  // edge or vertex they share: a closed manifold that crosses itself has no single inside (its winding number is
  // 2 or -1 in places), so no sign. Tested (CGAL, exact predicates) only when the topology is a solid's.
  std::vector<std::array<std::size_t, 2>> crossing_triangles;
  // Where the first few (kReportExamples) of each problem lie, as indices into the mesh (solid_problem names them
  // as the file does).
  std::vector<std::array<std::uint32_t, 2>> boundary_edges_at, nonmanifold_edges_at, misoriented_edges_at;
  std::vector<std::uint32_t> pinched_vertices_at;
  std::vector<std::size_t> degenerate_faces_at;
};
inline constexpr std::size_t kReportExamples = 3;
inline constexpr double kSeamReach = 1e-6;

// Throws MeshError if a triangle indexes past the vertex array.
MeshReport inspect(const Mesh& mesh);

// The one rule for taking a mesh as a solid (a sign for its distance, an inside for its reference): closed,
// manifold at every edge and vertex, consistently oriented, no degenerate face, and not passing through itself.
// "" when it holds, otherwise every problem found, each with its count and where its first few lie, joined by
// "; ": vertices by their number in the file (Mesh::vertex_numbers) and position, faces by their number in the
// file (triangles counted from 1 where the mesh has no file numbering). Orientation is separate: an inward solid
// is still a solid (see MeshReport::outward). report must be inspect(mesh).
std::string solid_problem(const MeshReport& report, const Mesh& mesh);

}  // namespace marchcheck::meshes
