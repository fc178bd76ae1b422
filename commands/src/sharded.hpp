// Runs a command's work list whole, as one shard of it (--shard I/N, its file merged later by `marchcheck merge`),
// or as one rank of an MPI job (launched by mpirun, every rank's shard gathered to rank 0 and merged there). The
// whole run is itself a shard of one, merged, so the three give the same result file and the same table.
#pragma once

#include "marchcheck/reports/shards.hpp"
#include "marchcheck/sdf/scene.hpp"

#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace marchcheck::commands {

// A shard's work: it prints each item's lines to out as it goes (and any progress bar to progress), and returns
// the shard's results. Throws std::exception on bad input (the message names the file or the option).
using ShardWork =
    std::function<reports::ShardFile(const validation::Shard& shard, std::ostream& out, std::ostream& progress)>;
// What the whole run does with the merged results: prints its table (and each item's lines unless `printed`),
// writes its files, returns its exit status.
using WholeFinish =
    std::function<int(const reports::ShardFile& whole, bool printed, std::ostream& out, std::ostream& err)>;

struct ShardedRun {
  std::string command;               // "sweep" or "validate", for messages
  std::optional<std::string> shard;  // --shard I/N
  std::optional<std::string> json;   // --json: a shard's file
};

int run_sharded(const ShardedRun& run, const ShardWork& work, const WholeFinish& finish, std::ostream& out,
                std::ostream& err);

// The exit status of a run's results: 1 when a validated scene failed a check, else 0.
int results_status(const reports::ShardFile& results);

// content_hash of the scenes as they will run (their scene files as loaded, with overrides) and of every file
// they read (meshes, GLSL sources): what RunConfiguration::scenes holds.
std::string scenes_hash(const std::vector<sdf::Scene>& scenes);

}  // namespace marchcheck::commands
