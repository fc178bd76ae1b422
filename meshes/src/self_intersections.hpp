// Where a closed manifold mesh passes through itself, by CGAL's exact predicates (defined in cgal/cgal_surface.cpp,
// the one CGAL file of meshes/); no CGAL type in this header, so checks.cpp compiles without CGAL.
#pragma once

#include "marchcheck/meshes/mesh.hpp"

#include <array>
#include <cstddef>
#include <vector>

namespace marchcheck::meshes {

// Pairs of triangles (indices into mesh.triangles) that meet anywhere but at the edge or vertex they share. The
// mesh must be a closed, consistently oriented manifold without degenerate faces (solid_problem's topology).
std::vector<std::array<std::size_t, 2>> crossing_triangles(const Mesh& mesh);

}  // namespace marchcheck::meshes
