#include "mpi_world.hpp"

#include <cstdlib>
#include <stdexcept>

#ifdef MARCHCHECK_MPI
#include <mpi.h>
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

struct Joined {
  MpiWorld world;
  Joined() {
    MPI_Init(nullptr, nullptr);
    MPI_Comm_rank(MPI_COMM_WORLD, &world.rank);
    MPI_Comm_size(MPI_COMM_WORLD, &world.size);
  }
  ~Joined() { MPI_Finalize(); }
};

}  // namespace

std::optional<MpiWorld> launched_world() {
  if (!launched_size()) return std::nullopt;
  static const Joined joined;  // left when the program exits
  return joined.world;
}

std::vector<std::string> gather_to_root(const std::string& piece) {
  const MpiWorld world = *launched_world();
  int length = static_cast<int>(piece.size());
  std::vector<int> lengths(static_cast<size_t>(world.size)), offsets(lengths.size());
  MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  std::string all;
  if (world.rank == 0) {
    long total = 0;
    for (size_t r = 0; r < lengths.size(); ++r) {
      offsets[r] = static_cast<int>(total);
      total += lengths[r];
    }
    all.resize(static_cast<size_t>(total));
  }
  MPI_Gatherv(piece.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR, 0, MPI_COMM_WORLD);
  std::vector<std::string> pieces;
  if (world.rank == 0)
    for (size_t r = 0; r < lengths.size(); ++r)
      pieces.push_back(all.substr(static_cast<size_t>(offsets[r]), static_cast<size_t>(lengths[r])));
  return pieces;
}

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
