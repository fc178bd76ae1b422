// A solid mesh as CGAL's Surface_mesh, for the files that use CGAL (the self-intersection test here, the mesh
// reference in validation/): one conversion, one rule for faces CGAL cannot take.
#pragma once

#include "marchcheck/meshes/mesh.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>

namespace marchcheck::meshes::cgal {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;

// Every triangle, as face i for mesh.triangles[i]. Throws MeshError when the triangles form no oriented
// 2-manifold surface (CGAL would drop faces, or its preconditions fail) or CGAL took fewer faces than given:
// a reference never answers for a surface with faces missing.
SurfaceMesh surface_mesh(const Mesh& mesh);

}  // namespace marchcheck::meshes::cgal
