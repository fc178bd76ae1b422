// Convergence studies: how accuracy and cost move with the step limit and the hit threshold, and how many
// steps a grazing ray needs against the pi * sqrt(2R / b) law.
#pragma once

#include "marchcheck/march/marcher.hpp"
#include "marchcheck/sdf/scene.hpp"

#include <vector>

namespace marchcheck::validation {

struct ConvergenceRow {
  double parameter;      // the max_steps or hit_eps of this row
  double decided;        // fraction of rays ending hit or miss_far
  double t_err_p99;      // over rays the reference and the march both hit
  double t_err_max;
  double evals_per_ray;  // primary march only
};

// The scene's sampled rays marched at each max_steps (everything else as declared).
std::vector<ConvergenceRow> steps_study(const sdf::Scene& scene, const std::vector<int>& max_steps,
                                        int rays_x = 48, int rays_y = 27);
// The same at each hit_eps.
std::vector<ConvergenceRow> eps_study(const sdf::Scene& scene, const std::vector<double>& hit_eps,
                                      int rays_x = 48, int rays_y = 27);

struct GrazingRow {
  double clearance;  // b: the ray passes the unit sphere at 1 + b from its centre
  int steps;         // steps the sphere tracer needed to get past (miss_far)
  double law;        // pi * sqrt(2 R / b)
  march::Outcome outcome;  // miss_far when it got past; miss_steps when max_steps ran out first
};
// Double-precision sphere tracing past a unit sphere (hit_eps below every clearance), at most max_steps each.
std::vector<GrazingRow> grazing_study(const std::vector<double>& clearances, int max_steps = 1 << 24);
// The study's settings for clearance b (hit_eps b / 1000, so that any hit is wrong), and its one ray.
march::MarchSettings grazing_settings(double clearance, int max_steps);
GrazingRow grazing_row(double clearance, const march::MarchSettings& settings);

}  // namespace marchcheck::validation
