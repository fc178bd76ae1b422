// Scene files' mesh nodes read through meshes/: OBJ, OFF, PLY and STL files, and procedural:SPEC generators.
#pragma once

#include "marchcheck/meshes/mesh.hpp"
#include "marchcheck/sdf/scene_file.hpp"

namespace marchcheck::validation {

// What the program passes to scene loading (sdf::resolve_scene, sdf::load_scene_file, ...).
sdf::MeshLoader mesh_loader();

// The same triangles in each module's type.
meshes::Mesh to_mesh(const sdf::TriangleMesh& mesh);
sdf::TriangleMesh to_triangle_mesh(const meshes::Mesh& mesh);

}  // namespace marchcheck::validation
