// The hard-case battery: inputs that break marchers (grazing rays, far coordinates, extreme scales, thin
// features, non-Lipschitz fields, NaN rays, broken meshes), each case with what it checks, its pass criterion
// and its numbers. Every case also knows its naive variant (what a marcher without the guard does); running the
// battery on the naive variants shows each case can fail.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace marchcheck::validation {

struct StabilityOptions {
  bool naive = false;  // run each case against its naive variant instead (every case should then be unstable)
  bool full = false;   // the slow sizes (the 1M-triangle mesh) instead of the fast defaults
};

struct StabilityCase {
  std::string name;       // dotted and stable, e.g. "grazing.b1e-3"
  std::string checks;     // what it checks
  std::string criterion;  // when it is stable
  std::string naive;      // the naive variant StabilityOptions::naive runs
  std::map<std::string, double> metrics;  // outcomes as march::Outcome's number: 0 hit, 1 miss_far, 2 miss_steps,
                                          // 3 inside, 4 invalid
  bool stable = false;
  std::string detail;  // why not, when unstable
};

// The names of every case, in battery order.
std::vector<std::string> stability_case_names();

// Runs one case by name (std::invalid_argument for an unknown name).
StabilityCase run_stability_case(const std::string& name, const StabilityOptions& options = {});

// Runs every case.
std::vector<StabilityCase> run_stability(const StabilityOptions& options = {});

}  // namespace marchcheck::validation
