// Regression comparison of two result files (`validate` or `sweep` JSON): metric by metric, what got better
// and what got worse beyond its tolerance.
#pragma once

#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace marchcheck::reports {

struct ResultFileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// One value of a result file, keyed "<scene>: <metric>" (validate) or "<scene> [k=v, ...]: <metric>" (sweep);
// a check's verdict is "<scene>: check <name>" with value 1 (pass) or 0 (fail).
struct FlatResults {
  std::string kind;  // "validate" or "sweep"
  std::map<std::string, double> values;  // NaN where the file has null
};
// Throws ResultFileError naming the source and what is wrong.
FlatResults flatten_results(const std::string& json_text, const std::string& source);

// "METRIC=REL": relative tolerance for a metric name, or for every metric starting with a prefix ("cost.*", "*").
struct Tolerance {
  std::string pattern;
  double relative = 0;
};
Tolerance parse_tolerance(const std::string& text);  // throws ResultFileError

enum class Direction { lower_is_better, higher_is_better, informational };
// Errors, counts and costs are better lower, PSNR higher; sample counts, declared and measured constants and
// wall time (unless a tolerance names it) are informational.
Direction direction_of(const std::string& metric, bool has_explicit_tolerance);

enum class Verdict { same, better, worse_within_tolerance, regression, informational, missing, added };
const char* to_string(Verdict verdict);

struct MetricChange {
  std::string key;
  std::optional<double> baseline, current;
  double tolerance = 0;
  Verdict verdict = Verdict::same;
};

struct Comparison {
  std::vector<MetricChange> changes;  // every key of either file, in key order
  size_t count(Verdict verdict) const;
  bool regression() const { return count(Verdict::regression) + count(Verdict::missing) > 0; }
};

// Default relative tolerance: deterministic metrics are compared to 1e-6 (float noise from a different
// summation order), with an absolute floor of 1e-12 so that a zero baseline tolerates only rounding.
constexpr double kDefaultTolerance = 1e-6;

Comparison compare_results(const FlatResults& baseline, const FlatResults& current,
                           const std::vector<Tolerance>& tolerances);

}  // namespace marchcheck::reports
