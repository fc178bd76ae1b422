// Shard files: one process's share of a sweep's combinations or of validate's scenes (validation::Shard), written
// losslessly with what the run depends on, so that merging every shard gives exactly the result file and the table
// the single process gives. The single process is itself one shard of one, merged: one path, so they cannot drift.
#pragma once

#include "marchcheck/validation/shard.hpp"
#include "marchcheck/validation/sweep.hpp"
#include "marchcheck/validation/validate.hpp"

#include <string>
#include <string_view>
#include <vector>

namespace marchcheck::reports {

// What a run's results depend on. Shards merge only when theirs are equal; each part is kept apart so that a
// refusal can say which one differs.
struct RunConfiguration {
  std::string kind;      // "sweep" or "validate"
  std::string scenes;    // content_hash of the scenes as loaded and of every file they read (meshes, GLSL)
  std::string settings;  // content_hash of the command's settings (axes, targets, overrides, ...)
  std::string program;   // program_version()
  size_t items = 0;      // the length of the work list
  bool operator==(const RunConfiguration&) const = default;
};

// A checksum of text (CRC-64/XZ, as 16 hex digits): it tells configurations apart, it is not a signature.
std::string content_hash(std::string_view text);
// "marchcheck VERSION (COMMIT)": the version and the git commit the build was configured from.
std::string program_version();

// How the sweep's table is printed: its first line and the columns after the error metric.
struct SweepTable {
  std::string title;
  std::vector<std::string> columns;
};

// One scene of a validate run: what the command printed for it, and its result.
struct ValidatedScene {
  size_t index = 0;
  std::string printed;
  validation::SceneResult result;  // its scene, defects, reference, metrics, checks and not_checked
};

struct ShardFile {
  RunConfiguration configuration;
  validation::Shard shard;
  validation::SweepResult sweep;  // kind sweep: the shard's points, each with its index
  SweepTable table;
  std::vector<ValidatedScene> scenes;  // kind validate, in index order
};

// {"kind": "shard", configuration, shard, shards, ...}: every number exactly (non-finite ones as "nan", "inf", "-inf").
std::string shard_json(const ShardFile& shard);
// Throws ResultFileError naming `source` and what is wrong.
ShardFile read_shard_json(std::string_view text, const std::string& source);

struct NamedText {
  std::string name;  // a file name, or "rank 2" for an MPI rank's piece
  std::string text;
};
// The shards of one run as one whole shard (0 of 1; a sweep finished): refused, with ResultFileError naming the
// piece, when a piece is not a shard file, comes from another configuration or another split, repeats a shard, or
// does not hold exactly its shard's items; and when a shard is missing.
ShardFile merge_shards(const std::vector<NamedText>& pieces);

}  // namespace marchcheck::reports
