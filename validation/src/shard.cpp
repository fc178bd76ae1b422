#include "marchcheck/validation/shard.hpp"

#include "marchcheck/sdf/scene.hpp"

#include <charconv>

namespace marchcheck::validation {

Shard parse_shard(const std::string& text) {
  const auto bad = [&](const std::string& why) { return sdf::SceneError("--shard " + text + ": " + why); };
  const auto slash = text.find('/');
  if (slash == std::string::npos) throw bad("expected I/N, e.g. 0/4 for the first of four shards");
  const auto number = [&](size_t first, size_t last) {
    size_t value = 0;
    const auto [end, ec] = std::from_chars(text.data() + first, text.data() + last, value);
    if (ec != std::errc() || end != text.data() + last || first == last) throw bad("expected I/N with whole numbers");
    return value;
  };
  const Shard shard{number(0, slash), number(slash + 1, text.size())};
  if (shard.count == 0) throw bad("the number of shards must be at least 1");
  if (shard.index >= shard.count)
    throw bad("shards count from 0, so the index must be below " + std::to_string(shard.count));
  return shard;
}

}  // namespace marchcheck::validation
