#include "marchcheck/validation/slice.hpp"

#include "marchcheck/validation/certified.hpp"

#include "marchcheck/sdf/interval.hpp"
#include "marchcheck/sdf/lipschitz.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace marchcheck::validation {

namespace {

// Cells per side of the certified grid over the right panel, and the colour that outlines one over L.
constexpr int kCells = 32;
constexpr float kOutline[3] = {1.f, 0.85f, 0.f};

glm::dvec3 point_at(const SlicePlane& plane, double u, double v) {
  glm::dvec3 p;
  p[plane.axis] = plane.value;
  p[(plane.axis + 1) % 3] = u;
  p[(plane.axis + 2) % 3] = v;
  return p;
}

// Inigo Quilez's palette: orange outside, blue inside, darker with distance, banded, the zero contour white.
void distance_colour(double d, double band, double pixel, float* rgb) {
  const glm::dvec3 base = d > 0 ? glm::dvec3(0.9, 0.6, 0.3) : glm::dvec3(0.65, 0.85, 1.0);
  glm::dvec3 c = base * (1 - std::exp(-4 * std::abs(d) / (10 * band)));
  c *= 0.8 + 0.2 * std::cos(2 * std::numbers::pi * d / band);
  if (std::abs(d) < 1.5 * pixel) c = glm::dvec3(1);
  for (int i = 0; i < 3; ++i) rgb[i] = static_cast<float>(std::clamp(c[i], 0.0, 1.0));
}

// |grad f| - 1: grey at 0, towards red above (steeper than a distance), blue below; 1 at full colour.
void slope_colour(double excess, float* rgb) {
  const double t = std::clamp(std::abs(excess), 0.0, 1.0);
  const glm::dvec3 towards = excess > 0 ? glm::dvec3(0.9, 0.15, 0.1) : glm::dvec3(0.15, 0.3, 0.9);
  const glm::dvec3 c = glm::mix(glm::dvec3(0.5), towards, t);
  for (int i = 0; i < 3; ++i) rgb[i] = static_cast<float>(c[i]);
}

}  // namespace

SlicePlane parse_plane(const std::string& text) {
  const std::string axes = "xyz";
  if (text.size() < 3 || axes.find(text[0]) == std::string::npos || text[1] != '=')
    throw std::invalid_argument("--plane '" + text + "': expected x=VALUE, y=VALUE or z=VALUE");
  SlicePlane p;
  p.axis = static_cast<int>(axes.find(text[0]));
  const char* end = text.data() + text.size();
  const auto [last, ec] = std::from_chars(text.data() + 2, end, p.value);
  if (ec != std::errc() || last != end || !std::isfinite(p.value))
    throw std::invalid_argument("--plane '" + text + "': '" + text.substr(2) + "' is not a finite number");
  return p;
}

SlicePlane default_plane(const sdf::Scene& scene) { return {1, scene.camera.target.y}; }

Slice slice(const sdf::Scene& scene, SlicePlane plane, int width, int height) {
  const sdf::Tape tape = sdf::compile(scene.root, scene.time);
  const double declared = sdf::derive_info(scene.root, scene.time).lipschitz;
  Slice out;
  const glm::dvec3 target = scene.camera.target;
  out.centre_u = target[(plane.axis + 1) % 3];
  out.centre_v = target[(plane.axis + 2) % 3];
  out.half = std::max(0.5 * glm::length(scene.camera.position - target), 1e-3);
  out.image = march::Image(2 * width, height, 3);
  const double side = 2 * out.half, pixel = side / std::max(width, height);
  auto uv = [&](double px, double py) {
    return glm::dvec2(out.centre_u - out.half + side * px / width, out.centre_v + out.half - side * py / height);
  };
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const glm::dvec2 w = uv(x + 0.5, y + 0.5);
      const glm::dvec3 p = point_at(plane, w.x, w.y);
      const sdf::Dual<double> f = sdf::evaluate(tape, sdf::seeded(p));
      distance_colour(f.v, side / 10, pixel, out.image.at(x, y));
      slope_colour(glm::length(f.d) - 1, out.image.at(width + x, y));
    }
  out.certified = sdf::interval_supported(tape);
  if (!out.certified) return out;
  // Each square of the grid as a box of zero thickness across the plane: its certified bound on |grad f|.
  for (int j = 0; j < kCells; ++j)
    for (int i = 0; i < kCells; ++i) {
      const int x0 = i * width / kCells, x1 = (i + 1) * width / kCells - 1;
      const int y0 = j * height / kCells, y1 = (j + 1) * height / kCells - 1;
      const glm::dvec2 a = uv(x0, y1 + 1), b = uv(x1 + 1, y0);
      glm::vec<3, sdf::Interval> box;
      box[plane.axis] = sdf::Interval(plane.value);
      box[(plane.axis + 1) % 3] = sdf::Interval(a.x, b.x);
      box[(plane.axis + 2) % 3] = sdf::Interval(a.y, b.y);
      const double bound = sdf::evaluate(tape, sdf::seeded(box)).n;
      ++out.cells;
      out.steepest_bound = std::max(out.steepest_bound, bound);
      if (!(bound > kLipschitzTolerance * declared)) continue;
      ++out.cells_over;
      for (int x = x0; x <= x1; ++x)
        for (const int y : {y0, y1}) std::copy_n(kOutline, 3, out.image.at(width + x, y));
      for (int y = y0; y <= y1; ++y)
        for (const int x : {x0, x1}) std::copy_n(kOutline, 3, out.image.at(width + x, y));
    }
  return out;
}

}  // namespace marchcheck::validation
