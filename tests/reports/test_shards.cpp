// Shard files and their merge: every number comes back exactly, the merge is the single process's result whatever
// order the shards arrive in, and every way a set of shards can fail to be one run is refused, naming the piece.
#include "marchcheck/reports/compare.hpp"
#include "marchcheck/reports/results_io.hpp"
#include "marchcheck/reports/shards.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace marchcheck::reports {
namespace {

using validation::Shard;

// Values a float pipeline produces and JSON text tends to lose: NaN, both infinities, -0, a subnormal, a value
// with 17 significant digits, the largest double.
const std::vector<double> kAwkward = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                                      -std::numeric_limits<double>::infinity(), -0.0, 4.9e-324, 0.1 + 0.2,
                                      std::numeric_limits<double>::max()};

RunConfiguration sweep_configuration(size_t items) { return {"sweep", "scenes-a", "settings-a", "marchcheck test", items}; }

// Point i of a made-up sweep over one axis: error falls and cost rises with i except at every third point (which
// the fronts leave out), and its metrics hold the awkward values.
validation::SweepPoint point(size_t i) {
  validation::SweepPoint p;
  p.index = i;
  p.settings = {{"hit_eps", std::to_string(i)}};
  p.pass = i % 2 == 0;
  const double worse = i % 3 == 2 ? 10 : 0;
  p.metrics = {{"image.rms", 1.0 / double(i + 1) + worse}, {"cost.evals_per_pixel", double(i) + worse},
               {"cost.seconds", double(i) * 1e-3 + worse}, {"odd", kAwkward[i % kAwkward.size()]}};
  return p;
}

ShardFile sweep_shard(const Shard& shard, size_t items) {
  ShardFile f{sweep_configuration(items), shard, {}, {"title", {"odd"}}, {}};
  f.sweep.scene = "crum-torus";
  f.sweep.axes = {{"hit_eps", {}}};
  f.sweep.error_metric = "image.rms";
  f.sweep.targets = {{"cost.evals_per_pixel", 5}};
  for (size_t i = 0; i < items; ++i)
    if (shard.holds(i)) f.sweep.points.push_back(point(i));
  return f;
}

std::vector<NamedText> split(size_t items, size_t count) {
  std::vector<NamedText> pieces;
  for (size_t s = 0; s < count; ++s)
    pieces.push_back({"shard" + std::to_string(s) + ".json", shard_json(sweep_shard({s, count}, items))});
  return pieces;
}

std::string merge_error(const std::vector<NamedText>& pieces) {
  try {
    merge_shards(pieces);
  } catch (const ResultFileError& e) {
    return e.what();
  }
  return "(merged)";
}

TEST(Shard, ItemsGoRoundTheShardsAndEveryShardKnowsItsShare) {
  const Shard shard{1, 3};
  EXPECT_FALSE(shard.holds(0));
  EXPECT_TRUE(shard.holds(1));
  EXPECT_TRUE(shard.holds(4));
  EXPECT_FALSE(shard.whole());
  // 7 items over 3 shards: 0,3,6 | 1,4 | 2,5.
  EXPECT_EQ((Shard{0, 3}.share_of(7)), 3u);
  EXPECT_EQ((Shard{1, 3}.share_of(7)), 2u);
  EXPECT_EQ((Shard{2, 3}.share_of(7)), 2u);
  EXPECT_EQ((Shard{2, 3}.share_of(2)), 0u);  // more shards than items: some hold nothing
}

TEST(Shard, ParsesIndexOverCountFromZeroAndRefusesTheRest) {
  const Shard s = validation::parse_shard("2/5");
  EXPECT_EQ(s.index, 2u);
  EXPECT_EQ(s.count, 5u);
  for (const char* bad : {"3/3", "1/0", "1", "a/3", "1/3x", "-1/3", "/3", "1/"})
    EXPECT_THROW(validation::parse_shard(bad), sdf::SceneError) << bad;
  try {
    validation::parse_shard("3/3");
  } catch (const sdf::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("must be below 3"), std::string::npos) << e.what();
  }
}

// Variant caught: numbers written as JSON writes them (null for NaN and the infinities, as result files do).
TEST(Shards, EveryNumberComesBackBitForBit) {
  const ShardFile back = read_shard_json(shard_json(sweep_shard({0, 1}, 14)), "s.json");
  ASSERT_EQ(back.sweep.points.size(), 14u);
  for (const auto& p : back.sweep.points) {
    const validation::SweepPoint original = point(p.index);
    for (const auto& [name, value] : original.metrics)
      EXPECT_EQ(std::bit_cast<std::uint64_t>(p.metrics.at(name)), std::bit_cast<std::uint64_t>(value))
          << name << " of point " << p.index;
    EXPECT_EQ(p.settings, original.settings);
    EXPECT_EQ(p.pass, original.pass);
  }
  EXPECT_EQ(back.table.title, "title");
  EXPECT_EQ(back.sweep.targets.at(0).value, 5);
}

TEST(Shards, AValidateSceneComesBackWithItsChecksAndLines) {
  validation::SceneResult r;
  r.scene = "lee-flat";
  r.defects = {"fov"};
  r.reference = "certified";
  r.metrics = {{"hit.t_err_max", -std::numeric_limits<double>::infinity()}, {"hit.rays", 2304}};
  r.checks = {{"hit.false_hit", 0.25, 0, false, "default", "no false hits"}};
  r.not_checked = {"image.rms"};
  const ShardFile f{{"validate", "a", "b", "c", 1}, {}, {}, {}, {{0, "lee-flat  FAIL\n", r}}};
  const ShardFile back = read_shard_json(shard_json(f), "v.json");
  ASSERT_EQ(back.scenes.size(), 1u);
  EXPECT_EQ(back.scenes[0].printed, "lee-flat  FAIL\n");
  EXPECT_EQ(validate_json({back.scenes[0].result}), validate_json({r}));
  EXPECT_FALSE(back.scenes[0].result.pass());
  EXPECT_TRUE(std::isinf(back.scenes[0].result.metrics.at("hit.t_err_max")));
}

// Variants caught: fronts computed within each shard, points in arrival order, a merge that keeps shard 0's points.
TEST(Shards, MergedInAnyOrderTheyAreTheWholeRun) {
  ShardFile whole = sweep_shard({0, 1}, 14);
  validation::finish_sweep(whole.sweep);
  const std::string expected = sweep_json(whole.sweep);
  ASSERT_TRUE(whole.sweep.cheapest_meeting.has_value());
  auto pieces = split(14, 3);
  std::swap(pieces[0], pieces[2]);
  const ShardFile merged = merge_shards(pieces);
  EXPECT_EQ(sweep_json(merged.sweep), expected);
  EXPECT_EQ(merged.shard.count, 1u);
  // The single process's path: one shard of one, merged.
  EXPECT_EQ(sweep_json(merge_shards(split(14, 1)).sweep), expected);
  // The fronts are the whole run's: point 2 leads the front of shard 2/3's points alone (every third point is
  // worse), and is dominated in the whole run.
  ShardFile third = sweep_shard({2, 3}, 14);
  validation::mark_pareto(third.sweep.points, "image.rms");
  EXPECT_TRUE(third.sweep.points[0].pareto_evals);
  EXPECT_FALSE(merged.sweep.points[2].pareto_evals);
  EXPECT_TRUE(merged.sweep.points[1].pareto_evals);
}

TEST(Shards, AMissingShardIsRefusedNamingIt) {
  auto pieces = split(14, 3);
  pieces.erase(pieces.begin() + 1);
  const std::string e = merge_error(pieces);
  EXPECT_NE(e.find("shard 1/3 is missing (5 items)"), std::string::npos) << e;
}

TEST(Shards, ARepeatedShardIsRefusedNamingBothFiles) {
  auto pieces = split(14, 3);
  pieces.push_back({"again.json", pieces[2].text});
  const std::string e = merge_error(pieces);
  EXPECT_NE(e.find("again.json and shard2.json are both shard 2/3"), std::string::npos) << e;
}

TEST(Shards, AShardOfAnotherRunIsRefusedSayingWhatDiffers) {
  const auto other = [](const RunConfiguration& c) {
    auto pieces = split(14, 3);
    ShardFile f = sweep_shard({1, 3}, 14);
    f.configuration = c;
    pieces[1] = {"other.json", shard_json(f)};
    return merge_error(pieces);
  };
  RunConfiguration c = sweep_configuration(14);
  c.scenes = "scenes-b";
  EXPECT_NE(other(c).find("other.json: not from the same run as shard0.json: its scenes differ"), std::string::npos)
      << other(c);
  c = sweep_configuration(14);
  c.settings = "settings-b";
  EXPECT_NE(other(c).find("its settings differ"), std::string::npos) << other(c);
  c = sweep_configuration(14);
  c.program = "marchcheck 0.0.9";
  EXPECT_NE(other(c).find("made by marchcheck 0.0.9"), std::string::npos) << other(c);
  c = sweep_configuration(14);
  c.kind = "validate";
  c.items = 0;
  const std::string e = merge_error({split(14, 1)[0], {"v.json", shard_json({c, {}, {}, {}, {}})}});
  EXPECT_NE(e.find("v.json: not from the same run as shard0.json: it is a validate run's shard, not a sweep run's"),
            std::string::npos) << e;
}

TEST(Shards, ShardsOfAnotherSplitAreRefused) {
  auto pieces = split(14, 3);
  pieces[2] = split(14, 4)[2];
  pieces[2].name = "four.json";
  const std::string e = merge_error(pieces);
  EXPECT_NE(e.find("four.json: shard 2/4, but shard0.json is shard 0/3"), std::string::npos) << e;
}

// Variant caught: a shard file cut short, or edited to hold another shard's items.
TEST(Shards, AShardThatDoesNotHoldExactlyItsItemsIsRefused) {
  ShardFile f = sweep_shard({1, 3}, 14);
  f.sweep.points.pop_back();
  std::string e;
  try {
    read_shard_json(shard_json(f), "short.json");
  } catch (const ResultFileError& error) {
    e = error.what();
  }
  EXPECT_NE(e.find("short.json: shard 1/3 holds 4 of its 5 items"), std::string::npos) << e;
  f = sweep_shard({1, 3}, 14);
  f.sweep.points[1].index = 5;
  EXPECT_THROW(read_shard_json(shard_json(f), "moved.json"), ResultFileError);
}

TEST(Shards, AFileThatIsNotAShardIsRefused) {
  ShardFile whole = sweep_shard({0, 1}, 3);
  validation::finish_sweep(whole.sweep);
  const std::string e = merge_error({{"result.json", sweep_json(whole.sweep)}});
  EXPECT_NE(e.find("result.json: not a shard file"), std::string::npos) << e;
  EXPECT_NE(merge_error({{"cut.json", shard_json(whole).substr(0, 100)}}).find("cut.json: not a readable shard file"),
            std::string::npos);
  EXPECT_NE(merge_error({}).find("no shards"), std::string::npos);
}

TEST(Shards, ContentHashIsCrc64XzAndTellsTextsApart) {
  // CRC-64/XZ's check value (the CRC of "123456789"), from the CRC catalogue's entry for it.
  EXPECT_EQ(content_hash("123456789"), "995dc9bbdf1939fa");
  EXPECT_NE(content_hash("crum-torus"), content_hash("crum-torus "));
  EXPECT_EQ(program_version().rfind("marchcheck ", 0), 0u);
}

}  // namespace
}  // namespace marchcheck::reports
