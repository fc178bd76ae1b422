#include "marchcheck/reports/compare.hpp"

#include "marchcheck/validation/sweep.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

namespace marchcheck::reports {

namespace {

constexpr double kAbsoluteFloor = 1e-12;
constexpr const char* kCheckPrefix = "check ";

double number_at(const nlohmann::json& v, const std::string& where) {
  if (v.is_null()) return std::numeric_limits<double>::quiet_NaN();
  if (!v.is_number()) throw ResultFileError(where + ": expected a number or null");
  return v.get<double>();
}

const nlohmann::json& member(const nlohmann::json& object, const char* name, const std::string& where) {
  if (!object.is_object() || !object.contains(name)) throw ResultFileError(where + ": missing \"" + name + "\"");
  return object.at(name);
}

void add_metrics(FlatResults& flat, const std::string& prefix, const nlohmann::json& metrics, const std::string& where) {
  if (!metrics.is_object()) throw ResultFileError(where + ": expected an object of metrics");
  for (const auto& [name, value] : metrics.items()) flat.values[prefix + name] = number_at(value, where + "." + name);
}

std::string metric_of(const std::string& key) { return key.substr(key.rfind(": ") + 2); }

}  // namespace

FlatResults flatten_results(const std::string& json_text, const std::string& source) {
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(json_text);
  } catch (const nlohmann::json::parse_error& e) {
    throw ResultFileError(source + ": not JSON: " + e.what());
  }
  FlatResults flat;
  const auto& kind = member(doc, "kind", source);
  flat.kind = kind.is_string() ? kind.get<std::string>() : "";
  if (flat.kind == "validate") {
    const auto& results = member(doc, "results", source);
    if (!results.is_array()) throw ResultFileError(source + ": results: expected an array");
    for (size_t i = 0; i < results.size(); ++i) {
      const std::string where = source + ": results[" + std::to_string(i) + "]";
      const auto& scene = member(results[i], "scene", where);
      if (!scene.is_string()) throw ResultFileError(where + ".scene: expected a string");
      const std::string prefix = scene.get<std::string>() + ": ";
      add_metrics(flat, prefix, member(results[i], "metrics", where), where + ".metrics");
      for (const auto& check : member(results[i], "checks", where)) {
        const auto& name = member(check, "name", where + ".checks");
        const auto& pass = member(check, "pass", where + ".checks");
        if (!name.is_string() || !pass.is_boolean()) throw ResultFileError(where + ".checks: expected name and pass");
        flat.values[prefix + kCheckPrefix + name.get<std::string>()] = pass.get<bool>() ? 1 : 0;
      }
    }
  } else if (flat.kind == "sweep") {
    const auto& scene = member(doc, "scene", source);
    if (!scene.is_string()) throw ResultFileError(source + ": scene: expected a string");
    const auto& points = member(doc, "points", source);
    if (!points.is_array()) throw ResultFileError(source + ": points: expected an array");
    for (size_t i = 0; i < points.size(); ++i) {
      const std::string where = source + ": points[" + std::to_string(i) + "]";
      std::string settings;
      for (const auto& [k, v] : member(points[i], "settings", where).items())
        settings += (settings.empty() ? "" : ", ") + k + "=" + (v.is_string() ? v.get<std::string>() : v.dump());
      add_metrics(flat, scene.get<std::string>() + " [" + settings + "]: ", member(points[i], "metrics", where),
                  where + ".metrics");
    }
  } else {
    throw ResultFileError(source + ": \"kind\" must be \"validate\" or \"sweep\" (a file written by marchcheck "
                          "validate --json or sweep --json)");
  }
  return flat;
}

Tolerance parse_tolerance(const std::string& text) {
  if (const auto parsed = validation::parse_metric_number(text); parsed && parsed->value >= 0)
    return Tolerance{parsed->metric, parsed->value};
  throw ResultFileError("--tolerance " + text + ": expected METRIC=REL with REL >= 0 (METRIC may end in *)");
}

Direction direction_of(const std::string& metric, bool has_explicit_tolerance) {
  static const std::set<std::string> informational = {"hit.rays",           "shadow.samples",
                                                      "normal.edge_samples", "hit.grazing_excluded",
                                                      "sdf.lipschitz_declared", "sdf.lipschitz_measured"};
  if (informational.count(metric)) return Direction::informational;
  const bool seconds = metric.size() >= 7 && metric.compare(metric.size() - 7, 7, "seconds") == 0;
  if (seconds && !has_explicit_tolerance) return Direction::informational;  // wall time differs across machines
  if (metric == "image.psnr" || metric.rfind(kCheckPrefix, 0) == 0) return Direction::higher_is_better;
  return Direction::lower_is_better;
}

const char* to_string(Verdict verdict) {
  switch (verdict) {
    case Verdict::same: return "same";
    case Verdict::better: return "better";
    case Verdict::worse_within_tolerance: return "worse (within tolerance)";
    case Verdict::regression: return "REGRESSION";
    case Verdict::informational: return "changed (informational)";
    case Verdict::missing: return "MISSING from current";
    case Verdict::added: return "new in current";
  }
  return "?";
}

size_t Comparison::count(Verdict verdict) const {
  return static_cast<size_t>(
      std::count_if(changes.begin(), changes.end(), [&](const MetricChange& c) { return c.verdict == verdict; }));
}

Comparison compare_results(const FlatResults& baseline, const FlatResults& current,
                           const std::vector<Tolerance>& tolerances) {
  if (baseline.kind != current.kind)
    throw ResultFileError("cannot compare a " + baseline.kind + " result with a " + current.kind + " result");
  std::set<std::string> keys;
  for (const auto& [k, v] : baseline.values) keys.insert(k);
  for (const auto& [k, v] : current.values) keys.insert(k);
  Comparison comparison;
  for (const auto& key : keys) {
    MetricChange change;
    change.key = key;
    const std::string metric = metric_of(key);
    // The longest matching pattern wins: "cost.seconds" over "cost.*" over "*".
    const Tolerance* chosen = nullptr;
    for (const auto& t : tolerances) {
      const bool prefix = !t.pattern.empty() && t.pattern.back() == '*';
      const bool match = prefix ? metric.rfind(t.pattern.substr(0, t.pattern.size() - 1), 0) == 0 : metric == t.pattern;
      if (match && (!chosen || t.pattern.size() > chosen->pattern.size())) chosen = &t;
    }
    const bool is_check = metric.rfind(kCheckPrefix, 0) == 0;
    change.tolerance = is_check ? 0 : chosen ? chosen->relative : kDefaultTolerance;
    if (auto b = baseline.values.find(key); b != baseline.values.end()) change.baseline = b->second;
    if (auto c = current.values.find(key); c != current.values.end()) change.current = c->second;
    if (!change.current) {
      change.verdict = Verdict::missing;
    } else if (!change.baseline) {
      change.verdict = Verdict::added;
    } else {
      const double b = *change.baseline, c = *change.current;
      const Direction direction = direction_of(metric, chosen != nullptr);
      if (std::isnan(b) && std::isnan(c)) {
        change.verdict = Verdict::same;
      } else if (std::isnan(b) != std::isnan(c)) {
        // A metric that stops being measurable (or starts) is a change nobody should miss.
        change.verdict = direction == Direction::informational ? Verdict::informational
                         : std::isnan(c)                         ? Verdict::regression
                                                                 : Verdict::better;
      } else if (b == c) {
        change.verdict = Verdict::same;
      } else if (direction == Direction::informational) {
        change.verdict = Verdict::informational;
      } else {
        const double worse_by = direction == Direction::lower_is_better ? c - b : b - c;
        const double allowed = std::max(change.tolerance * std::abs(b), kAbsoluteFloor);
        change.verdict = worse_by < 0 ? Verdict::better
                         : worse_by > allowed ? Verdict::regression
                                              : Verdict::worse_within_tolerance;
      }
    }
    comparison.changes.push_back(change);
  }
  return comparison;
}

}  // namespace marchcheck::reports
