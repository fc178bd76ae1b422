// The commands behind the command line. Each returns the process exit status (0 ok, 1 a check failed,
// 2 bad input) and prints errors to stderr naming the file or argument at fault.
#pragma once

#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace marchcheck::reports {

struct ScenesCommand {
  bool json = false;
  std::optional<std::string> export_name;
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

struct ValidateCommand {
  std::vector<std::string> scenes;  // names or files; "all" = every built-in
  std::optional<std::string> json;
  std::vector<std::string> sets;
};
int run_validate(const ValidateCommand& cmd, std::ostream& out, std::ostream& err);

struct StabilityCommand {
  std::optional<std::string> json;
  bool naive = false;  // run every case's naive variant instead (each should come out unstable)
  bool full = false;   // the slow sizes (the 1M-triangle mesh)
};
// The hard-case battery: 0 all stable, 1 a case is not, 2 the JSON cannot be written.
int run_stability(const StabilityCommand& cmd, std::ostream& out, std::ostream& err);

// Renders every built-in scene into dir (the main job until the accuracy report exists).
int run_render_all(const std::string& dir, std::ostream& out, std::ostream& err);

}  // namespace marchcheck::reports
