// The hard-case battery: inputs that break marchers (grazing rays, far coordinates, extreme scales, thin
// features, non-Lipschitz fields, NaN rays, broken meshes), each case with what it checks, its pass criterion
// and its numbers. Every case also knows its naive variant (what a marcher without the guard does), and for each
// clause of its criterion a broken variant that fails that clause alone: so no clause can stop checking unseen.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace marchcheck::validation {

struct StabilityOptions {
  // "" runs the marchers as they are; "naive" each case's naive variant (every case should then be unstable);
  // any other name one of a case's own variants (run_stability_case only).
  std::string variant;
  bool full = false;  // the slow sizes (the 1.3M-triangle mesh) instead of the fast defaults
};

// A deliberately broken variant of a case: what it breaks, and the one criterion clause it must fail (empty for
// a naive variant that fails several).
struct StabilityVariant {
  std::string name, breaks, what;
};

struct StabilityCase {
  std::string name;       // dotted and stable, e.g. "grazing.b1e-3"
  std::string checks;     // what it checks
  std::string criterion;  // when it is stable
  std::vector<StabilityVariant> variants;  // the naive one first (named "naive"), then one or more per clause
  std::vector<std::string> clauses;        // the criterion's clauses this run checked, in order
  std::vector<std::string> failed;         // those that failed, and any unmet "needs." precondition
  std::map<std::string, double> metrics;  // outcomes as march::Outcome's number: 0 hit, 1 miss_far, 2 miss_steps,
                                          // 3 inside, 4 invalid
  bool stable = false;
  std::string detail;  // why not, when unstable
};

// The names of every case, in battery order.
std::vector<std::string> stability_case_names();

// Runs one case by name (std::invalid_argument for an unknown case or a variant it does not have).
StabilityCase run_stability_case(const std::string& name, const StabilityOptions& options = {});

// Runs every case.
std::vector<StabilityCase> run_stability(const StabilityOptions& options = {});

}  // namespace marchcheck::validation
