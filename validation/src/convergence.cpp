#include "marchcheck/validation/convergence.hpp"

#include "marchcheck/march/camera.hpp"
#include "marchcheck/march/render.hpp"
#include "marchcheck/validation/reference.hpp"
#include "marchcheck/validation/statistics.hpp"
#include "marchcheck/validation/validate.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace marchcheck::validation {

namespace {

// The scene's rays marched as validate marches them (scene_subject: precision and miss reading included).
ConvergenceRow study_row(const sdf::Scene& scene, double parameter, int rays_x, int rays_y) {
  const Subject subject = scene_subject(scene);
  const Reference ref(scene.intended ? *scene.intended : scene.root, scene.time);
  const march::Camera camera(scene.camera, scene.width, scene.height);
  const double max_dist = std::isfinite(scene.march.max_dist) ? scene.march.max_dist : 1e6;
  std::vector<double> errors;
  int decided = 0, rays = 0;
  double evals = 0;
  for (int j = 0; j < rays_y; ++j)
    for (int i = 0; i < rays_x; ++i) {
      const march::Ray ray = camera.ray((i + 0.5) * scene.width / rays_x, (j + 0.5) * scene.height / rays_y);
      const double len = glm::length(ray.direction);
      const MarchedRay rec = subject.march(ray.origin, ray.direction);
      ++rays;
      evals += rec.evals;
      if (rec.decided()) ++decided;
      if (rec.outcome != march::Outcome::hit) continue;
      const ReferenceHit rh = ref.first_hit(ray.origin, ray.direction / len, max_dist);
      if (rh.hit) errors.push_back(std::abs(rec.t * len - rh.t));
    }
  const double worst = errors.empty() ? 0 : *std::max_element(errors.begin(), errors.end());
  return {parameter, static_cast<double>(decided) / rays, percentile(errors, 0.99), worst, evals / rays};
}

}  // namespace

std::vector<ConvergenceRow> steps_study(const sdf::Scene& scene, const std::vector<int>& max_steps, int rays_x,
                                        int rays_y) {
  std::vector<ConvergenceRow> rows;
  for (int n : max_steps) {
    sdf::Scene s = scene;
    s.march.max_steps = n;
    rows.push_back(study_row(s, n, rays_x, rays_y));
  }
  return rows;
}

std::vector<ConvergenceRow> eps_study(const sdf::Scene& scene, const std::vector<double>& hit_eps, int rays_x,
                                      int rays_y) {
  std::vector<ConvergenceRow> rows;
  for (double e : hit_eps) {
    sdf::Scene s = scene;
    s.march.hit_eps = e;
    rows.push_back(study_row(s, e, rays_x, rays_y));
  }
  return rows;
}

march::MarchSettings grazing_settings(double clearance, int max_steps) {
  march::MarchSettings s;
  s.max_steps = max_steps;
  s.max_dist = 10;
  s.hit_eps = clearance * 1e-3;
  return s;
}

GrazingRow grazing_row(double clearance, const march::MarchSettings& settings) {
  const sdf::Tape unit = sdf::compile(sdf::sphere(1));
  // From far enough that the approach is straight, to just past the sphere's far side.
  const auto rec = march::march<double>(march::TapeField{&unit}, glm::dvec3(0, 1 + clearance, -5), glm::dvec3(0, 0, 1),
                                        settings, {});
  return {clearance, rec.steps, std::numbers::pi * std::sqrt(2 / clearance), rec.outcome};
}

std::vector<GrazingRow> grazing_study(const std::vector<double>& clearances, int max_steps) {
  std::vector<GrazingRow> rows;
  for (double b : clearances) rows.push_back(grazing_row(b, grazing_settings(b, max_steps)));
  return rows;
}

}  // namespace marchcheck::validation
