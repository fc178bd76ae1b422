#include "marchcheck/validation/mesh_loader.hpp"

#include "marchcheck/meshes/io.hpp"

namespace marchcheck::validation {

sdf::MeshLoader mesh_loader() {
  return [](const std::string& source) { return to_triangle_mesh(meshes::load_mesh_source(source)); };
}

meshes::Mesh to_mesh(const sdf::TriangleMesh& mesh) {
  meshes::Mesh out;
  out.vertices = mesh.vertices;
  for (const auto& t : mesh.triangles) out.triangles.push_back({t.x, t.y, t.z});
  return out;
}

sdf::TriangleMesh to_triangle_mesh(const meshes::Mesh& mesh) {
  sdf::TriangleMesh out;
  out.vertices = mesh.vertices;
  for (const auto& t : mesh.triangles) out.triangles.emplace_back(t[0], t[1], t[2]);
  return out;
}

}  // namespace marchcheck::validation
