#include "marchcheck/reports/commands.hpp"

#include "marchcheck/march/render.hpp"
#include "marchcheck/reports/results_io.hpp"
#include "marchcheck/sdf/builtin_scenes.hpp"
#include "marchcheck/sdf/scene_file.hpp"
#include "marchcheck/validation/validate.hpp"

#include <nlohmann/json.hpp>

#include <charconv>
#include <filesystem>
#include <iomanip>

namespace marchcheck::reports {

namespace {

constexpr int kBadInput = 2;

void apply_sets(sdf::Scene& scene, const std::vector<std::string>& sets) {
  for (const auto& kv : sets) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos || eq == 0) throw sdf::SceneError("--set " + kv + ": expected KEY=VALUE");
    sdf::apply_setting(scene, kv.substr(0, eq), kv.substr(eq + 1));
  }
}

// from_chars, not sscanf: "%d" on "99999999999" is undefined behaviour.
void apply_size(sdf::Scene& scene, const std::string& size) {
  int w = 0, h = 0;
  const char* end = size.data() + size.size();
  const auto [x, ew] = std::from_chars(size.data(), end, w);
  bool ok = ew == std::errc() && x != end && (*x == 'x' || *x == 'X');
  if (ok) {
    const auto [last, eh] = std::from_chars(x + 1, end, h);
    ok = eh == std::errc() && last == end && w >= 1 && h >= 1 && w <= 16384 && h <= 16384;
  }
  if (!ok) throw sdf::SceneError("--size " + size + ": expected WIDTHxHEIGHT, each 1..16384");
  scene.width = w;
  scene.height = h;
}

}  // namespace

int run_scenes(const ScenesCommand& cmd, std::ostream& out, std::ostream& err) {
  if (cmd.export_name) {
    try {
      out << sdf::scene_to_json(sdf::builtin_scene(*cmd.export_name));
      return 0;
    } catch (const sdf::SceneError& e) {
      err << "marchcheck scenes: " << e.what() << "\n";
      return kBadInput;
    }
  }
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const auto& name : sdf::builtin_scene_names()) {
    const auto scene = sdf::builtin_scene(name);
    const auto info = sdf::derive_info(scene.root, scene.time);
    list.push_back({{"name", name},
                    {"description", scene.description},
                    {"defects", scene.defects},
                    {"effects", sdf::declared_effects(scene)},
                    {"kind", std::string(sdf::to_string(info.kind))},
                    {"lipschitz", info.lipschitz},
                    {"kind_reason", info.reason}});
  }
  if (cmd.json) {
    out << list.dump(2) << "\n";
    return 0;
  }
  out << std::left << std::setw(33) << "scene" << std::setw(11) << "kind" << std::setw(6) << "L" << std::setw(24)
      << "reproduces" << "effects\n";
  for (const auto& s : list) {
    std::string effects, defects = s["defects"].empty() ? "-" : "defect:";
    for (const auto& e : s["effects"]) effects += (effects.empty() ? "" : " ") + e.get<std::string>();
    for (const auto& d : s["defects"]) defects += d.get<std::string>();
    out << std::setw(33) << s["name"].get<std::string>() << std::setw(11) << s["kind"].get<std::string>()
        << std::setw(6) << std::setprecision(3) << s["lipschitz"].get<double>() << std::setw(24) << defects
        << effects << "\n";
  }
  return 0;
}

int run_render(const RenderCommand& cmd, std::ostream& out, std::ostream& err) {
  sdf::Scene scene;
  std::vector<march::Aov> aovs;
  try {
    scene = sdf::resolve_scene(cmd.scene);
    apply_sets(scene, cmd.sets);
    if (cmd.size) apply_size(scene, *cmd.size);
    if (!cmd.aovs.empty()) aovs = march::parse_aovs(cmd.aovs);
    sdf::compile(scene.root, scene.time);  // reports tree errors before any work
  } catch (const std::exception& e) {
    err << "marchcheck render: " << e.what() << "\n";
    return kBadInput;
  }
  std::optional<validation::Reference> reference;
  std::optional<march::SurfaceOracle> oracle;
  if (cmd.reference) {
    reference.emplace(scene.intended ? *scene.intended : scene.root, scene.time);
    oracle = validation::oracle_of(*reference);
  }
  const auto result = march::render(scene, aovs, oracle ? &*oracle : nullptr);
  try {
    march::write_render(result, cmd.output, aovs);
    if (cmd.stats) write_text_atomically(*cmd.stats, metrics_json(march::cost_metrics(result)));
  } catch (const std::exception& e) {
    err << "marchcheck render: " << e.what() << "\n";
    return kBadInput;
  }
  out << scene.name << ": " << scene.width << "x" << scene.height << ", " << std::fixed << std::setprecision(1)
      << result.evals_per_pixel() << " evaluations per pixel, " << std::setprecision(3) << result.seconds
      << " s -> " << cmd.output << "\n";
  return 0;
}

int run_validate(const ValidateCommand& cmd, std::ostream& out, std::ostream& err) {
  std::vector<sdf::Scene> scenes;
  try {
    for (const auto& name : cmd.scenes) {
      const auto names = name == "all" ? sdf::builtin_scene_names() : std::vector<std::string>{name};
      for (const auto& n : names) {
        scenes.push_back(sdf::resolve_scene(n));
        apply_sets(scenes.back(), cmd.sets);
        sdf::compile(scenes.back().root, scenes.back().time);
      }
    }
  } catch (const std::exception& e) {
    err << "marchcheck validate: " << e.what() << "\n";
    return kBadInput;
  }
  nlohmann::ordered_json results = nlohmann::ordered_json::array();
  bool all_pass = true;
  for (const auto& scene : scenes) {
    const auto r = validation::validate_scene(scene);
    all_pass = all_pass && r.pass();
    out << scene.name << (scene.defects.empty() ? "" : "  (reproduces a seed defect)") << ": "
        << (r.pass() ? "PASS" : "FAIL") << "\n";
    out << "  " << std::left << std::setw(30) << "check" << std::right << std::setw(13) << "value" << std::setw(13)
        << "limit" << "  result  limit from\n";
    nlohmann::ordered_json checks = nlohmann::ordered_json::array();
    for (const auto& c : r.checks) {
      out << "  " << std::left << std::setw(30) << c.name << std::right << std::setw(13) << std::setprecision(4)
          << std::defaultfloat << c.value << std::setw(13) << c.limit << "  " << (c.pass ? "pass  " : "FAIL  ") << "  "
          << c.limit_source << "\n";
      checks.push_back({{"name", c.name}, {"value", c.value}, {"limit", c.limit}, {"pass", c.pass},
                        {"limit_source", c.limit_source}, {"why", c.why}});
    }
    nlohmann::ordered_json metrics = nlohmann::ordered_json::object();
    for (const auto& [k, v] : r.metrics) metrics[k] = std::isfinite(v) ? nlohmann::ordered_json(v) : nullptr;
    results.push_back({{"scene", scene.name}, {"defects", scene.defects}, {"pass", r.pass()}, {"checks", checks},
                       {"metrics", metrics}});
  }
  if (cmd.json) {
    try {
      write_text_atomically(*cmd.json, nlohmann::ordered_json{{"kind", "validate"}, {"results", results}}.dump(2) + "\n");
    } catch (const std::exception& e) {
      err << "marchcheck validate: " << e.what() << "\n";
      return kBadInput;
    }
  }
  return all_pass ? 0 : 1;
}

int run_render_all(const std::string& dir, std::ostream& out, std::ostream& err) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    err << "marchcheck: " << dir << ": cannot create the folder: " << ec.message() << "\n";
    return kBadInput;
  }
  for (const auto& name : sdf::builtin_scene_names()) {
    RenderCommand cmd;
    cmd.scene = name;
    cmd.output = (std::filesystem::path(dir) / (name + ".png")).string();
    cmd.aovs = "steps";
    cmd.stats = (std::filesystem::path(dir) / (name + ".stats.json")).string();
    if (const int status = run_render(cmd, out, err); status != 0) return status;
  }
  return 0;
}

}  // namespace marchcheck::reports
