#include "marchcheck/march/camera.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <numbers>

namespace marchcheck::march {

namespace {

constexpr double kDegree = std::numbers::pi / 180;

// Brown-Conrady distortion of normalised image coordinates, and its Jacobian columns (d/dx, d/dy) in closed form.
struct Lens {
  double k1, k2, p1, p2;
  glm::dvec2 distort(glm::dvec2 u) const {
    const double r2 = u.x * u.x + u.y * u.y;
    const double radial = 1 + k1 * r2 + k2 * r2 * r2;
    return {u.x * radial + 2 * p1 * u.x * u.y + p2 * (r2 + 2 * u.x * u.x),
            u.y * radial + p1 * (r2 + 2 * u.y * u.y) + 2 * p2 * u.x * u.y};
  }
  std::pair<glm::dvec2, glm::dvec2> jacobian(glm::dvec2 u) const {
    const double r2 = u.x * u.x + u.y * u.y, radial = 1 + k1 * r2 + k2 * r2 * r2;
    const double dradial = 2 * (k1 + 2 * k2 * r2);  // d radial / d x = dradial * x, likewise for y
    return {glm::dvec2(radial + u.x * dradial * u.x + 2 * p1 * u.y + 6 * p2 * u.x,
                       u.y * dradial * u.x + 2 * p1 * u.x + 2 * p2 * u.y),
            glm::dvec2(u.x * dradial * u.y + 2 * p1 * u.x + 2 * p2 * u.y,
                       radial + u.y * dradial * u.y + 6 * p1 * u.y + 2 * p2 * u.x)};
  }
};

constexpr int kNewtonSteps = 30;
constexpr double kNewtonTolerance = 1e-15;  // |residual|_1 in normalised coordinates

// One Newton step of distort(u) = target: whether it moved u (false once converged, or where it cannot move).
// Written without branches so a loop over many pixels vectorises; both undistortions use it.
struct NewtonStep {
  glm::dvec2 next;
  bool moved;
};
inline NewtonStep newton_step(const Lens& lens, glm::dvec2 target, glm::dvec2 u) {
  const glm::dvec2 r = lens.distort(u) - target;
  const auto [jx, jy] = lens.jacobian(u);
  const double det = jx.x * jy.y - jy.x * jx.y;
  const bool moved = !(std::abs(r.x) + std::abs(r.y) < kNewtonTolerance) & (std::abs(det) > 0);  // no branch
  return {u - glm::dvec2(jy.y * r.x - jy.x * r.y, -jx.y * r.x + jx.x * r.y) / det, moved};
}

Lens lens_of(const sdf::CameraSpec& spec) {
  const sdf::LensCoefficients c = sdf::image_lens(spec);
  return Lens{c.k1, c.k2, c.p1, c.p2};
}

}  // namespace

Camera::Camera(const sdf::CameraSpec& spec, int width, int height) : spec_(spec), width_(width), height_(height) {
  const sdf::CameraFrame frame = sdf::camera_frame(spec);
  eye_ = frame.eye;
  right_ = frame.right;
  up_ = frame.up;
  forward_ = frame.forward;
  if (spec.model == sdf::CameraModel::intrinsics) {
    fx_ = spec.fx;
    fy_ = spec.fy;
    cx_ = spec.cx >= 0 ? spec.cx : width * 0.5;
    cy_ = spec.cy >= 0 ? spec.cy : height * 0.5;
  } else {
    fy_ = fx_ = (spec.fov_full_height ? height : height * 0.5) / std::tan(spec.fov_deg * kDegree * 0.5);
    cx_ = width * 0.5;
    cy_ = height * 0.5;
  }
}

glm::dvec2 Camera::distort(glm::dvec2 u) const {
  // Lens distortion belongs to the intrinsics model only.
  if (spec_.model != sdf::CameraModel::intrinsics) return u;
  return lens_of(spec_).distort(u);
}

glm::dvec2 Camera::undistort(glm::dvec2 d) const {
  if (spec_.model != sdf::CameraModel::intrinsics) return d;
  const Lens lens = lens_of(spec_);
  glm::dvec2 u = d;
  for (int i = 0; i < kNewtonSteps; ++i) {
    const NewtonStep step = newton_step(lens, d, u);
    if (!step.moved) break;
    u = step.next;
  }
  return u;
}

glm::dvec2 Camera::through_lens(glm::dvec2 pixel) const {
  return spec_.lens == sdf::LensConvention::shader ? distort(pixel) : undistort(pixel);
}

glm::dvec2 Camera::onto_image(glm::dvec2 ray) const {
  return spec_.lens == sdf::LensConvention::shader ? undistort(ray) : distort(ray);
}

Ray Camera::intrinsics_ray(glm::dvec2 undistorted) const {
  const glm::dvec3 d = forward_ + right_ * undistorted.x - up_ * undistorted.y;
  return {eye_, spec_.normalize_rays ? glm::normalize(d) : d};
}

void Camera::rays(const double* px, const double* py, int n, Ray* out) const {
  if (spec_.model == sdf::CameraModel::orthographic || spec_.model == sdf::CameraModel::frustum) {
    for (int i = 0; i < n; ++i) out[i] = ray(px[i], py[i]);
    return;
  }
  // ray() for a block of pixels at once, each step a loop over the block that vectorises: through_lens() (the
  // shader's distortion in closed form, or undistortion's Newton steps, each lane taking the same steps as alone and
  // stopping with it), then intrinsics_ray().
  constexpr int kBlock = 64;
  const bool lens = spec_.model == sdf::CameraModel::intrinsics;  // distort() and undistort() pass u on otherwise
  const Lens coefficients = lens_of(spec_);
  for (int base = 0; base < n; base += kBlock) {
    const int m = std::min(kBlock, n - base);
    double tx[kBlock], ty[kBlock], ux[kBlock], uy[kBlock];
    for (int i = 0; i < m; ++i) {
      tx[i] = ux[i] = (px[base + i] - cx_) / fx_;
      ty[i] = uy[i] = (py[base + i] - cy_) / fy_;
    }
    if (lens && spec_.lens == sdf::LensConvention::shader) {
      for (int i = 0; i < m; ++i) {
        const glm::dvec2 d = coefficients.distort({tx[i], ty[i]});
        ux[i] = d.x;
        uy[i] = d.y;
      }
    } else if (lens) {
      std::int64_t moving[kBlock];
      std::fill_n(moving, m, 1);
      for (int step = 0; step < kNewtonSteps; ++step) {
        std::int64_t any = 0;
        for (int i = 0; i < m; ++i) {
          const NewtonStep next = newton_step(coefficients, {tx[i], ty[i]}, {ux[i], uy[i]});
          moving[i] &= static_cast<std::int64_t>(next.moved);
          ux[i] = moving[i] ? next.next.x : ux[i];
          uy[i] = moving[i] ? next.next.y : uy[i];
          any |= moving[i];
        }
        if (!any) break;
      }
    }
    // intrinsics_ray() lane by lane, as glm computes it: d = forward + right x - up y, d * (1 / sqrt(dot(d, d))).
    double dx[kBlock], dy[kBlock], dz[kBlock], scale[kBlock];
    for (int i = 0; i < m; ++i) {
      dx[i] = forward_.x + right_.x * ux[i] - up_.x * uy[i];
      dy[i] = forward_.y + right_.y * ux[i] - up_.y * uy[i];
      dz[i] = forward_.z + right_.z * ux[i] - up_.z * uy[i];
      scale[i] = spec_.normalize_rays ? 1.0 / std::sqrt(dx[i] * dx[i] + dy[i] * dy[i] + dz[i] * dz[i]) : 1.0;
    }
    for (int i = 0; i < m; ++i) out[base + i] = {eye_, glm::dvec3(dx[i] * scale[i], dy[i] * scale[i], dz[i] * scale[i])};
  }
}

Ray Camera::ray(double px, double py) const {
  switch (spec_.model) {
    case sdf::CameraModel::orthographic: {
      const double unit = spec_.ortho_height / height_;
      return {eye_ + right_ * ((px - width_ * 0.5) * unit) - up_ * ((py - height_ * 0.5) * unit), forward_};
    }
    case sdf::CameraModel::frustum: {
      // The four corner rays at unit depth, interpolated bilinearly (as an image effect's vertex shader does).
      const double th = std::tan(spec_.fov_deg * kDegree * 0.5), tw = th * width_ / height_;
      const double u = px / width_, v = py / height_;
      const glm::dvec3 top_left = forward_ - right_ * tw + up_ * th, top_right = forward_ + right_ * tw + up_ * th;
      const glm::dvec3 bottom_left = forward_ - right_ * tw - up_ * th, bottom_right = forward_ + right_ * tw - up_ * th;
      const glm::dvec3 top = glm::mix(top_left, top_right, u), bottom = glm::mix(bottom_left, bottom_right, u);
      return {eye_, glm::normalize(glm::mix(top, bottom, v))};
    }
    default: return intrinsics_ray(through_lens({(px - cx_) / fx_, (py - cy_) / fy_}));
  }
}

std::optional<glm::dvec2> Camera::project(glm::dvec3 world) const {
  const glm::dvec3 v = world - eye_;
  if (spec_.model == sdf::CameraModel::orthographic) {
    const double unit = spec_.ortho_height / height_;
    return glm::dvec2(glm::dot(v, right_) / unit + width_ * 0.5, -glm::dot(v, up_) / unit + height_ * 0.5);
  }
  const double z = glm::dot(v, forward_);
  if (!(z > 0)) return std::nullopt;
  const glm::dvec2 n(glm::dot(v, right_) / z, -glm::dot(v, up_) / z);
  if (spec_.model == sdf::CameraModel::frustum) {
    // Invert the bilinear corner interpolation: at unit depth it is linear in (u, v) for a rectangular frustum.
    const double th = std::tan(spec_.fov_deg * kDegree * 0.5), tw = th * width_ / height_;
    return glm::dvec2((n.x / tw + 1) * 0.5 * width_, (n.y / th + 1) * 0.5 * height_);
  }
  const glm::dvec2 d = onto_image(n);
  return glm::dvec2(fx_ * d.x + cx_, fy_ * d.y + cy_);
}

double Camera::footprint_at_0() const {
  return spec_.model == sdf::CameraModel::orthographic ? 0.5 * spec_.ortho_height / height_ : 0.0;
}

double Camera::footprint_slope() const { return spec_.model == sdf::CameraModel::orthographic ? 0.0 : 0.5 / fy_; }

double Camera::measured_vertical_fov_deg() const {
  if (spec_.model == sdf::CameraModel::orthographic) return 0;
  const glm::dvec3 top = ray(width_ * 0.5, 0).direction, bottom = ray(width_ * 0.5, height_).direction;
  return std::acos(glm::clamp(glm::dot(top, bottom), -1.0, 1.0)) / kDegree;
}

}  // namespace marchcheck::march
