// The accuracy report: the scenes validated, the standard sweeps, studies and the hard-case battery run and
// plotted, all written as one folder with index.html.
#pragma once

#include "marchcheck/sdf/scene.hpp"

#include <filesystem>
#include <ostream>
#include <vector>

namespace marchcheck::reports {

struct ReportOptions {
  bool quick = false;     // fewer sweep points and smaller renders (for tests)
  bool progress = false;  // a line per step on err
};

// Writes the report of the scenes into dir: built in a sibling folder and swapped into place, so that a failure
// leaves the previous report whole. Throws std::runtime_error naming the problem when dir cannot take a report
// (a folder that is not empty and holds no report) or the build fails. Returns 0 when every correct scene
// passes, every defect variant is caught and every hard case is stable; 1 otherwise.
int write_report(std::vector<sdf::Scene> scenes, std::filesystem::path dir, const ReportOptions& options,
                 std::ostream& err);

}  // namespace marchcheck::reports
