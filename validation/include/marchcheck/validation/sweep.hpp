// Parameter sweeps: every combination of the given settings, each with its accuracy (the validate metrics)
// and its cost (evaluations per pixel, exact; seconds, the median of repeated renders), and the Pareto front
// of error against cost.
#pragma once

#include "marchcheck/sdf/scene.hpp"
#include "marchcheck/validation/shard.hpp"
#include "marchcheck/validation/validate.hpp"

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace marchcheck::validation {

// An axis varies one setting, or several that only make sense together (a linked axis: "eps_mode:hit_eps", each
// value one text per key, "relative:1.5e-7"): keys and values joined by ':'.
struct SweepAxis {
  std::string key;                  // keys sdf::apply_setting accepts, joined by ':'
  std::vector<std::string> values;  // as text, applied in order
};
// "KEY=V1,V2,..." or "K1:K2=A1:A2,B1:B2,..."; throws sdf::SceneError naming the argument when it is malformed.
SweepAxis parse_sweep_axis(const std::string& text);
// The settings one axis value stands for, key by key; throws sdf::SceneError when a value has not one text per key.
std::vector<std::pair<std::string, std::string>> linked_settings(const std::string& key, const std::string& value);
// Applies one axis value (linked_settings) to the scene.
void apply_sweep_setting(sdf::Scene& scene, const std::string& key, const std::string& value);

// METRIC=VALUE: a combination meets the target when its metric is at most VALUE.
struct SweepTarget {
  std::string metric;
  double value = 0;
};
SweepTarget parse_sweep_target(const std::string& text);
// "METRIC=NUMBER" with a finite number, or nothing; shared by every option of that shape.
std::optional<SweepTarget> parse_metric_number(const std::string& text);

struct SweepOptions {
  std::string error_metric = "image.rms";  // the error axis of the Pareto front
  int repeat = 3;                          // timed renders per combination; seconds is their median
  int render_width = 640;                  // width of the timed render (the scene's own when smaller)
  std::vector<SweepTarget> targets;
  ValidateOptions validate;
  std::function<void(size_t done, size_t total)> progress;  // total: the combinations this shard holds
  Shard shard;  // measure only these combinations; the fronts and the cheapest wait for the merge (finish_sweep)
};

struct SweepPoint {
  size_t index = 0;  // in the cartesian product, which fixes the order of points in every result file
  std::vector<std::pair<std::string, std::string>> settings;  // key, value in axis order
  std::map<std::string, double> metrics;  // validate's metrics; cost.* from the timed render
  bool pass = false;                      // every check passed
  bool pareto_evals = false;              // no other point has both less error and fewer evaluations
  bool pareto_seconds = false;            // the same against seconds
  bool meets_targets = false;
};

struct SweepResult {
  std::string scene;
  std::vector<SweepAxis> axes;
  std::string error_metric;
  std::vector<SweepTarget> targets;
  std::vector<SweepPoint> points;          // the cartesian product, the last axis varying fastest (a shard: its own)
  std::optional<size_t> cheapest_meeting;  // fewest evaluations among the points meeting every target
};

// The number of combinations of the axes.
size_t combination_count(const std::vector<SweepAxis>& axes);

// Throws sdf::SceneError when a key or value does not apply to the scene (before any work is done). With a shard,
// the result holds that shard's points, measured but not finished. Keeps freed memory for the rest of the process
// (march::keep_freed_memory), so that every combination's renders are timed alike.
SweepResult sweep(const sdf::Scene& scene, const std::vector<SweepAxis>& axes, const SweepOptions& options = {});

// Every combination of the axes (the last varying fastest) that the options' shard holds, measured by `measure`
// (given the point with its settings: it fills metrics, cost.evals_per_pixel and cost.seconds among them, and
// pass), then, when the shard is the whole, finished: what sweep does for a scene's own settings, and what a sweep
// of anything else (a user's shader parameters) does too.
SweepResult sweep_combinations(const std::string& name, const std::vector<SweepAxis>& axes,
                               const SweepOptions& options, const std::function<void(SweepPoint&)>& measure);
// What depends on every point, computed once all are there (in one process or after a merge) and in index order:
// which meet the targets, the Pareto fronts (no other point has both less error and less cost; points without the
// error metric are never on them) and the cheapest meeting the targets.
void finish_sweep(SweepResult& result);
// The fronts alone: marks which points no other point dominates on (error, cost).
void mark_pareto(std::vector<SweepPoint>& points, const std::string& error_metric);

// The seed's own settings beaten: a sweep of the known levers around the scene's settings (its marcher and the
// relaxed one, the secant refinement, the hit threshold with its mode (absolute from a tenth to ten times the
// seed's, relative at 1.5 units in the last place of t), clipping to the field's bounds,
// and on a field that declares a perturbation the perturbed step bound), then a finer sweep of the continuous
// levers about the grid's cheapest point at the seed's accuracy (refine_levers), and, among the points of both that
// pass every check, the cheapest at the seed's hit accuracy and the most accurate at no more than the seed's cost.
// Accuracy: hit.t_err_p99; cost: cost.evals_per_pixel. Targets: 0.6 of the seed's cost, 10 times its accuracy.
struct SeedBeaten {
  std::string scene;
  SweepResult sweep;    // the levers' grid; its first point is the seed's own settings
  SweepResult refined;  // about the grid's cheapest, its first point (none when the grid has no cheapest)
  std::optional<size_t> cheapest;       // fewest evaluations with an error no larger than the seed's
  std::optional<size_t> most_accurate;  // smallest error with no more evaluations than the seed's
  static constexpr double kCostTarget = 0.6, kAccuracyTarget = 10;
  const SweepPoint& seed() const { return sweep.points.front(); }
  // Point i of the grid then of the refinement, as cheapest and most_accurate count them.
  const SweepPoint& point(size_t i) const;
  size_t point_count() const { return sweep.points.size() + refined.points.size(); }
  double cost_ratio() const;      // the cheapest's evaluations over the seed's (infinity: none found)
  double accuracy_gain() const;   // the seed's error over the most accurate's (0: none found)
};
SeedBeaten beat_the_seed(const sdf::Scene& scene, const SweepOptions& options);
// The axes beat_the_seed sweeps, each starting with the scene's own value.
std::vector<SweepAxis> seed_levers(const sdf::Scene& scene);
// The finer sweep about a point of the grid: each of its settings held, but the hit threshold (its own, then 1.4 and
// 2 times it: between the grid's steps of about 3) and, when it marches relaxed, the over-relaxation factor (the
// scene's, then 1.1, 1.3 and 1.8). The grid's levers are on or off; these two are continuous, and where the cheapest
// lies between the grid's values is a matter of degree (measured on crum-lattice: relaxation 1.1 at 2 times the
// threshold costs 6% less than the grid's cheapest at the same accuracy).
std::vector<SweepAxis> refine_levers(const sdf::Scene& scene, const SweepPoint& about);
// The choices of beat_the_seed among a sweep's points (the first the seed's), for tests of the rule alone.
void choose_beaten(SeedBeaten& beaten);

}  // namespace marchcheck::validation
