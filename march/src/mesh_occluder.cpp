#include "marchcheck/march/mesh_occluder.hpp"

#include "embree_module.hpp"

#include "marchcheck/files/loadable_module.hpp"

namespace marchcheck::march {

namespace {

const EmbreeModule& embree_module() {
  static const EmbreeModule& module = files::module_table<EmbreeModule>(
      reinterpret_cast<const void*>(&embree_module), "libmarchcheck_embree.so", "marchcheck_embree_module");
  return module;
}

}  // namespace

MeshOccluder::MeshOccluder(const std::vector<sdf::SceneMesh>& meshes) : scene_(embree_module().build(meshes)) {}

MeshOccluder::~MeshOccluder() { embree_module().release(scene_); }

MeshHit MeshOccluder::intersect(glm::dvec3 origin, glm::dvec3 direction, double t_max) const {
  return embree_module().intersect(scene_, origin, direction, t_max);
}

}  // namespace marchcheck::march
