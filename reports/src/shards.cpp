#include "marchcheck/reports/shards.hpp"

#include "marchcheck/reports/compare.hpp"

#include <boost/crc.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <limits>
#include <map>

namespace marchcheck::reports {

namespace {

using Json = nlohmann::ordered_json;

// JSON numbers round-trip every finite double (nlohmann writes enough digits and reads them correctly rounded);
// the rest are written as words, so that a merged file's nulls and comparisons are the single process's.
Json exact(double v) {
  if (std::isfinite(v)) return v;
  return std::isnan(v) ? "nan" : v > 0 ? "inf" : "-inf";
}

double exact_value(const Json& j) {
  if (j.is_number()) return j.get<double>();
  const auto word = j.get<std::string>();
  if (word == "nan") return std::numeric_limits<double>::quiet_NaN();
  if (word == "inf" || word == "-inf") return (word == "inf" ? 1 : -1) * std::numeric_limits<double>::infinity();
  throw std::invalid_argument("'" + word + "' is not a number");
}

Json exact_metrics(const std::map<std::string, double>& metrics) {
  Json j = Json::object();
  for (const auto& [name, value] : metrics) j[name] = exact(value);
  return j;
}

std::map<std::string, double> read_metrics(const Json& j) {
  std::map<std::string, double> metrics;
  for (const auto& [name, value] : j.items()) metrics[name] = exact_value(value);
  return metrics;
}

Json scene_result_json(const validation::SceneResult& r) {
  Json checks = Json::array();
  for (const auto& c : r.checks)
    checks.push_back({{"name", c.name}, {"value", exact(c.value)}, {"limit", exact(c.limit)}, {"pass", c.pass},
                      {"limit_source", c.limit_source}, {"why", c.why}});
  return {{"scene", r.scene}, {"defects", r.defects}, {"reference", r.reference}, {"checks", checks},
          {"not_checked", r.not_checked}, {"metrics", exact_metrics(r.metrics)}};
}

validation::SceneResult read_scene_result(const Json& j) {
  validation::SceneResult r;
  r.scene = j.at("scene").get<std::string>();
  r.defects = j.at("defects").get<std::vector<std::string>>();
  r.reference = j.at("reference").get<std::string>();
  for (const auto& c : j.at("checks"))
    r.checks.push_back({c.at("name").get<std::string>(), exact_value(c.at("value")), exact_value(c.at("limit")),
                        c.at("pass").get<bool>(), c.at("limit_source").get<std::string>(), c.at("why").get<std::string>()});
  r.not_checked = j.at("not_checked").get<std::vector<std::string>>();
  r.metrics = read_metrics(j.at("metrics"));
  return r;
}

Json sweep_json_part(const validation::SweepResult& s, const SweepTable& table) {
  Json axes = Json::array(), targets = Json::array(), points = Json::array();
  for (const auto& a : s.axes) axes.push_back({{"key", a.key}, {"values", a.values}});
  for (const auto& t : s.targets) targets.push_back({{"metric", t.metric}, {"value", exact(t.value)}});
  for (const auto& p : s.points) {
    Json settings = Json::array();
    for (const auto& [k, v] : p.settings) settings.push_back({k, v});
    points.push_back({{"index", p.index}, {"settings", settings}, {"pass", p.pass}, {"metrics", exact_metrics(p.metrics)}});
  }
  return {{"scene", s.scene}, {"axes", axes},   {"error_metric", s.error_metric}, {"targets", targets},
          {"title", table.title}, {"columns", table.columns}, {"points", points}};
}

void read_sweep_part(const Json& j, ShardFile& shard) {
  auto& s = shard.sweep;
  s.scene = j.at("scene").get<std::string>();
  for (const auto& a : j.at("axes")) s.axes.push_back({a.at("key").get<std::string>(), a.at("values").get<std::vector<std::string>>()});
  s.error_metric = j.at("error_metric").get<std::string>();
  for (const auto& t : j.at("targets")) s.targets.push_back({t.at("metric").get<std::string>(), exact_value(t.at("value"))});
  shard.table = {j.at("title").get<std::string>(), j.at("columns").get<std::vector<std::string>>()};
  for (const auto& p : j.at("points")) {
    validation::SweepPoint point;
    point.index = p.at("index").get<size_t>();
    for (const auto& kv : p.at("settings")) point.settings.emplace_back(kv.at(0).get<std::string>(), kv.at(1).get<std::string>());
    point.pass = p.at("pass").get<bool>();
    point.metrics = read_metrics(p.at("metrics"));
    s.points.push_back(std::move(point));
  }
}

std::vector<size_t> item_indices(const ShardFile& shard) {
  std::vector<size_t> indices;
  for (const auto& p : shard.sweep.points) indices.push_back(p.index);
  for (const auto& s : shard.scenes) indices.push_back(s.index);
  return indices;
}

std::string shard_name(const validation::Shard& shard) {
  return std::to_string(shard.index) + "/" + std::to_string(shard.count);
}

// Why two configurations differ, part by part.
std::string difference(const RunConfiguration& a, const RunConfiguration& b) {
  if (a.kind != b.kind) return "it is a " + a.kind + " run's shard, not a " + b.kind + " run's";
  if (a.program != b.program) return "it was made by " + a.program + ", not " + b.program;
  if (a.items != b.items) return "its run has " + std::to_string(a.items) + " items, not " + std::to_string(b.items);
  if (a.scenes != b.scenes) return "its scenes differ (content " + a.scenes + " against " + b.scenes + ")";
  return "its settings differ (" + a.settings + " against " + b.settings + ")";
}

// The shard must hold exactly the items its index gives it, in order.
void check_items(const ShardFile& shard, const std::string& name) {
  const auto indices = item_indices(shard);
  size_t expected = shard.shard.index;
  for (const size_t i : indices) {
    if (i != expected)
      throw ResultFileError(name + ": shard " + shard_name(shard.shard) + " should hold item " + std::to_string(expected) +
                            " next, but holds " + std::to_string(i));
    expected += shard.shard.count;
  }
  const size_t share = shard.shard.share_of(shard.configuration.items);
  if (indices.size() != share)
    throw ResultFileError(name + ": shard " + shard_name(shard.shard) + " holds " + std::to_string(indices.size()) +
                          " of its " + std::to_string(share) + " items");
}

}  // namespace

std::string content_hash(std::string_view text) {
  boost::crc_optimal<64, 0x42F0E1EBA9EA3693, ~0ULL, ~0ULL, true, true> crc;
  crc.process_bytes(text.data(), text.size());
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(crc.checksum()));
  return hex;
}

std::string program_version() { return std::string("marchcheck ") + MARCHCHECK_VERSION + " (" + MARCHCHECK_COMMIT + ")"; }

std::string shard_json(const ShardFile& shard) {
  const auto& c = shard.configuration;
  Json j = {{"kind", "shard"},
            {"configuration",
             {{"kind", c.kind}, {"scenes", c.scenes}, {"settings", c.settings}, {"program", c.program}, {"items", c.items}}},
            {"shard", shard.shard.index},
            {"shards", shard.shard.count}};
  if (c.kind == "sweep") {
    j["sweep"] = sweep_json_part(shard.sweep, shard.table);
  } else {
    Json scenes = Json::array();
    for (const auto& s : shard.scenes)
      scenes.push_back({{"index", s.index}, {"printed", s.printed}, {"result", scene_result_json(s.result)}});
    j["scenes"] = scenes;
  }
  return j.dump(1) + "\n";
}

ShardFile read_shard_json(std::string_view text, const std::string& source) {
  ShardFile shard;
  try {
    const Json j = Json::parse(text);
    if (!j.is_object() || j.value("kind", "") != "shard")
      throw ResultFileError(source + ": not a shard file (write one with --shard I/N --json FILE)");
    const Json& c = j.at("configuration");
    shard.configuration = {c.at("kind").get<std::string>(), c.at("scenes").get<std::string>(),
                           c.at("settings").get<std::string>(), c.at("program").get<std::string>(),
                           c.at("items").get<size_t>()};
    shard.shard = {j.at("shard").get<size_t>(), j.at("shards").get<size_t>()};
    if (shard.shard.count == 0 || shard.shard.index >= shard.shard.count)
      throw ResultFileError(source + ": shard " + shard_name(shard.shard) + " does not exist");
    if (shard.configuration.kind == "sweep") {
      read_sweep_part(j.at("sweep"), shard);
    } else if (shard.configuration.kind == "validate") {
      for (const auto& s : j.at("scenes"))
        shard.scenes.push_back({s.at("index").get<size_t>(), s.at("printed").get<std::string>(), read_scene_result(s.at("result"))});
    } else {
      throw ResultFileError(source + ": a shard of '" + shard.configuration.kind + "', expected sweep or validate");
    }
  } catch (const ResultFileError&) {
    throw;
  } catch (const std::exception& e) {
    throw ResultFileError(source + ": not a readable shard file: " + e.what());
  }
  check_items(shard, source);
  return shard;
}

ShardFile merge_shards(const std::vector<NamedText>& pieces) {
  if (pieces.empty()) throw ResultFileError("no shards to merge");
  std::vector<ShardFile> shards;
  std::map<size_t, std::string> named;  // shard index -> the piece that has it
  for (const auto& piece : pieces) {
    shards.push_back(read_shard_json(piece.text, piece.name));
    const ShardFile& s = shards.back();
    const ShardFile& first = shards.front();
    if (!(s.configuration == first.configuration))
      throw ResultFileError(piece.name + ": not from the same run as " + pieces.front().name + ": " +
                            difference(s.configuration, first.configuration));
    if (s.shard.count != first.shard.count)
      throw ResultFileError(piece.name + ": shard " + shard_name(s.shard) + ", but " + pieces.front().name + " is shard " +
                            shard_name(first.shard) + ": the run was split another way");
    const auto [at, added] = named.emplace(s.shard.index, piece.name);
    if (!added) throw ResultFileError(piece.name + " and " + at->second + " are both shard " + shard_name(s.shard));
  }
  const size_t count = shards.front().shard.count;
  for (size_t i = 0; i < count; ++i)
    if (!named.count(i)) {
      const validation::Shard missing{i, count};
      throw ResultFileError("shard " + shard_name(missing) + " is missing (" +
                            std::to_string(missing.share_of(shards.front().configuration.items)) +
                            " items); merging " + std::to_string(named.size()) + " of " + std::to_string(count) + " shards");
    }
  // Item i is the (i / count)-th of shard i mod count: the order is the index's, whatever order the pieces came in.
  std::vector<const ShardFile*> by_index(count);
  for (const auto& s : shards) by_index[s.shard.index] = &s;
  ShardFile whole = *by_index[0];  // what is not an item (the sweep's table) from shard 0, as in one process
  whole.shard = {};
  whole.sweep.points.clear();
  whole.scenes.clear();
  for (size_t i = 0; i < whole.configuration.items; ++i) {
    const ShardFile& from = *by_index[i % count];
    if (whole.configuration.kind == "sweep") whole.sweep.points.push_back(from.sweep.points[i / count]);
    else whole.scenes.push_back(from.scenes[i / count]);
  }
  if (whole.configuration.kind == "sweep") validation::finish_sweep(whole.sweep);
  return whole;
}

}  // namespace marchcheck::reports
