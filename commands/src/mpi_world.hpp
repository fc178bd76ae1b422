// The MPI job this process was started in, when mpirun (or srun with PMI) started it and marchcheck was built with
// MPI (MARCHCHECK_MPI): joined on the first call, left at exit.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace marchcheck::commands {

struct MpiWorld {
  int rank = 0;
  int size = 1;
};

// None for a process started alone. Throws std::runtime_error when a launcher started several copies of a
// build without MPI: each would do the whole run.
std::optional<MpiWorld> launched_world();

// Collective: every rank's piece, in rank order, at rank 0; nothing at the others.
std::vector<std::string> gather_to_root(const std::string& piece);

}  // namespace marchcheck::commands
