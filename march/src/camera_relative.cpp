#include "marchcheck/march/camera_relative.hpp"

#include "marchcheck/march/camera.hpp"

namespace marchcheck::march {

sdf::Node camera_relative(const sdf::Node& root, glm::dvec3 eye) {
  using sdf::Op;
  switch (root.op) {
    case Op::translate: {
      sdf::Node out = root;
      out.params = {root.params[0] - eye.x, root.params[1] - eye.y, root.params[2] - eye.z};
      return out;
    }
    case Op::union_:
    case Op::intersection:
    case Op::subtraction:
    case Op::smooth_union:
    case Op::smooth_intersection:
    case Op::smooth_subtraction: {
      sdf::Node out = root;
      for (auto& child : out.children) child = camera_relative(child, eye);
      return out;
    }
    default: return sdf::translate(-eye, root);
  }
}

glm::dvec3 march_origin(const sdf::Scene& scene) {
  if (scene.march.coordinates == sdf::Coordinates::world) return glm::dvec3(0);
  return Camera(scene.camera, scene.width, scene.height).eye();
}

sdf::Tape march_tape(const sdf::Scene& scene, glm::dvec3 origin) {
  return origin == glm::dvec3(0) ? sdf::compile(scene) : sdf::compile(scene, camera_relative(scene.root, origin));
}

}  // namespace marchcheck::march
