// Normals at sharp features: box edges and corners, and the seam of two united spheres.
#include "battery.hpp"

#include "marchcheck/march/normals.hpp"

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

namespace marchcheck::validation::stability {

namespace {

// ---- normals at sharp features ----

// The angle from n to the cone of the sides' normals (their non-negative combinations; 0 inside it). On a sharp
// feature the gradient is undefined and every normal in that cone is a right answer.
double cone_angle_deg(dvec3 n, const std::vector<dvec3>& sides) {
  double best = 180;
  for (const dvec3& s : sides) best = std::min(best, angle_deg(n, s));
  for (size_t i = 0; i < sides.size(); ++i)
    for (size_t j = i + 1; j < sides.size(); ++j) {  // n projected onto the plane of two sides, if between them
      const dvec3 a = sides[i], b = sides[j];
      const double aa = glm::dot(a, a), ab = glm::dot(a, b), bb = glm::dot(b, b), det = aa * bb - ab * ab;
      const double alpha = (glm::dot(n, a) * bb - glm::dot(n, b) * ab) / det;
      const double beta = (glm::dot(n, b) * aa - glm::dot(n, a) * ab) / det;
      if (det > 0 && alpha >= 0 && beta >= 0 && alpha + beta > 0) best = std::min(best, angle_deg(n, alpha * a + beta * b));
    }
  if (sides.size() == 3) {  // inside the cone of three
    const glm::dmat3 basis(sides[0], sides[1], sides[2]);
    const dvec3 c = glm::inverse(basis) * n;
    if (glm::determinant(basis) != 0 && c.x >= 0 && c.y >= 0 && c.z >= 0) best = 0;
  }
  return best;
}

// Central-difference normals at points on a sharp feature: finite, unit, and inside the feature's normal cone
// (within a degree); at points 2 normal_eps off it, within a degree of their side's normal.
void sharp_normals(Run& r, const sdf::Node& node, const std::vector<dvec3>& on, const std::vector<dvec3>& off,
                   const std::function<std::vector<dvec3>(dvec3)>& sides) {
  const sdf::Tape tape = sdf::compile(node);
  const TapeField field{&tape};
  const float eps = r.as("wide_eps") ? 0.05f : 1e-3f;  // wide_eps: 50 normal_eps, wider than the gap to the feature
  const auto gradient = [&](vec3 q, float e) {
    return vec3(field(q + vec3(e, 0, 0)) - field(q - vec3(e, 0, 0)), field(q + vec3(0, e, 0)) - field(q - vec3(0, e, 0)),
                field(q + vec3(0, 0, e)) - field(q - vec3(0, 0, e))) / (2 * e);
  };
  const auto normal = [&](dvec3 p, const std::vector<dvec3>& at, bool on_feature) {
    const vec3 q(p);
    if (r.naive()) return dvec3(glm::normalize(gradient(q, 1e-9f)));  // epsilon under float's spacing: 0 / 0
    if (r.as("unnormalised")) return dvec3(gradient(q, eps));
    if (r.as("inward_on_feature") && on_feature) {  // a wrong tie-break where the sides meet: into the solid
      dvec3 sum(0);
      for (const dvec3& s : at) sum += glm::normalize(s);
      return -glm::normalize(sum);
    }
    return dvec3(march::estimate_normal(field, q, sdf::NormalMethod::central, eps).n);
  };
  int bad = 0;
  // On the feature: the angle to its normal cone; beside it: to the nearest side's normal.
  const auto worst = [&](const std::vector<dvec3>& pts, bool on_feature) {
    double w = 0;
    for (const dvec3& p : pts) {
      const std::vector<dvec3> at = sides(p);
      const dvec3 n = normal(p, at, on_feature);
      if (!std::isfinite(n.x + n.y + n.z) || std::abs(glm::length(n) - 1) > 1e-5) ++bad;
      if (!std::isfinite(n.x + n.y + n.z) || glm::dot(n, n) == 0) continue;  // no direction to judge
      double angle = on_feature ? cone_angle_deg(n, at) : 180;
      if (!on_feature)
        for (const dvec3& s : at) angle = std::min(angle, angle_deg(n, s));
      w = std::max(w, angle);
    }
    return w;
  };
  const double on_err = worst(on, true), off_err = worst(off, false);
  r.m["on_feature.cone_angle_max_deg"] = on_err;
  r.m["off_feature.angle_max_deg"] = off_err;
  r.m["normals_not_unit"] = bad;
  r.require("finite_unit", bad == 0, std::to_string(bad) + " normals NaN, infinite or not unit length");
  r.require("on_feature", on_err <= 1, "on the feature: " + num(on_err) + " degrees outside the normal cone");
  r.require("off_feature", off_err <= 1, "2 normal_eps off the feature: " + num(off_err) + " degrees off the side's normal");
}

void box_normals(Run& r, bool corner) {
  std::vector<dvec3> on, off;
  for (int i = 0; i <= 10; ++i) {
    const double y = corner ? 1 : -0.5 + 0.1 * i;
    on.push_back(corner ? dvec3(1, 1, 1) * (1 - 1e-8 * i) : dvec3(1, y, 1));
    off.push_back(corner ? dvec3(1 - 2e-3 - 1e-2 * i, 1 - 2e-3, 1) : dvec3(1 - 2e-3 - 1e-2 * i, y, 1));
  }
  const auto sides = [](dvec3 p) {
    std::vector<dvec3> s;
    if (p.x > 1 - 1e-6) s.push_back({1, 0, 0});
    if (p.y > 1 - 1e-6) s.push_back({0, 1, 0});
    if (p.z > 1 - 1e-6) s.push_back({0, 0, 1});
    return s;
  };
  sharp_normals(r, sdf::box({1, 1, 1}), on, off, sides);
}

void seam_normals(Run& r, const StabilityOptions&) {
  // Two unit spheres at x = -0.5 and 0.5: the seam is the circle x = 0, radius sqrt(0.75).
  const sdf::Node node = sdf::unite({sdf::translate({-0.5, 0, 0}, sdf::sphere(1)), sdf::translate({0.5, 0, 0}, sdf::sphere(1))});
  std::vector<dvec3> on, off;
  for (int i = 0; i < 12; ++i) {
    const double a = 2 * kPi * i / 12, rr = std::sqrt(0.75);
    on.push_back({0, rr * std::cos(a), rr * std::sin(a)});
    const dvec3 q = dvec3(0.5, 0, 0) + glm::normalize(dvec3(-0.5 + 0.01, rr * std::cos(a), rr * std::sin(a)));
    off.push_back(q);
  }
  // On the seam: both spheres' normals (60 degrees apart); beside it, the nearer one's is the closer.
  const auto sides = [](dvec3 p) { return std::vector<dvec3>{p - dvec3(-0.5, 0, 0), p - dvec3(0.5, 0, 0)}; };
  sharp_normals(r, node, on, off, sides);
}

}  // namespace

void add_normal_cases(Battery& b) {
  const Variants feature_variants = {{"naive", "", "raw gradient normalised (eps under float spacing)"},
                                     {"unnormalised", "finite_unit", "the central difference not normalised"},
                                     {"inward_on_feature", "on_feature", "on the feature, a normal into the solid"},
                                     {"wide_eps", "off_feature", "normal_eps 0.05, wider than the gap to the feature"}};
  b.add("normal.box_edge", "central-difference normals on and beside a box edge",
        "finite unit; on the edge inside its faces' normal cone (within 1 degree), "
        "beside it within 1 degree of the face",
        feature_variants, [](Run& r, const StabilityOptions&) { box_normals(r, false); });
  b.add("normal.box_corner", "central-difference normals on and beside a box corner",
        "finite unit; on the corner inside its faces' normal cone (within 1 degree), "
        "beside it within 1 degree of the face",
        feature_variants, [](Run& r, const StabilityOptions&) { box_normals(r, true); });
  b.add("normal.csg_seam", "normals on and beside the seam of two united spheres",
        "finite unit; on the seam between the spheres' normals (within 1 degree), "
        "beside it within 1 degree of the nearer",
        feature_variants, seam_normals);
}

}  // namespace marchcheck::validation::stability
