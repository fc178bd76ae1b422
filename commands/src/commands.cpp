#include "marchcheck/commands/commands.hpp"

#include "marchcheck/files/atomic_file.hpp"
#include "marchcheck/march/render.hpp"
#include "marchcheck/march/texture.hpp"
#include "marchcheck/reports/compare.hpp"
#include "marchcheck/reports/results_io.hpp"
#include "marchcheck/reports/report.hpp"
#include "marchcheck/sdf/builtin_scenes.hpp"
#include "marchcheck/sdf/glsl_export.hpp"
#include "marchcheck/sdf/glsl_field.hpp"
#include "marchcheck/sdf/scene_file.hpp"
#include "marchcheck/validation/slice.hpp"
#include "marchcheck/validation/stability.hpp"
#include "marchcheck/validation/validate.hpp"
#include "sharded.hpp"
#include "user_marcher.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <charconv>
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <sstream>

namespace marchcheck::commands {

using namespace reports;  // the result files, the comparison and the report that the commands drive

namespace {

constexpr int kBadInput = 2;

std::string format_value(double v) {
  std::ostringstream text;
  text << std::setprecision(4) << v;
  return text.str();
}

void apply_sets(sdf::Scene& scene, const std::vector<std::string>& sets) {
  for (const auto& kv : sets) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos || eq == 0) throw sdf::SceneError("--set " + kv + ": expected KEY=VALUE");
    try {
      sdf::apply_setting(scene, kv.substr(0, eq), kv.substr(eq + 1));
    } catch (const sdf::SceneError& e) {
      throw sdf::SceneError(std::string("--set ") + e.what());
    }
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

sdf::Scene load_scene(const std::string& name_or_path, const std::vector<std::string>& sets) {
  sdf::Scene scene =
      name_or_path.ends_with(".glsl") ? sdf::glsl_scene(name_or_path) : sdf::resolve_scene(name_or_path);
  apply_sets(scene, sets);
  sdf::compile(scene.root, scene.time);
  march::check_texture_files(scene);  // an unreadable image is bad input, said before any work
  return scene;
}

// A GLSL file alone is validated as the GPU runs it (float) and as its reference (double), unless --set chooses.
std::vector<sdf::Scene> glsl_scenes(const std::string& path, const std::string& function,
                                    const std::vector<std::string>& sets) {
  const sdf::Scene base = sdf::glsl_scene(path, function);
  constexpr std::string_view kPrecisionSet = "precision=";
  const auto chosen =
      std::find_if(sets.begin(), sets.end(), [&](const std::string& s) { return s.starts_with(kPrecisionSet); });
  std::vector<sdf::Scene> out;
  for (const char* precision : {"float", "double"}) {
    if (chosen != sets.end() && precision != std::string("float")) break;
    sdf::Scene s = base;
    sdf::apply_setting(s, "precision", precision);
    apply_sets(s, sets);
    s.name += " (" + (chosen != sets.end() ? chosen->substr(kPrecisionSet.size()) : precision) + ")";
    sdf::compile(s.root, s.time);
    out.push_back(std::move(s));
  }
  return out;
}

int run_scenes(const ScenesCommand& cmd, std::ostream& out, std::ostream& err) {
  if (cmd.export_glsl) {
    try {
      out << sdf::shadertoy_shader(load_scene(*cmd.export_glsl, {}));
      return 0;
    } catch (const std::exception& e) {
      err << "marchcheck scenes: " << e.what() << "\n";
      return kBadInput;
    }
  }
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
    scene = load_scene(cmd.scene, cmd.sets);
    if (cmd.size) apply_size(scene, *cmd.size);
    if (!cmd.aovs.empty()) aovs = march::parse_aovs(cmd.aovs);
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
  const auto result = march::render(scene, aovs, oracle ? &*oracle : nullptr, march::Images::asked);
  std::optional<march::Image> error;  // the difference from the reference render, as validate computes it
  if (std::find(aovs.begin(), aovs.end(), march::Aov::error) != aovs.end())
    error = validation::render_image_pair(scene, scene.width).difference;
  try {
    march::write_render(result, cmd.output, aovs, error ? &*error : nullptr);
    if (cmd.stats) files::write_bytes_atomically(*cmd.stats, metrics_json(march::cost_metrics(result)));
  } catch (const std::exception& e) {
    err << "marchcheck render: " << e.what() << "\n";
    return kBadInput;
  }
  for (const std::string& note : sdf::mesh_notes(scene.root)) out << scene.name << ": " << note << "\n";
  out << scene.name << ": " << scene.width << "x" << scene.height << ", " << std::fixed << std::setprecision(1)
      << result.evals_per_pixel() << " evaluations per pixel, " << std::setprecision(3) << result.seconds
      << " s -> " << cmd.output << "\n";
  return 0;
}

int run_slice(const SliceCommand& cmd, std::ostream& out, std::ostream& err) {
  sdf::Scene scene;
  validation::SlicePlane plane;
  int width = 512, height = 512;
  try {
    scene = load_scene(cmd.scene, cmd.sets);
    plane = cmd.plane ? validation::parse_plane(*cmd.plane) : validation::default_plane(scene);
    if (cmd.size) {
      sdf::Scene sized = scene;
      apply_size(sized, *cmd.size);
      width = sized.width;
      height = sized.height;
    }
  } catch (const std::exception& e) {
    err << "marchcheck slice: " << e.what() << "\n";
    return kBadInput;
  }
  const validation::Slice s = validation::slice(scene, plane, width, height);
  try {
    march::write_image(s.image, cmd.output, false);
  } catch (const std::exception& e) {
    err << "marchcheck slice: " << e.what() << "\n";
    return kBadInput;
  }
  const char axes[] = "xyz";
  out << scene.name << ": slice " << axes[plane.axis] << " = " << plane.value << ", " << 2 * s.half << " wide around ("
      << s.centre_u << ", " << s.centre_v << "); ";
  if (s.certified) {
    out << s.cells_over << " of " << s.cells << " squares where the certified |grad f| bound exceeds the declared "
        << "constant (largest bound " << s.steepest_bound << ")";
  } else {
    out << "no interval rule for this field: no certified squares";
  }
  out << " -> " << cmd.output << "\n";
  return 0;
}

namespace {

// validate's results to --json (0, or 2 when the file cannot be written), and its status: 1 when a scene failed.
int finish_validate(const ShardFile& whole, bool printed, const std::optional<std::string>& json, std::ostream& out,
                    std::ostream& err) {
  std::vector<validation::SceneResult> results;
  for (const auto& s : whole.scenes) {
    if (!printed) out << s.printed;
    results.push_back(s.result);
  }
  if (json) {
    try {
      files::write_bytes_atomically(*json, validate_json(results));
    } catch (const std::exception& e) {
      err << "marchcheck validate: " << e.what() << "\n";
      return kBadInput;
    }
  }
  return results_status(whole);
}

// What a command's results depend on besides its scenes: its options, one per line.
std::string settings_hash(const std::vector<std::string>& options) {
  std::string text;
  for (const auto& o : options) text += o + "\n";
  return content_hash(text);
}

std::string validate_settings_hash(const ValidateCommand& cmd) {
  std::vector<std::string> options = {"function=" + cmd.function, "march=" + cmd.march, "normal=" + cmd.normal};
  for (const auto& set : cmd.sets) options.push_back("set " + set);
  return settings_hash(options);
}

UserShader read_user_shader(const std::string& path) {
  const std::optional<std::string> text = sdf::read_text_file(path);
  if (!text) throw sdf::SceneError(path + ": cannot read the GLSL file");
  return {path, *text, {}};
}

// A GLSL file's own marcher on the GL driver, judged: the table, and what the scene was made of.
std::string judge_printed(const sdf::Scene& scene, const ValidateCommand& cmd, const validation::SceneResult& judged,
                          const std::string& renderer) {
  std::ostringstream out;
  validation::print_checks(judged, out);
  out << "  scene: " << scene.description << "\n  marcher: " << cmd.march
      << (cmd.normal.empty() ? "" : ", normal " + cmd.normal) << ", map calls counted, on " << renderer
      << "; march.safe_step_ratio assumes steps of f\n";
  const auto& m = judged.metrics;
  out << "  driver against CPU (the same marcher, float): " << m.at("driver.outcome_differs")
      << " rays with another outcome, t within " << m.at("driver.t_ulps_max") << " ulps where both hit; float "
      << "against double on the CPU: " << m.at("cpu.float_double_outcome_differs") << " rays with another outcome"
      << ", against half (mediump): " << m.at("cpu.float_half_outcome_differs") << ", t within "
      << format_value(m.at("cpu.float_half_t_rel_max")) << " relative"
      << (m.at("driver.cpu_unfinished") > 0
              ? "; " + format_value(m.at("driver.cpu_unfinished")) + " rays the CPU evaluator could not finish"
              : "")
      << "\n";
  return out.str();
}

// The GLSL files' own marchers, each judged on the GL driver: the files are the work items.
ShardFile validate_user_marchers(const ValidateCommand& cmd, const validation::Shard& shard, std::ostream& out) {
  const gpu::UserMarcher marcher{cmd.march, cmd.normal, cmd.function};
  std::string shaders;
  for (const auto& path : cmd.scenes) {
    if (!path.ends_with(".glsl")) throw sdf::SceneError(path + ": --march runs a .glsl file's own marcher");
    shaders += path + "\n" + read_user_shader(path).text + "\n";
  }
  ShardFile results{{"validate", content_hash(shaders), validate_settings_hash(cmd), program_version(), cmd.scenes.size()}, shard, {}, {}, {}};
  for (size_t i = 0; i < cmd.scenes.size(); ++i) {
    if (!shard.holds(i)) continue;
    const std::string& path = cmd.scenes[i];
    try {
      std::string renderer;
      const UserShader shader = read_user_shader(path);
      sdf::Scene scene = user_marcher_scene(shader, marcher);
      apply_sets(scene, cmd.sets);
      // The driver runs the marcher in float whatever the scene says; its binary16 run is the CPU's, under the table.
      if (scene.march.precision == sdf::Precision::float16)
        throw sdf::SceneError(path + ": --march judges the GL driver's run, in float; the marcher in half (mediump) "
                                     "is run on the CPU and compared under the table");
      sdf::compile(scene.root, scene.time);
      const validation::SceneResult judged = judge_user_marcher(scene, shader, marcher, renderer);
      results.scenes.push_back({i, judge_printed(scene, cmd, judged, renderer), judged});
      out << results.scenes.back().printed;
    } catch (const gpu::DriverUnavailable& e) {
      throw std::runtime_error(path + ": no GL driver to run the marcher on: " + e.what());
    }
  }
  return results;
}

// The scenes validated: every one loaded (a bad one is bad input in every shard), the shard's own run.
ShardFile validate_scenes(const ValidateCommand& cmd, const validation::Shard& shard, std::ostream& out) {
  std::vector<sdf::Scene> scenes;
  for (const auto& name : cmd.scenes) {
    if (name.ends_with(".glsl")) {
      for (sdf::Scene& s : glsl_scenes(name, cmd.function, cmd.sets)) scenes.push_back(std::move(s));
      continue;
    }
    const auto names = name == "all" ? sdf::builtin_scene_names() : std::vector<std::string>{name};
    for (const auto& n : names) scenes.push_back(load_scene(n, cmd.sets));
  }
  ShardFile results{{"validate", scenes_hash(scenes), validate_settings_hash(cmd), program_version(), scenes.size()}, shard, {}, {}, {}};
  for (size_t i = 0; i < scenes.size(); ++i) {
    if (!shard.holds(i)) continue;
    const sdf::Scene& scene = scenes[i];
    const validation::SceneResult validated = validation::validate_scene(scene);
    std::ostringstream printed;
    validation::print_checks(validated, printed);
    // A GLSL file's scene was made here: say how (the camera's framing, found by sampling).
    if (scene.root.op == sdf::Op::glsl && !scene.description.empty()) printed << "  scene: " << scene.description << "\n";
    for (const std::string& note : sdf::mesh_notes(scene.root)) printed << "  " << note << "\n";
    results.scenes.push_back({i, printed.str(), validated});
    out << results.scenes.back().printed;
  }
  return results;
}

}  // namespace

int run_validate(const ValidateCommand& cmd, std::ostream& out, std::ostream& err) {
  const auto work = [&](const validation::Shard& shard, std::ostream& shard_out, std::ostream&) {
    return cmd.march.empty() ? validate_scenes(cmd, shard, shard_out) : validate_user_marchers(cmd, shard, shard_out);
  };
  const auto finish = [&](const ShardFile& whole, bool printed, std::ostream& whole_out, std::ostream& whole_err) {
    return finish_validate(whole, printed, cmd.json, whole_out, whole_err);
  };
  return run_sharded({"validate", cmd.shard, cmd.json}, work, finish, out, err);
}

int run_stability(const StabilityCommand& cmd, std::ostream& out, std::ostream& err) {
  if (cmd.json) {
    // Checked before the battery runs, so a bad path costs no time; the write itself is atomic.
    const auto parent = std::filesystem::absolute(*cmd.json).parent_path();
    if (!std::filesystem::is_directory(parent)) {
      err << "marchcheck stability: " << *cmd.json << ": the folder " << parent.string() << " does not exist\n";
      return kBadInput;
    }
  }
  const validation::StabilityOptions options{cmd.naive ? "naive" : "", cmd.full};
  const auto cases = validation::run_stability(options);
  int stable = 0;
  out << std::left << std::setw(34) << "case" << std::setw(10) << "result" << "numbers\n";
  for (const auto& c : cases) {
    stable += c.stable;
    // The table shows a case's first numbers; the JSON has them all.
    constexpr int kShown = 6;
    std::ostringstream numbers;
    numbers << std::setprecision(3);
    int shown = 0;
    for (const auto& [k, v] : c.metrics)
      if (shown++ < kShown) numbers << (shown > 1 ? " " : "") << k << "=" << v;
    if (shown > kShown) numbers << " (+" << shown - kShown << " in --json)";
    out << std::left << std::setw(34) << c.name << std::setw(10) << (c.stable ? "stable" : "UNSTABLE") << numbers.str()
        << "\n";
    if (!c.stable) out << std::string(44, ' ') << "why: " << c.detail << "\n";
  }
  const bool all_stable = stable == static_cast<int>(cases.size());
  out << stable << " of " << cases.size() << " cases stable" << (cmd.naive ? " (naive variants)" : "") << "\n";
  if (cmd.json) {
    try {
      files::write_bytes_atomically(*cmd.json, stability_json(cases, options));
    } catch (const std::exception& e) {
      err << "marchcheck stability: " << e.what() << "\n";
      return kBadInput;
    }
  }
  return all_stable ? 0 : 1;
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

namespace {

std::string metric_text(const validation::SweepPoint& p, const std::string& name) {
  const auto it = p.metrics.find(name);
  return it == p.metrics.end() ? "-" : format_value(it->second);
}

// The sweep's table: each combination's settings, the error metric and the other columns, its place on the
// fronts, its checks, and the cheapest that meets the targets.
void print_sweep(const validation::SweepResult& result, const std::vector<std::string>& others, std::ostream& out) {
  std::vector<std::string> columns = {result.error_metric};
  for (const auto& c : others)
    if (c != result.error_metric) columns.push_back(c);
  // Each axis as wide as its key and its longest value (a linked axis's run long), at least 12.
  std::vector<int> widths;
  for (const auto& a : result.axes) {
    size_t w = std::max<size_t>(12, a.key.size());
    for (const auto& v : a.values) w = std::max(w, v.size());
    widths.push_back(static_cast<int>(w));
  }
  for (size_t a = 0; a < result.axes.size(); ++a) out << std::left << std::setw(widths[a]) << result.axes[a].key << " ";
  for (const auto& c : columns) out << std::right << std::setw(std::max<int>(12, static_cast<int>(c.size()) + 1)) << c;
  out << "  front  checks\n";
  for (size_t i = 0; i < result.points.size(); ++i) {
    const auto& p = result.points[i];
    for (size_t a = 0; a < p.settings.size(); ++a) out << std::left << std::setw(widths[a]) << p.settings[a].second << " ";
    for (const auto& c : columns)
      out << std::right << std::setw(std::max<int>(12, static_cast<int>(c.size()) + 1)) << metric_text(p, c);
    out << "  " << (p.pareto_evals ? "E" : " ") << (p.pareto_seconds ? "S" : " ") << "     "
        << (p.pass ? "pass" : "FAIL") << (result.cheapest_meeting == i ? "  <- cheapest meeting the target" : "") << "\n";
  }
  if (!result.targets.empty() && !result.cheapest_meeting) out << "no combination meets the target\n";
}

void draw_progress(std::ostream& err, size_t done, size_t total) {
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(kWidth * done / std::max<size_t>(total, 1));
  err << "\r[" << std::string(static_cast<size_t>(filled), '#') << std::string(static_cast<size_t>(kWidth - filled), ' ')
      << "] " << done << "/" << total << (done == total ? "\n" : "") << std::flush;
}

// The finished sweep: its table (title, then the rows), and its --json and --csv files. 0, or 2 when a target or
// the error metric names a metric no combination has, or a file cannot be written.
int finish_sweep_run(const ShardFile& whole, const std::optional<std::string>& json, const std::optional<std::string>& csv,
                     std::ostream& out, std::ostream& err) {
  const validation::SweepResult& result = whole.sweep;
  const auto known = [&](const std::string& metric) {
    return std::any_of(result.points.begin(), result.points.end(), [&](const auto& p) { return p.metrics.count(metric) > 0; });
  };
  for (const auto& t : result.targets)
    if (!known(t.metric)) {
      err << "marchcheck sweep: --target " << t.metric << ": no combination has this metric\n";
      return kBadInput;
    }
  if (!known(result.error_metric)) {
    err << "marchcheck sweep: --error " << result.error_metric << ": no combination has this metric\n";
    return kBadInput;
  }
  out << whole.table.title << "\n";
  print_sweep(result, whole.table.columns, out);
  try {
    if (json) files::write_bytes_atomically(*json, sweep_json(result));
    if (csv) files::write_bytes_atomically(*csv, sweep_csv(result));
  } catch (const std::exception& e) {
    err << "marchcheck sweep: " << e.what() << "\n";
    return kBadInput;
  }
  return 0;
}

std::string sweep_settings_hash(const SweepCommand& cmd) {
  std::vector<std::string> options = {"error=" + cmd.error_metric, "repeat=" + std::to_string(cmd.repeat),
                                      "width=" + std::to_string(cmd.render_width), "march=" + cmd.march,
                                      "normal=" + cmd.normal, "function=" + cmd.function};
  for (const auto& v : cmd.vary) options.push_back("vary " + v);
  for (const auto& t : cmd.targets) options.push_back("target " + t);
  for (const auto& set : cmd.sets) options.push_back("set " + set);
  return settings_hash(options);
}

validation::SweepOptions sweep_options(const SweepCommand& cmd, const validation::Shard& shard, std::ostream& progress) {
  validation::SweepOptions options;
  for (const auto& t : cmd.targets) options.targets.push_back(validation::parse_sweep_target(t));
  options.error_metric = cmd.error_metric;
  options.shard = shard;
  if (cmd.progress) options.progress = [&progress](size_t done, size_t total) { draw_progress(progress, done, total); };
  return options;
}

// A sweep of a GLSL file's own parameters, its own marcher judged at each combination on the GL driver; the
// error axis hit.t_err_p99 unless asked, the cost its map calls per ray (in cost.evals_per_pixel: a ray a
// sampled pixel) and the driver's seconds.
ShardFile sweep_user_marcher(const SweepCommand& cmd, const validation::Shard& shard, std::ostream& progress) {
  const gpu::UserMarcher marcher{cmd.march, cmd.normal, cmd.function};
  std::vector<validation::SweepAxis> axes;
  validation::SweepOptions options = sweep_options(cmd, shard, progress);
  if (cmd.error_metric == "image.rms") options.error_metric = "hit.t_err_p99";  // no image here
  if (!cmd.scene.ends_with(".glsl")) throw sdf::SceneError(cmd.scene + ": --march runs a .glsl file's own marcher");
  const UserShader shader = read_user_shader(cmd.scene);
  for (const auto& v : cmd.vary) {
    axes.push_back(validation::parse_sweep_axis(v));
    if (!axes.back().key.starts_with("glsl."))
      throw sdf::SceneError("--vary " + v + ": with --march, the axes are the shader's own (glsl.NAME)");
    for (const auto& value : axes.back().values) {
      UserShader probe = shader;  // every value applies before any work is done
      set_shader_parameter(probe, axes.back().key.substr(5), value);
    }
  }
  std::string renderer;
  try {
    ShardFile results{{"sweep", content_hash(shader.path + "\n" + shader.text), sweep_settings_hash(cmd), program_version(),
                       validation::combination_count(axes)}, shard, {}, {}, {}};
    results.sweep = validation::sweep_combinations(cmd.scene, axes, options, [&](validation::SweepPoint& point) {
      UserShader s = shader;
      for (const auto& [key, value] : point.settings) set_shader_parameter(s, key.substr(5), value);
      sdf::Scene scene = user_marcher_scene(s, marcher);
      apply_sets(scene, cmd.sets);
      sdf::compile(scene.root, scene.time);
      const auto start = std::chrono::steady_clock::now();
      const validation::SceneResult judged = judge_user_marcher(scene, s, marcher, renderer);
      point.metrics = judged.metrics;
      point.metrics["cost.evals_per_pixel"] = judged.metrics.at("cost.march_evals_per_ray");
      point.metrics["cost.seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      point.pass = judged.pass();
    });
    results.table = {cmd.scene + ", marcher " + cmd.march + " on " + renderer + ": " +
                         std::to_string(results.configuration.items) + " combinations (front: E = Pareto front of " +
                         options.error_metric + " against map calls per ray, S = against seconds, each a whole judged run)",
                     {"hit.false_hit", "hit.false_miss", "hit.overshoot", "hit.undecided", "march.over_max_steps",
                      "cost.evals_per_pixel", "cost.seconds"}};
    return results;
  } catch (const gpu::DriverUnavailable& e) {
    throw std::runtime_error(cmd.scene + ": no GL driver to run the marcher on: " + e.what());
  }
}

// A sweep of a scene's own settings.
ShardFile sweep_scene(const SweepCommand& cmd, const validation::Shard& shard, std::ostream& progress) {
  const sdf::Scene scene = load_scene(cmd.scene, cmd.sets);
  std::vector<validation::SweepAxis> axes;
  for (const auto& v : cmd.vary) axes.push_back(validation::parse_sweep_axis(v));
  validation::SweepOptions options = sweep_options(cmd, shard, progress);
  if (cmd.repeat < 1) throw sdf::SceneError("--repeat " + std::to_string(cmd.repeat) + ": expected at least 1");
  if (cmd.render_width < 1) throw sdf::SceneError("--width " + std::to_string(cmd.render_width) + ": expected at least 1");
  options.repeat = cmd.repeat;
  options.render_width = cmd.render_width;
  ShardFile results{{"sweep", scenes_hash({scene}), sweep_settings_hash(cmd), program_version(),
                     validation::combination_count(axes)}, shard, validation::sweep(scene, axes, options), {}, {}};
  std::ostringstream title;
  title << scene.name << ": " << results.configuration.items << " combinations (front: E = Pareto front of "
        << options.error_metric << " against evaluations, S = against seconds; seconds = median of " << options.repeat
        << " renders at width " << std::min(options.render_width, scene.width) << ")";
  results.table = {title.str(), {"hit.undecided", "hit.t_err_p99", "normal.angle_p99_deg", "cost.evals_per_pixel",
                                 "cost.seconds"}};
  return results;
}

}  // namespace

int run_sweep(const SweepCommand& cmd, std::ostream& out, std::ostream& err) {
  const auto work = [&](const validation::Shard& shard, std::ostream&, std::ostream& progress) {
    return cmd.march.empty() ? sweep_scene(cmd, shard, progress) : sweep_user_marcher(cmd, shard, progress);
  };
  const auto finish = [&](const ShardFile& whole, bool, std::ostream& whole_out, std::ostream& whole_err) {
    return finish_sweep_run(whole, cmd.json, cmd.csv, whole_out, whole_err);
  };
  return run_sharded({"sweep", cmd.shard, cmd.json}, work, finish, out, err);
}

int run_merge(const MergeCommand& cmd, std::ostream& out, std::ostream& err) {
  ShardFile whole;
  try {
    std::vector<NamedText> pieces;
    for (const auto& path : cmd.shards) {
      const std::optional<std::string> text = sdf::read_text_file(path);
      if (!text) throw ResultFileError(path + ": cannot read the file");
      pieces.push_back({path, *text});
    }
    whole = merge_shards(pieces);
    if (whole.configuration.kind == "validate" && cmd.csv)
      throw ResultFileError("--csv: a validate run has no CSV file, only a sweep");
  } catch (const std::exception& e) {
    err << "marchcheck merge: " << e.what() << "\n";
    return kBadInput;
  }
  if (whole.configuration.kind == "sweep") return finish_sweep_run(whole, cmd.output, cmd.csv, out, err);
  return finish_validate(whole, false, cmd.output, out, err);
}

int run_compare(const CompareCommand& cmd, std::ostream& out, std::ostream& err) {
  const auto load = [](const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw ResultFileError(path + ": cannot open the file");
    std::ostringstream text;
    text << in.rdbuf();
    return flatten_results(text.str(), path);
  };
  Comparison comparison;
  try {
    std::vector<Tolerance> tolerances;
    for (const auto& t : cmd.tolerances) tolerances.push_back(parse_tolerance(t));
    comparison = compare_results(load(cmd.baseline), load(cmd.current), tolerances);
  } catch (const std::exception& e) {
    err << "marchcheck compare: " << e.what() << "\n";
    return kBadInput;
  }
  const auto value_text = [](const std::optional<double>& v) { return v ? format_value(*v) : std::string("-"); };
  for (const auto& c : comparison.changes) {
    if (c.verdict == Verdict::same) continue;
    out << std::left << std::setw(26) << to_string(c.verdict) << c.key << ": " << value_text(c.baseline) << " -> "
        << value_text(c.current);
    if (c.verdict == Verdict::regression || c.verdict == Verdict::worse_within_tolerance)
      out << " (tolerance " << c.tolerance << " relative)";
    out << "\n";
  }
  out << comparison.changes.size() << " values: " << comparison.count(Verdict::same) << " same, "
      << comparison.count(Verdict::better) << " better, " << comparison.count(Verdict::worse_within_tolerance)
      << " worse within tolerance, " << comparison.count(Verdict::regression) << " regressions, "
      << comparison.count(Verdict::missing) << " missing, " << comparison.count(Verdict::added) << " new\n";
  return comparison.regression() ? 1 : 0;
}

int run_report(const ReportCommand& cmd, std::ostream& out, std::ostream& err) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<sdf::Scene> scenes;
  try {
    for (const auto& name : cmd.scenes.empty() ? std::vector<std::string>{"all"} : cmd.scenes)
      for (const auto& n : name == "all" ? sdf::builtin_scene_names() : std::vector<std::string>{name})
        scenes.push_back(load_scene(n, cmd.sets));
  } catch (const std::exception& e) {
    err << "marchcheck report: " << e.what() << "\n";
    return kBadInput;
  }
  int status = 0;
  try {
    status = write_report(std::move(scenes), cmd.dir, {cmd.quick, cmd.progress}, err);
  } catch (const std::exception& e) {
    err << "marchcheck report: " << e.what() << "\n";
    return kBadInput;
  }
  std::filesystem::path dir = std::filesystem::path(cmd.dir).lexically_normal();
  out << "report: " << (dir / "index.html").string() << " ("
      << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() << " s)"
      << (status == 0 ? "" : "; a check failed where it should pass, or a defect went uncaught: see the summary") << "\n";
  return status;
}

}  // namespace marchcheck::commands
