#include "sharded.hpp"

#include "marchcheck/files/atomic_file.hpp"
#include "marchcheck/reports/compare.hpp"
#include "marchcheck/sdf/glsl_field.hpp"
#include "marchcheck/sdf/scene_file.hpp"
#include "mpi_world.hpp"

#include <algorithm>
#include <map>
#include <sstream>

namespace marchcheck::commands {

namespace {

constexpr int kBadInput = 2;

// Files a node and its children read as they run: meshes (not generated ones) and GLSL sources.
void read_files(const sdf::Node& node, std::string& content) {
  std::string path = node.op == sdf::Op::mesh && !node.source.starts_with("procedural:") ? node.source : "";
  if (node.glsl) path = node.glsl->spec().source;
  if (!path.empty()) content += path + "\n" + sdf::read_text_file(path).value_or("(unreadable)") + "\n";
  for (const auto& child : node.children) read_files(child, content);
}

// An MPI rank's piece: its status on the first line, then its shard file or its error message.
std::string rank_piece(int status, const std::string& body) { return std::to_string(status) + "\n" + body; }

// Rank 0: every rank's piece merged and finished, or each failed rank's message (ranks with the same message on
// one line) and no file.
int finish_at_root(const ShardedRun& run, const std::vector<std::string>& pieces, const WholeFinish& finish,
                   std::ostream& out, std::ostream& err) {
  std::map<std::string, std::string> failed;  // message -> the ranks that gave it
  std::vector<reports::NamedText> shards;
  int status = 0;
  for (size_t rank = 0; rank < pieces.size(); ++rank) {
    const auto newline = pieces[rank].find('\n');
    const int piece_status = std::stoi(pieces[rank].substr(0, newline));
    std::string body = pieces[rank].substr(newline + 1);
    if (piece_status == 0) {
      shards.push_back({"rank " + std::to_string(rank), std::move(body)});
      continue;
    }
    status = std::max(status, piece_status);
    auto& ranks = failed[body];
    ranks += (ranks.empty() ? "" : ",") + std::to_string(rank);
  }
  for (const auto& [message, ranks] : failed)
    err << "marchcheck " << run.command << ": rank" << (ranks.find(',') == std::string::npos ? " " : "s ") << ranks
        << ": " << message << "\n";
  if (status != 0) return status;
  try {
    return finish(reports::merge_shards(shards), false, out, err);
  } catch (const std::exception& e) {
    err << "marchcheck " << run.command << ": " << e.what() << "\n";
    return kBadInput;
  }
}

// One rank of an MPI job: its shard's work, gathered to rank 0, which finishes the run. The other ranks exit 0:
// mpirun exits with the status of the first rank that fails.
int run_rank(const ShardedRun& run, const MpiWorld& world, const ShardWork& work, const WholeFinish& finish,
             std::ostream& out, std::ostream& err) {
  std::string piece;
  try {
    if (run.shard) throw sdf::SceneError("--shard " + *run.shard + ": mpirun already splits the run by rank");
    std::ostringstream quiet;  // rank 0 prints every item's lines once merged; no rank draws a progress bar
    const validation::Shard shard{static_cast<size_t>(world.rank), static_cast<size_t>(world.size)};
    piece = rank_piece(0, reports::shard_json(work(shard, quiet, quiet)));
  } catch (const std::exception& e) {
    piece = rank_piece(kBadInput, e.what());
  }
  const std::vector<std::string> pieces = gather_to_root(piece);
  return world.rank == 0 ? finish_at_root(run, pieces, finish, out, err) : 0;
}

}  // namespace

int results_status(const reports::ShardFile& results) {
  const bool failed = std::any_of(results.scenes.begin(), results.scenes.end(),
                                  [](const reports::ValidatedScene& s) { return !s.result.pass(); });
  return failed ? 1 : 0;
}

std::string scenes_hash(const std::vector<sdf::Scene>& scenes) {
  std::string content;
  for (const auto& scene : scenes) {
    content += sdf::scene_to_json(scene);
    read_files(scene.root, content);
  }
  return reports::content_hash(content);
}

int run_sharded(const ShardedRun& run, const ShardWork& work, const WholeFinish& finish, std::ostream& out,
                std::ostream& err) {
  try {
    if (const auto world = launched_world(); world && world->size > 1) return run_rank(run, *world, work, finish, out, err);
    if (!run.shard) {
      const std::string whole = reports::shard_json(work({}, out, err));
      return finish(reports::merge_shards({{"this run", whole}}), true, out, err);
    }
    const validation::Shard shard = validation::parse_shard(*run.shard);
    if (!run.json) throw sdf::SceneError("--shard " + *run.shard + ": needs --json FILE for the shard's results");
    const reports::ShardFile results = work(shard, out, err);
    files::write_bytes_atomically(*run.json, reports::shard_json(results));
    const char* items = results.configuration.kind == "sweep" ? " combinations" : " scenes";
    out << "shard " << *run.shard << ": " << shard.share_of(results.configuration.items) << " of "
        << results.configuration.items << items << " -> " << *run.json << " (marchcheck merge puts the shards together)\n";
    return results_status(results);
  } catch (const std::exception& e) {
    err << "marchcheck " << run.command << ": " << e.what() << "\n";
    return kBadInput;
  }
}

}  // namespace marchcheck::commands
