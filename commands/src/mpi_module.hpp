// What marchcheck does through MPI, in a module of its own, libmarchcheck_mpi.so, loaded only in a process an MPI
// launcher started: Open MPI (libmpi, open-rte, open-pal, hwloc, libevent) cost every command ~2.4 ms of dynamic
// loading when the commands library linked it.
#pragma once

#include "mpi_world.hpp"

#include <string>
#include <vector>

namespace marchcheck::commands {

struct MpiModule {
  // Joins the job (MPI_Init; MPI_Finalize when the program exits): this rank and the job's size.
  MpiWorld (*join)();
  // As gather_to_root, once joined.
  std::vector<std::string> (*gather_to_root)(const std::string& piece);
};

}  // namespace marchcheck::commands
