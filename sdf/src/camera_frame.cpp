#include "marchcheck/sdf/scene.hpp"

#include <cmath>
#include <numbers>

namespace marchcheck::sdf {

CameraFrame camera_frame(const CameraSpec& spec) {
  CameraFrame f;
  if (spec.pose == CameraPose::orbit) {
    const double degree = std::numbers::pi / 180, yaw = spec.yaw_deg * degree, pitch = spec.pitch_deg * degree;
    // Behind the view's own forward axis at yaw 0: +z for a right-handed view (which looks along -z), -z for a
    // shader's (which looks along +z: the lee seed's eye (-6 cos(pitch) sin(-yaw), 6 sin(pitch), -6 cos(pitch) cos(-yaw))).
    const double behind = spec.axes == CameraAxes::shader ? -1 : 1;
    f.eye = spec.target + spec.distance * glm::dvec3(std::cos(pitch) * std::sin(yaw), std::sin(pitch),
                                                     behind * std::cos(pitch) * std::cos(yaw));
  } else {
    f.eye = spec.position;
  }
  f.forward = glm::normalize(spec.target - f.eye);
  if (spec.axes == CameraAxes::shader) {
    f.right = glm::normalize(glm::cross(spec.up, f.forward));
    f.up = glm::cross(f.forward, f.right);
  } else {
    f.right = glm::normalize(glm::cross(f.forward, spec.up));
    f.up = glm::cross(f.right, f.forward);
  }
  return f;
}

LensCoefficients image_lens(const CameraSpec& spec) {
  return {spec.k1, spec.k2, spec.lens == LensConvention::shader ? -spec.p1 : spec.p1, spec.p2};
}

}  // namespace marchcheck::sdf
