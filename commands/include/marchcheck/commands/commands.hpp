// The commands behind the command line. Each returns the process exit status (0 ok, 1 a check failed,
// 2 bad input) and prints errors to stderr naming the file or argument at fault.
#pragma once

#include "marchcheck/sdf/scene.hpp"

#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace marchcheck::commands {

// A built-in scene, a scene file or a GLSL file (its scene: sdf::glsl_scene), with "--set KEY=VALUE" overrides
// applied and its tree compiled (tree errors come before any work): what every command that takes scenes loads
// them with. Throws std::exception naming the scene or the option at fault.
sdf::Scene load_scene(const std::string& name_or_path, const std::vector<std::string>& sets);

struct ScenesCommand {
  bool json = false;
  std::optional<std::string> export_name;
  std::optional<std::string> export_glsl;  // a built-in or a scene file, as a Shadertoy shader
};
int run_scenes(const ScenesCommand& cmd, std::ostream& out, std::ostream& err);

struct RenderCommand {
  std::string scene;
  std::string output = "render.png";
  std::optional<std::string> size;  // "WxH"
  std::string aovs;                 // "depth,normal,..."
  std::optional<std::string> stats;
  std::vector<std::string> sets;  // "KEY=VALUE"
  bool reference = false;         // exact references instead of marching
};
int run_render(const RenderCommand& cmd, std::ostream& out, std::ostream& err);

struct SliceCommand {
  std::string scene;
  std::optional<std::string> plane;  // "y=0.5"; default: the horizontal plane through the camera's target
  std::string output = "slice.png";
  std::optional<std::string> size;  // of each panel, "WxH"
  std::vector<std::string> sets;
};
// The field's slice (validation/slice.hpp) as a PNG: distance bands, and |grad f| - 1 with the squares where the
// certified slope exceeds the declared constant outlined.
int run_slice(const SliceCommand& cmd, std::ostream& out, std::ostream& err);

struct ValidateCommand {
  std::vector<std::string> scenes;  // names or files (.json scenes, .glsl fields); "all" = every built-in
  std::optional<std::string> json;
  std::vector<std::string> sets;
  std::string function = "map";  // a .glsl file's field function
  // A .glsl file's own marcher and normal function, run on the GL driver and judged instead of marchcheck's
  // marching of its field (see gpu::UserMarcher for their forms).
  std::string march, normal;
  // "I/N": validate only the scenes i with i mod N = I and write them to --json as a shard file (see merge).
  std::optional<std::string> shard;
};
// Under mpirun (built with MPI), each rank validates its share and rank 0 merges and writes the whole.
int run_validate(const ValidateCommand& cmd, std::ostream& out, std::ostream& err);

struct StabilityCommand {
  std::optional<std::string> json;
  bool naive = false;  // run every case's naive variant instead (each should come out unstable)
  bool full = false;   // the slow sizes (the 1M-triangle mesh)
};
// The hard-case battery: 0 all stable, 1 a case is not, 2 the JSON cannot be written.
int run_stability(const StabilityCommand& cmd, std::ostream& out, std::ostream& err);

// Renders every built-in scene into dir.
int run_render_all(const std::string& dir, std::ostream& out, std::ostream& err);

struct SweepCommand {
  std::string scene;
  std::vector<std::string> vary;     // "KEY=V1,V2,..."
  std::vector<std::string> targets;  // "METRIC=VALUE"
  std::string error_metric = "image.rms";
  int repeat = 3;
  int render_width = 640;
  std::optional<std::string> json, csv;
  std::vector<std::string> sets;
  bool progress = false;  // a progress bar on err
  // A .glsl scene's own marcher on the GL driver (as validate's --march), its axes the shader's own parameters:
  // glsl.NAME for a #define or a uniform.
  std::string march, normal, function = "map";
  std::optional<std::string> shard;  // "I/N": only the combinations i with i mod N = I, to --json as a shard file
};
// Under mpirun (built with MPI), each rank sweeps its share and rank 0 merges, prints and writes the whole.
int run_sweep(const SweepCommand& cmd, std::ostream& out, std::ostream& err);

struct MergeCommand {
  std::vector<std::string> shards;  // the shard files of one sweep or validate run, in any order
  std::optional<std::string> output;  // the run's --json file, as the single process writes it
  std::optional<std::string> csv;     // a sweep's --csv file
};
// The shards put together: the run's table and files exactly as one process makes them. 2 when a shard is missing,
// repeated, or from another run (the message names it); otherwise the run's own status (validate: 1 a scene failed).
int run_merge(const MergeCommand& cmd, std::ostream& out, std::ostream& err);

struct CompareCommand {
  std::string baseline, current;
  std::vector<std::string> tolerances;  // "METRIC=REL" (METRIC may end in '*')
};
int run_compare(const CompareCommand& cmd, std::ostream& out, std::ostream& err);

struct ReportCommand {
  std::string dir = "reports/out";
  std::vector<std::string> scenes;  // names, scene files, .glsl files; "all" or empty: every built-in
  std::vector<std::string> sets;
  bool quick = false;     // fewer sweep points and smaller renders (for tests)
  bool progress = false;  // a line per step on err
};
// Validates the scenes, runs the standard sweeps and studies, plots them, and writes DIR/index.html. The
// report is built in a sibling folder and swapped into place, so an interrupted run leaves the previous
// report whole. Exit 0 when every correct scene passes, every defect variant is caught and every hard case of
// the stability battery is stable; 1 otherwise.
int run_report(const ReportCommand& cmd, std::ostream& out, std::ostream& err);

}  // namespace marchcheck::commands
