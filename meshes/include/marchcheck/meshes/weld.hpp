// Repairs a user asks for by name: welding vertices that a file keeps apart (split seams, STL's unshared corners,
// exporters' near-coincident copies).
#pragma once

#include "marchcheck/meshes/mesh.hpp"

#include <string>

namespace marchcheck::meshes {

struct WeldResult {
  int merged_vertices = 0;  // vertices that became another one
  int removed_faces = 0;    // faces left with a repeated index by the merge (a seam's zero-area slivers)
};

// Merges each vertex into the first earlier kept vertex within tolerance (Euclidean; 0 merges exactly equal
// positions only), removes the faces the merge leaves with a repeated index, and drops vertices no face uses.
// Faces keep their order. Throws MeshError for a negative or non-finite tolerance, or one below about 2^-47 of
// the coordinates (where double cannot tell positions that close apart).
WeldResult weld(Mesh& mesh, double tolerance);

// "welded at TOL: N vertices merged, M faces with a repeated index removed" (or "nothing to weld").
std::string describe(const WeldResult& result, double tolerance);

}  // namespace marchcheck::meshes
