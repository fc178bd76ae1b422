#include "marchcheck/validation/sweep.hpp"

#include "marchcheck/march/render.hpp"
#include "marchcheck/validation/statistics.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

namespace marchcheck::validation {

namespace {

std::vector<std::string> split(const std::string& text, char sep) {
  std::vector<std::string> parts;
  size_t start = 0;
  for (size_t comma = text.find(sep); comma != std::string::npos; comma = text.find(sep, start)) {
    parts.push_back(text.substr(start, comma - start));
    start = comma + 1;
  }
  parts.push_back(text.substr(start));
  return parts;
}

double metric_or_nan(const SweepPoint& p, const std::string& name) { return metric_value(p.metrics, name); }

}  // namespace

std::vector<std::pair<std::string, std::string>> linked_settings(const std::string& key, const std::string& value) {
  const std::vector<std::string> keys = split(key, ':'), values = split(value, ':');
  if (keys.size() != values.size())
    throw sdf::SceneError(key + "=" + value + ": " + std::to_string(keys.size()) + " keys but " +
                          std::to_string(values.size()) + " values (linked values are joined by ':')");
  std::vector<std::pair<std::string, std::string>> settings;
  for (size_t i = 0; i < keys.size(); ++i) settings.emplace_back(keys[i], values[i]);
  return settings;
}

void apply_sweep_setting(sdf::Scene& scene, const std::string& key, const std::string& value) {
  for (const auto& [k, v] : linked_settings(key, value)) sdf::apply_setting(scene, k, v);
}

SweepAxis parse_sweep_axis(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
    throw sdf::SceneError("--vary " + text + ": expected KEY=V1,V2,...");
  SweepAxis axis{text.substr(0, eq), split(text.substr(eq + 1), ',')};
  for (const auto& v : axis.values)
    if (v.empty()) throw sdf::SceneError("--vary " + text + ": empty value in the list");
  return axis;
}

std::optional<SweepTarget> parse_metric_number(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0) return std::nullopt;
  SweepTarget target{text.substr(0, eq), 0};
  const char* first = text.data() + eq + 1;
  const char* last = text.data() + text.size();
  const auto [end, ec] = std::from_chars(first, last, target.value);
  if (ec != std::errc() || end != last || first == last || !std::isfinite(target.value)) return std::nullopt;
  return target;
}

SweepTarget parse_sweep_target(const std::string& text) {
  if (auto target = parse_metric_number(text)) return *target;
  throw sdf::SceneError("--target " + text + ": expected METRIC=NUMBER, e.g. hit.surface_dist_max=1e-3");
}

void mark_pareto(std::vector<SweepPoint>& points, const std::string& error_metric) {
  const auto front = [&](const std::string& cost, bool SweepPoint::*mark) {
    for (auto& p : points) {
      const double e = metric_or_nan(p, error_metric), c = metric_or_nan(p, cost);
      p.*mark = std::isfinite(e) && std::isfinite(c) && std::none_of(points.begin(), points.end(), [&](const SweepPoint& q) {
        const double qe = metric_or_nan(q, error_metric), qc = metric_or_nan(q, cost);
        return qe <= e && qc <= c && (qe < e || qc < c);
      });
    }
  };
  front("cost.evals_per_pixel", &SweepPoint::pareto_evals);
  front("cost.seconds", &SweepPoint::pareto_seconds);
}

SweepResult sweep(const sdf::Scene& scene, const std::vector<SweepAxis>& axes, const SweepOptions& options) {
  for (const auto& axis : axes) {
    sdf::Scene probe = scene;
    for (const auto& v : axis.values) try {
        apply_sweep_setting(probe, axis.key, v);
      } catch (const sdf::SceneError& e) {
        throw sdf::SceneError(std::string("--vary ") + e.what());
      }
  }
  march::keep_freed_memory();  // seconds that do not depend on which combination ran first
  return sweep_combinations(scene.name, axes, options, [&](SweepPoint& point) {
    sdf::Scene s = scene;
    for (const auto& [key, value] : point.settings) apply_sweep_setting(s, key, value);
    const SceneResult validated = validate_scene(s, options.validate);
    point.metrics = validated.metrics;
    point.pass = validated.pass();
    const sdf::Scene timed = sdf::scaled_to_width(s, std::min(options.render_width, s.width));
    std::vector<double> seconds;
    for (int r = 0; r < std::max(1, options.repeat); ++r) {
      const march::RenderResult render = march::render(timed, {}, nullptr, march::Images::asked);  // only its cost is read
      if (r == 0)
        for (const auto& [k, v] : march::cost_metrics(render)) point.metrics[k] = v;
      seconds.push_back(render.seconds);
    }
    point.metrics["cost.seconds"] = median(seconds);
  });
}

size_t combination_count(const std::vector<SweepAxis>& axes) {
  size_t total = 1;
  for (const auto& axis : axes) total *= axis.values.size();
  return total;
}

SweepResult sweep_combinations(const std::string& name, const std::vector<SweepAxis>& axes,
                               const SweepOptions& options, const std::function<void(SweepPoint&)>& measure) {
  SweepResult result{name, axes, options.error_metric, options.targets, {}, std::nullopt};
  const size_t total = combination_count(axes), held = options.shard.share_of(total);
  for (size_t index = 0; index < total; ++index) {
    if (!options.shard.holds(index)) continue;
    SweepPoint point;
    point.index = index;
    size_t rest = index;
    std::vector<size_t> digits(axes.size());
    for (size_t a = axes.size(); a-- > 0;) {
      digits[a] = rest % axes[a].values.size();
      rest /= axes[a].values.size();
    }
    for (size_t a = 0; a < axes.size(); ++a) point.settings.emplace_back(axes[a].key, axes[a].values[digits[a]]);
    measure(point);
    result.points.push_back(std::move(point));
    if (options.progress) options.progress(result.points.size(), held);
  }
  if (options.shard.whole()) finish_sweep(result);
  return result;
}

void finish_sweep(SweepResult& result) {
  for (auto& point : result.points)
    point.meets_targets = std::all_of(result.targets.begin(), result.targets.end(), [&](const SweepTarget& t) {
      return metric_or_nan(point, t.metric) <= t.value;
    });
  mark_pareto(result.points, result.error_metric);
  result.cheapest_meeting.reset();
  if (result.targets.empty()) return;
  for (size_t i = 0; i < result.points.size(); ++i) {
    if (!result.points[i].meets_targets) continue;
    if (!result.cheapest_meeting || metric_or_nan(result.points[i], "cost.evals_per_pixel") <
                                        metric_or_nan(result.points[*result.cheapest_meeting], "cost.evals_per_pixel"))
      result.cheapest_meeting = i;
  }
}

namespace {

constexpr const char* kError = "hit.t_err_p99";
constexpr const char* kCost = "cost.evals_per_pixel";

}  // namespace

const SweepPoint& SeedBeaten::point(size_t i) const {
  return i < sweep.points.size() ? sweep.points[i] : refined.points.at(i - sweep.points.size());
}

double SeedBeaten::cost_ratio() const {
  return cheapest ? point(*cheapest).metrics.at(kCost) / seed().metrics.at(kCost) : INFINITY;
}

double SeedBeaten::accuracy_gain() const {
  if (!most_accurate) return 0;
  const double best = point(*most_accurate).metrics.at(kError);
  return best > 0 ? seed().metrics.at(kError) / best : INFINITY;
}

void choose_beaten(SeedBeaten& beaten) {
  beaten.cheapest = beaten.most_accurate = std::nullopt;
  const double seed_error = beaten.seed().metrics.at(kError), seed_cost = beaten.seed().metrics.at(kCost);
  for (size_t i = 0; i < beaten.point_count(); ++i) {
    const SweepPoint& p = beaten.point(i);
    if (!p.pass || !p.metrics.count(kError)) continue;
    const double error = p.metrics.at(kError), cost = p.metrics.at(kCost);
    if (error <= seed_error && (!beaten.cheapest || cost < beaten.point(*beaten.cheapest).metrics.at(kCost)))
      beaten.cheapest = i;
    if (cost <= seed_cost &&
        (!beaten.most_accurate || error < beaten.point(*beaten.most_accurate).metrics.at(kError)))
      beaten.most_accurate = i;
  }
}

namespace {

// The setting is the text, whatever it reads: 12 digits make 3 * 1e-4 read 0.0003, not 0.00030000000000000003.
std::string text_of(double value, int digits) {
  char text[32];
  return std::string(text, std::to_chars(text, text + sizeof text, value, std::chars_format::general, digits).ptr);
}

// The axis with `other` added, unless it holds it already.
SweepAxis with(SweepAxis axis, const std::string& other) {
  if (std::find(axis.values.begin(), axis.values.end(), other) == axis.values.end()) axis.values.push_back(other);
  return axis;
}

}  // namespace

std::vector<SweepAxis> seed_levers(const sdf::Scene& scene) {
  // The first value of every axis is the scene's own, read back exactly.
  // The scene's own value of an axis, every linked key's text read back exactly and joined as linked_settings splits.
  const auto own = [&](const std::string& key) {
    std::string text;
    for (const std::string& k : split(key, ':')) text += (text.empty() ? "" : ":") + sdf::setting_text(scene, k);
    return SweepAxis{key, {text}};
  };
  // The hit threshold with its mode (hit_eps alone means nothing in pixel mode): absolute from a tenth to ten times
  // the seed's, and relative at 1.5 units in the last place of t per unit, the finest the march's arithmetic decides
  // (on crum-lattice, at 0.84 units 15% of the rays stayed undecided at t ~ 480, at 1.26 none; measured).
  SweepAxis eps = own("eps_mode:hit_eps");
  for (double f : {0.1, 0.3, 3.0, 10.0}) eps.values.push_back("absolute:" + text_of(scene.march.hit_eps * f, 12));
  const double ulp = scene.march.precision == sdf::Precision::float64 ? 0x1p-52 : 0x1p-23;  // half marches in float
  eps = with(eps, "relative:" + text_of(1.5 * ulp, 3));
  const SweepAxis marchers = with(own("marcher"), "relaxed"), refine = with(with(own("refine"), "none"), "secant");
  const SweepAxis clip = with(own("clip"), "bounds");
  std::vector<SweepAxis> axes{marchers, refine, eps, clip};
  // The perturbed bound changes nothing on a field that declares no perturbation.
  if (sdf::derive_info(scene.root, scene.time).perturbation) axes.push_back(with(own("step_bound"), "perturbed"));
  return axes;
}

std::vector<SweepAxis> refine_levers(const sdf::Scene& scene, const SweepPoint& about) {
  // The point's threshold, mode and marcher read from the scene its settings make, not parsed from their text.
  sdf::Scene at = scene;
  std::vector<SweepAxis> axes;
  for (const auto& [key, value] : about.settings) {
    apply_sweep_setting(at, key, value);
    SweepAxis axis{key, {value}};
    if (key == "eps_mode:hit_eps")
      for (double f : {1.4, 2.0})
        axis.values.push_back(sdf::setting_text(at, "eps_mode") + ":" + text_of(at.march.hit_eps * f, 12));
    axes.push_back(axis);
  }
  if (at.march.marcher == sdf::Marcher::relaxed) {
    SweepAxis relaxation{"relaxation", {sdf::setting_text(at, "relaxation")}};
    for (const char* omega : {"1.1", "1.3", "1.8"}) relaxation = with(relaxation, omega);
    axes.push_back(relaxation);
  }
  return axes;
}

SeedBeaten beat_the_seed(const sdf::Scene& scene, const SweepOptions& options) {
  SeedBeaten beaten{scene.name, sweep(scene, seed_levers(scene), options), {}, {}, {}};
  choose_beaten(beaten);
  if (beaten.cheapest) {
    beaten.refined = sweep(scene, refine_levers(scene, beaten.point(*beaten.cheapest)), options);
    choose_beaten(beaten);
  }
  return beaten;
}

}  // namespace marchcheck::validation
