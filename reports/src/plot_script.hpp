// The report's plot script (reports/plots.py), built into the library so that an installed marchcheck needs no
// file of its source tree.
#pragma once

namespace marchcheck::reports {
extern const char* const kPlotScript;
}
