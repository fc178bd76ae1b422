// marchcheck's command line: argument parsing only; the commands live in marchcheck::commands.
#include "marchcheck/commands/commands.hpp"
#include "marchcheck/march/render.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <iostream>
#include <unistd.h>

namespace {
// Every way out of main joins the render's worker threads first (see join_render_workers).
struct RenderWorkersJoinedAtExit {
  RenderWorkersJoinedAtExit() = default;
  RenderWorkersJoinedAtExit(const RenderWorkersJoinedAtExit&) = delete;
  RenderWorkersJoinedAtExit& operator=(const RenderWorkersJoinedAtExit&) = delete;
  ~RenderWorkersJoinedAtExit() { marchcheck::march::join_render_workers(); }
};
}  // namespace

int main(int argc, char** argv) {
  const RenderWorkersJoinedAtExit workers;
  using namespace marchcheck::commands;
  CLI::App app{"marchcheck: numerical validation of signed-distance-field ray marching"};
  app.require_subcommand(1);

  ScenesCommand scenes;
  auto* scenes_cmd = app.add_subcommand("scenes", "List the built-in scenes, their SDF kind and Lipschitz bound");
  scenes_cmd->add_flag("--json", scenes.json, "Print the list as JSON");
  scenes_cmd->add_option("--export", scenes.export_name, "Print the named built-in scene as a scene file");
  scenes_cmd->add_option("--export-glsl", scenes.export_glsl,
                         "Print a built-in scene or a scene file as a Shadertoy shader (mainImage, map, marcher)");

  RenderCommand render;
  auto* render_cmd = app.add_subcommand("render", "Render a scene (PNG: 8-bit sRGB, EXR: float) and its AOVs");
  render_cmd->add_option("scene", render.scene, "Built-in scene name or scene file (.json)")->required();
  render_cmd->add_option("-o,--output", render.output, "Output image (.png or .exr)");
  render_cmd->add_option("--size", render.size, "Image size WIDTHxHEIGHT");
  render_cmd->add_option("--aov", render.aovs, "Extra outputs: depth,normal,steps,evals,id,stages (per-stage evaluation heat maps),error (heat map of the colour difference from a reference render)");
  render_cmd->add_option("--stats", render.stats, "Write the cost per stage as JSON");
  render_cmd->add_flag("--reference", render.reference, "Render from the exact references instead of marching");
  render_cmd->add_option("--set", render.sets, "Override a scene or marching parameter KEY=VALUE (repeatable)");

  ValidateCommand validate;
  auto* validate_cmd = app.add_subcommand("validate", "Run every check on scenes; exit 0 all pass, 1 a check failed");
  validate_cmd->add_option("scenes", validate.scenes, "Built-in scene names, scene files, or all")->required();
  validate_cmd->add_option("--json", validate.json, "Write the metrics and checks as JSON");
  validate_cmd->add_option("--set", validate.sets, "Override a scene or marching parameter KEY=VALUE (repeatable)");
  validate_cmd->add_option("--function", validate.function, "A .glsl file's field function (default map)");
  validate_cmd->add_option("--march", validate.march,
                           "A .glsl file's own marcher, run on the GL driver: float|vec2|vec4 NAME(vec3 ro, vec3 rd) "
                           "(t is .x), or NAME.member for a struct");
  validate_cmd->add_option("--normal", validate.normal, "With --march: the file's vec3 NAME(vec3 p) normal function");
  validate_cmd->add_option("--shard", validate.shard,
                           "I/N: validate only scenes I, I+N, I+2N, ... (from 0) into --json, a shard file for merge");

  StabilityCommand stability;
  auto* stability_cmd = app.add_subcommand("stability", "The hard-case battery; exit 0 all stable, 1 a case is not");
  stability_cmd->add_option("--json", stability.json, "Write every case's criterion, numbers and verdict as JSON");
  stability_cmd->add_flag("--naive", stability.naive, "Run each case's naive variant instead (each should be unstable)");
  stability_cmd->add_flag("--full", stability.full, "Include the slow sizes (the 1.3M-triangle mesh)");

  std::string all_dir = "reports/out";
  SliceCommand slice;
  auto* slice_cmd = app.add_subcommand("slice", "Draw a plane through the field: distance bands and |grad f| - 1, with "
                                                "the squares where the certified slope exceeds the declared constant");
  slice_cmd->add_option("scene", slice.scene, "Built-in scene name, scene file (.json) or GLSL file")->required();
  slice_cmd->add_option("--plane", slice.plane, "The plane, x=VALUE, y=VALUE or z=VALUE (default: y through the camera's target)");
  slice_cmd->add_option("-o,--output", slice.output, "Output image (.png)")->capture_default_str();
  slice_cmd->add_option("--size", slice.size, "Size of each panel WIDTHxHEIGHT (default 512x512)");
  slice_cmd->add_option("--set", slice.sets, "Override a scene parameter KEY=VALUE (repeatable)");
  auto* all_cmd = app.add_subcommand("render-all", "Render every built-in scene into a folder");
  all_cmd->add_option("-o,--output", all_dir, "Folder for the images");

  SweepCommand sweep;
  auto* sweep_cmd = app.add_subcommand("sweep", "Accuracy and cost of every combination of parameters, and the Pareto front");
  sweep_cmd->add_option("scene", sweep.scene, "Built-in scene name, scene file (.json), or with --march a .glsl file")
      ->required();
  sweep_cmd->add_option("--vary", sweep.vary, "KEY=V1,V2,... (repeatable; every combination is run); linked keys K1:K2=A1:A2,B1:B2")->required();
  sweep_cmd->add_option("--target", sweep.targets, "METRIC=VALUE: name the cheapest combination with METRIC <= VALUE (repeatable)");
  sweep_cmd->add_option("--error", sweep.error_metric, "The error metric of the Pareto front")->capture_default_str();
  sweep_cmd->add_option("--repeat", sweep.repeat, "Timed renders per combination (seconds = their median)")->capture_default_str();
  sweep_cmd->add_option("--width", sweep.render_width, "Width of the timed render")->capture_default_str();
  sweep_cmd->add_option("--json", sweep.json, "Write every combination's metrics as JSON");
  sweep_cmd->add_option("--csv", sweep.csv, "Write every combination's metrics as CSV");
  sweep_cmd->add_option("--set", sweep.sets, "Override a scene or marching parameter KEY=VALUE (repeatable)");
  sweep_cmd->add_option("--march", sweep.march,
                        "A .glsl file's own marcher on the GL driver (as validate's); --vary glsl.NAME=... sets the "
                        "shader's #define or uniform NAME");
  sweep_cmd->add_option("--normal", sweep.normal, "With --march: the file's normal function");
  sweep_cmd->add_option("--function", sweep.function, "With --march: the field the marcher calls (default map)");
  sweep_cmd->add_option("--shard", sweep.shard,
                        "I/N: run only combinations I, I+N, I+2N, ... (from 0) into --json, a shard file for merge");

  MergeCommand merge;
  auto* merge_cmd = app.add_subcommand("merge", "Put the shard files of a sweep or validate run (--shard I/N) together: "
                                                "the table and files one process makes");
  merge_cmd->add_option("shards", merge.shards, "Every shard file of the run, in any order")->required();
  merge_cmd->add_option("-o,--json", merge.output, "Write the run's result file (as its --json)");
  merge_cmd->add_option("--csv", merge.csv, "Write a sweep's CSV file");

  CompareCommand compare;
  auto* compare_cmd = app.add_subcommand("compare", "Compare two validate/sweep result files; exit 1 on a regression");
  compare_cmd->add_option("baseline", compare.baseline, "Baseline result file (JSON)")->required();
  compare_cmd->add_option("current", compare.current, "Current result file (JSON)")->required();
  compare_cmd->add_option("--tolerance", compare.tolerances,
                          "METRIC=REL relative tolerance (METRIC may end in *; default 1e-6; seconds are only "
                          "compared when a tolerance names them)");

  ReportCommand report;
  auto* report_cmd = app.add_subcommand("report", "The accuracy report: validate every built-in scene, run the "
                                                  "standard sweeps, write an HTML report");
  report_cmd->add_option("-o,--output", report.dir, "Report folder (replaced as a whole)")->capture_default_str();
  report_cmd->add_option("scenes", report.scenes,
                         "Scenes to report on: names, scene files, .glsl files, all (default: every built-in)");
  report_cmd->add_flag("--quick", report.quick, "Fewer sweep points and smaller images");
  report_cmd->add_option("--set", report.sets, "Override a scene or marching parameter KEY=VALUE (repeatable)");

  const auto subcommands = app.get_subcommands({});
  const bool known = argc > 1 && std::any_of(subcommands.begin(), subcommands.end(),
                                             [&](const CLI::App* sub) { return sub->get_name() == argv[1]; });
  if (argc > 1 && argv[1][0] != '-' && !known) {
    std::cerr << "marchcheck: unknown command '" << argv[1] << "'; expected one of";
    for (const auto* sub : subcommands) std::cerr << " " << sub->get_name();
    std::cerr << "\n";
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 2;
  }
  if (*scenes_cmd) return run_scenes(scenes, std::cout, std::cerr);
  if (*render_cmd) return run_render(render, std::cout, std::cerr);
  if (*slice_cmd) return run_slice(slice, std::cout, std::cerr);
  if (*validate_cmd) return run_validate(validate, std::cout, std::cerr);
  if (*sweep_cmd) {
    sweep.progress = ::isatty(STDERR_FILENO) != 0;
    return run_sweep(sweep, std::cout, std::cerr);
  }
  if (*merge_cmd) return run_merge(merge, std::cout, std::cerr);
  if (*compare_cmd) return run_compare(compare, std::cout, std::cerr);
  if (*report_cmd) {
    report.progress = ::isatty(STDERR_FILENO) != 0;
    return run_report(report, std::cout, std::cerr);
  }
  if (*stability_cmd) return run_stability(stability, std::cout, std::cerr);
  return run_render_all(all_dir, std::cout, std::cerr);
}
