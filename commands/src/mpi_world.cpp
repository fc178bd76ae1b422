#include "mpi_world.hpp"

#include <cstdlib>
#include <stdexcept>

#ifdef MARCHCHECK_MPI
#include "mpi_module.hpp"

#include "marchcheck/files/loadable_module.hpp"
#endif

namespace marchcheck::commands {

namespace {

// How many processes a launcher started, from the variables it sets: Open MPI's mpirun, and MPICH's or Slurm's
// PMI; PMIx alone says only that there is a job (then MPI_Comm_size tells).
std::optional<int> launched_size() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* value = std::getenv(name)) return std::atoi(value);
  if (std::getenv("PMIX_RANK") != nullptr) return 0;
  return std::nullopt;
}

}  // namespace

#ifdef MARCHCHECK_MPI

namespace {

const MpiModule& mpi_module() {
  static const MpiModule& module = files::module_table<MpiModule>(
      reinterpret_cast<const void*>(&launched_world), "libmarchcheck_mpi.so", "marchcheck_mpi_module");
  return module;
}

}  // namespace

std::optional<MpiWorld> launched_world() {
  if (!launched_size()) return std::nullopt;
  return mpi_module().join();
}

std::vector<std::string> gather_to_root(const std::string& piece) { return mpi_module().gather_to_root(piece); }

#else

std::optional<MpiWorld> launched_world() {
  if (const auto size = launched_size(); size && *size > 1)
    throw std::runtime_error("started as one of " + std::to_string(*size) + " processes by an MPI launcher, but this "
                             "marchcheck was built without MPI, so each would do the whole run: build it with Open "
                             "MPI (libopenmpi-dev), or give each process its own --shard I/N");
  return std::nullopt;
}

// Without MPI there is never a world to gather in: launched_world() has none.
std::vector<std::string> gather_to_root(const std::string& piece) { return {piece}; }

#endif

}  // namespace marchcheck::commands
