// Exact ray-triangle intersection of a scene's triangle meshes (Embree's BVH), so the march can stop at the
// nearest mesh as the Unity seed does with its depth buffer. Embree itself lives in a module loaded by the first
// occluder (src/embree_module.hpp).
#pragma once

#include "marchcheck/sdf/scene.hpp"

#include <glm/glm.hpp>

#include <vector>

namespace marchcheck::march {

struct MeshHit {
  bool hit = false;
  double t = 0;
  glm::dvec3 normal{0};  // geometric normal facing the ray
  int material = -1;
};

class MeshOccluder {
 public:
  explicit MeshOccluder(const std::vector<sdf::SceneMesh>& meshes);
  ~MeshOccluder();
  MeshOccluder(const MeshOccluder&) = delete;
  MeshOccluder& operator=(const MeshOccluder&) = delete;

  // Nearest triangle along origin + t direction for t in (0, t_max). Thread-safe.
  MeshHit intersect(glm::dvec3 origin, glm::dvec3 direction, double t_max) const;

 private:
  void* scene_;  // the module's
};

}  // namespace marchcheck::march
