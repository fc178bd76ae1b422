#include "marchcheck/reports/results_io.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <iomanip>
#include <set>
#include <sstream>
#include <stdexcept>

namespace marchcheck::reports {

namespace {

nlohmann::ordered_json number_or_null(double v) { return std::isfinite(v) ? nlohmann::ordered_json(v) : nullptr; }

nlohmann::ordered_json metrics_object(const std::map<std::string, double>& metrics) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const auto& [name, value] : metrics) j[name] = number_or_null(value);
  return j;
}

}  // namespace

std::string metrics_json(const std::map<std::string, double>& metrics) { return metrics_object(metrics).dump(2) + "\n"; }

std::string validate_json(const std::vector<validation::SceneResult>& results) {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const auto& r : results) {
    nlohmann::ordered_json checks = nlohmann::ordered_json::array();
    for (const auto& c : r.checks)
      checks.push_back({{"name", c.name}, {"value", number_or_null(c.value)}, {"limit", number_or_null(c.limit)},
                        {"pass", c.pass}, {"limit_source", c.limit_source}, {"why", c.why}});
    list.push_back({{"scene", r.scene}, {"defects", r.defects}, {"reference", r.reference}, {"pass", r.pass()}, {"checks", checks},
                    {"not_checked", r.not_checked}, {"metrics", metrics_object(r.metrics)}});
  }
  return nlohmann::ordered_json{{"kind", "validate"}, {"results", list}}.dump(2) + "\n";
}

std::string sweep_json(const validation::SweepResult& result) {
  nlohmann::ordered_json axes = nlohmann::ordered_json::array(), targets = nlohmann::ordered_json::array(),
                         points = nlohmann::ordered_json::array();
  for (const auto& a : result.axes) axes.push_back({{"key", a.key}, {"values", a.values}});
  for (const auto& t : result.targets) targets.push_back({{"metric", t.metric}, {"value", t.value}});
  for (const auto& p : result.points) {
    nlohmann::ordered_json settings = nlohmann::ordered_json::object();
    for (const auto& [k, v] : p.settings) settings[k] = v;
    points.push_back({{"settings", settings}, {"pass", p.pass}, {"pareto_evals", p.pareto_evals},
                      {"pareto_seconds", p.pareto_seconds}, {"meets_targets", p.meets_targets},
                      {"metrics", metrics_object(p.metrics)}});
  }
  return nlohmann::ordered_json{{"kind", "sweep"},
                                {"scene", result.scene},
                                {"axes", axes},
                                {"error_metric", result.error_metric},
                                {"targets", targets},
                                {"cheapest_meeting", result.cheapest_meeting ? nlohmann::ordered_json(*result.cheapest_meeting)
                                                                             : nlohmann::ordered_json(nullptr)},
                                {"points", points}}
             .dump(2) +
         "\n";
}

std::string stability_json(const std::vector<validation::StabilityCase>& cases, const validation::StabilityOptions& options) {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  bool all_stable = true;
  for (const auto& c : cases) {
    all_stable = all_stable && c.stable;
    nlohmann::ordered_json variants = nlohmann::ordered_json::array();
    for (const auto& v : c.variants) variants.push_back({{"name", v.name}, {"breaks", v.breaks}, {"what", v.what}});
    list.push_back({{"name", c.name},         {"checks", c.checks},   {"criterion", c.criterion},
                    {"clauses", c.clauses},   {"variants", variants}, {"stable", c.stable},
                    {"failed", c.failed},     {"detail", c.detail},   {"metrics", metrics_object(c.metrics)}});
  }
  return nlohmann::ordered_json{{"kind", "stability"}, {"variant", options.variant}, {"full", options.full},
                                {"stable", all_stable}, {"cases", list}}
             .dump(2) +
         "\n";
}

std::string sweep_csv(const validation::SweepResult& result) {
  std::set<std::string> names;
  for (const auto& p : result.points)
    for (const auto& [k, v] : p.metrics) names.insert(k);
  std::ostringstream csv;
  csv << std::setprecision(17);
  for (const auto& a : result.axes) csv << a.key << ",";
  csv << "pass,pareto_evals,pareto_seconds,meets_targets";
  for (const auto& n : names) csv << "," << n;
  csv << "\n";
  for (const auto& p : result.points) {
    for (const auto& [k, v] : p.settings) csv << v << ",";
    csv << p.pass << "," << p.pareto_evals << "," << p.pareto_seconds << "," << p.meets_targets;
    for (const auto& n : names) {
      const auto it = p.metrics.find(n);
      csv << ",";
      if (it != p.metrics.end() && std::isfinite(it->second)) csv << it->second;
    }
    csv << "\n";
  }
  return csv.str();
}

}  // namespace marchcheck::reports
