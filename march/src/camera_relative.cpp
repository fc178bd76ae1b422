#include "marchcheck/march/camera_relative.hpp"

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

}  // namespace marchcheck::march
