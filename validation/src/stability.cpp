// The hard-case battery in order, and running its cases by name. The cases, each registered beside its body,
// live in stability/, one file per family.
#include "marchcheck/validation/stability.hpp"

#include "stability/battery.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace marchcheck::validation {

namespace {

using stability::Entry;
using stability::Run;

// The families in the order the tests and the report read the cases in.
std::vector<Entry> make_battery() {
  stability::Battery b;
  stability::add_grazing_and_start_cases(b);
  stability::add_shadow_cases(b);
  stability::add_far_and_scale_cases(b);
  stability::add_thin_cases(b);
  stability::add_normal_cases(b);
  stability::add_lipschitz_and_mandelbulb_cases(b);
  stability::add_input_cases(b);
  stability::add_mesh_cases(b);
  return std::move(b.entries);
}

const std::vector<Entry>& battery() {
  static const std::vector<Entry> b = make_battery();
  return b;
}

}  // namespace

std::vector<std::string> stability_case_names() {
  std::vector<std::string> names;
  for (const auto& e : battery()) names.push_back(e.name);
  return names;
}

StabilityCase run_stability_case(const std::string& name, const StabilityOptions& options) {
  for (const auto& e : battery()) {
    if (e.name != name) continue;
    if (!options.variant.empty() &&
        std::none_of(e.variants.begin(), e.variants.end(), [&](const auto& v) { return v.name == options.variant; }))
      throw std::invalid_argument("stability case '" + name + "' has no variant named '" + options.variant + "'");
    StabilityCase c{e.name, e.checks, e.criterion, e.variants, {}, {}, {}, false, ""};
    Run run{c.metrics, options.variant, {}, {}, ""};
    e.run(run, options);
    for (const auto& [k, v] : c.metrics)
      if (std::isnan(v)) run.needs("numbers", false, "metric " + k + " is NaN");
    c.clauses = run.clauses;
    c.failed = run.failed;
    c.stable = run.ok();
    c.detail = run.why;
    return c;
  }
  throw std::invalid_argument("no stability case named '" + name + "'");
}

std::vector<StabilityCase> run_stability(const StabilityOptions& options) {
  std::vector<StabilityCase> out;
  for (const auto& e : battery()) out.push_back(run_stability_case(e.name, options));
  return out;
}

}  // namespace marchcheck::validation
