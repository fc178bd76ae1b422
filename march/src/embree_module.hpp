// MeshOccluder's Embree half, in a module of its own, libmarchcheck_embree.so, loaded by the first scene with
// triangle meshes: Embree cost every command ~2.4 ms of dynamic loading when march linked it.
#pragma once

#include "marchcheck/march/mesh_occluder.hpp"

namespace marchcheck::march {

struct EmbreeModule {
  // The meshes in an Embree scene of their own; throws std::runtime_error when Embree cannot start.
  void* (*build)(const std::vector<sdf::SceneMesh>& meshes);
  void (*release)(void* scene);
  // As MeshOccluder::intersect.
  MeshHit (*intersect)(const void* scene, glm::dvec3 origin, glm::dvec3 direction, double t_max);
};

}  // namespace marchcheck::march
