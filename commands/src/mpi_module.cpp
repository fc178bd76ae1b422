// libmarchcheck_mpi.so: Open MPI behind mpi_module.hpp's table.
#include "mpi_module.hpp"

#include <mpi.h>

namespace marchcheck::commands {
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

MpiWorld join() {
  static const Joined joined;  // left when the program exits
  return joined.world;
}

std::vector<std::string> gather(const std::string& piece) {
  const MpiWorld world = join();
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

constexpr MpiModule kModule{join, gather};

}  // namespace
}  // namespace marchcheck::commands

extern "C" const marchcheck::commands::MpiModule* marchcheck_mpi_module() { return &marchcheck::commands::kModule; }
