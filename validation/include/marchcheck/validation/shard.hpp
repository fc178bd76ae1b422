// One share of a fixed list of work items (a sweep's combinations, validate's scenes), so that a run can be split
// over processes, machines or a batch scheduler's array and merged back into exactly the single process's result.
#pragma once

#include <cstddef>
#include <string>

namespace marchcheck::validation {

// Item i belongs to shard i mod count: shards are a function of the item's index alone (no shard needs to know
// another's progress), and neighbouring items, which a sweep's last axis makes alike in cost, go to different shards.
struct Shard {
  size_t index = 0;  // counted from 0, as MPI ranks and Slurm's --array=0-(N-1) count
  size_t count = 1;
  bool holds(size_t item) const { return item % count == index; }
  bool whole() const { return count == 1; }
  // How many of `items` items this shard holds.
  size_t share_of(size_t items) const { return items / count + (index < items % count ? 1 : 0); }
};

// "I/N" with 0 <= I < N; throws sdf::SceneError naming the option when it is not.
Shard parse_shard(const std::string& text);

}  // namespace marchcheck::validation
