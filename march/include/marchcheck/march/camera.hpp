// Cameras: pinhole by vertical field of view, pinhole by intrinsics with Brown-Conrady distortion (OpenCV's
// convention or a shader's), frustum-corner interpolation, orthographic; look-at or orbit pose, right-handed or a
// shader's axes (sdf::camera_frame). Pixel (x, y) has its centre at (x + 0.5, y + 0.5), y down.
#pragma once

#include "marchcheck/march/marcher.hpp"
#include "marchcheck/sdf/scene.hpp"

#include <glm/glm.hpp>

#include <optional>

namespace marchcheck::march {

struct Ray {
  glm::dvec3 origin;
  glm::dvec3 direction;  // unit length, unless the spec reproduces a seed that forgets to normalise
};

class Camera {
 public:
  Camera(const sdf::CameraSpec& spec, int width, int height);

  // The ray through continuous pixel coordinates (px, py).
  Ray ray(double px, double py) const;
  // out[i] = ray(px[i], py[i]) for i < n, bit for bit; lens undistortion runs for many pixels at once.
  void rays(const double* px, const double* py, int n, Ray* out) const;
  // The continuous pixel coordinates a world point projects to; nullopt behind the camera.
  std::optional<glm::dvec2> project(glm::dvec3 world) const;

  glm::dvec3 eye() const { return eye_; }
  glm::dvec3 forward() const { return forward_; }
  // A pixel's radius at distance t along a ray: footprint_at_0 + footprint_slope * t.
  double footprint_at_0() const;
  double footprint_slope() const;
  // The vertical field of view the generated rays really span, in degrees (orthographic: 0).
  double measured_vertical_fov_deg() const;

 private:
  glm::dvec2 distort(glm::dvec2 undistorted) const;
  glm::dvec2 undistort(glm::dvec2 distorted) const;
  // Normalised image coordinates to the ray's, and back, by the scene's lens convention.
  glm::dvec2 through_lens(glm::dvec2 pixel) const;
  glm::dvec2 onto_image(glm::dvec2 ray) const;
  Ray intrinsics_ray(glm::dvec2 undistorted) const;

  sdf::CameraSpec spec_;
  int width_, height_;
  glm::dvec3 eye_, right_, up_, forward_;
  double fx_, fy_, cx_, cy_;
};

// What a march through this camera needs beyond its settings: the pixel footprint (eps_mode pixel) and the field's
// declared Lipschitz bound (the marchers that honour L).
inline MarchContext march_context(const Camera& camera, double lipschitz = 1) {
  MarchContext c;
  c.lipschitz = lipschitz;
  c.footprint_at_0 = camera.footprint_at_0();
  c.footprint_slope = camera.footprint_slope();
  return c;
}

// The same for a scene's field: also its perturbation (StepBound::perturbed) and the boxes its zero set and inside
// lie in (clip=bounds), measured from origin as the march measures its points (march_origin).
inline MarchContext march_context(const Camera& camera, const sdf::Scene& scene, glm::dvec3 origin = glm::dvec3(0)) {
  const sdf::FieldInfo field = sdf::derive_info(scene.root, scene.time);
  MarchContext c = march_context(camera, field.lipschitz);
  c.perturbation = field.perturbation_or_plain();
  const std::vector<sdf::Box3> boxes = sdf::bounding_boxes(scene.root, scene.time, MarchContext::kMaxClipBoxes);
  c.clip_box_count = static_cast<int>(boxes.size());
  for (size_t i = 0; i < boxes.size(); ++i) c.clip_boxes[i] = {boxes[i].lo - origin, boxes[i].hi - origin};
  return c;
}

}  // namespace marchcheck::march
