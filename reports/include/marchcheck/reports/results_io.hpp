// Result files: flat dotted metrics as JSON (written with files::write_bytes_atomically).
#pragma once

#include "marchcheck/validation/stability.hpp"
#include "marchcheck/validation/sweep.hpp"
#include "marchcheck/validation/validate.hpp"

#include <map>
#include <string>
#include <vector>

namespace marchcheck::reports {

// {"metric.name": value, ...} sorted by name; non-finite values are written as null.
std::string metrics_json(const std::map<std::string, double>& metrics);

// {"kind": "validate", "results": [{scene, defects, pass, checks: [{name, value, limit, pass, limit_source,
// why}], metrics: {...}}]}
std::string validate_json(const std::vector<validation::SceneResult>& results);

// {"kind": "sweep", scene, axes, error_metric, targets, cheapest_meeting, points: [{settings, pass,
// pareto_evals, pareto_seconds, meets_targets, metrics}]}
std::string sweep_json(const validation::SweepResult& result);
// {"kind": "stability", variant, full, stable, cases: [{name, checks, criterion, clauses, variants: [{name, breaks,
// what}], stable, failed, detail, metrics}]}
std::string stability_json(const std::vector<validation::StabilityCase>& cases, const validation::StabilityOptions& options);

// One row per combination: its settings, pass, the front marks, then every metric any point has.
std::string sweep_csv(const validation::SweepResult& result);

}  // namespace marchcheck::reports
