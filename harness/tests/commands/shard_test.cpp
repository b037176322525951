// Sharding and merging: the split of a work list (common/shard.h) and `fx2d-bench merge`. The
// end-to-end tests run three shards as three concurrent fx2d-bench processes, merge their files,
// and require the merged file to hold exactly the unsharded run's work items, with every
// deterministic field equal: accuracy, state hashes, settings, stability boundaries and
// evaluations. Timings, and the fronts a sweep derives from them, are the only fields left out.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "tests/support/bench_process.h"
#include "analysis/stability_costs.h"
#include "analysis/stability_tests.h"
#include "common/errors.h"
#include "engines/engine.h"
#include "common/shard.h"
#include "storage/h5_tables.h"
#include "storage/results_h5.h"

namespace fxbench {
namespace {

namespace fs = std::filesystem;
using bench_test::BenchProcess;
using bench_test::Ending;
using bench_test::run_bench;

fs::path fresh_directory(const std::string& name) {
  const fs::path directory = fs::temp_directory_path() / ("fx2d_shard_test_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(directory);
  fs::create_directories(directory);
  return directory;
}

// The stability cost table holds every pair of the suite and the registry's engines: a pair left
// out costs 1 s, which for a new engine's pyramid (seconds) or its quick tests (hundredths) puts
// the shards out of balance.
TEST(StabilityCosts, EveryTestOfTheSuiteOnEveryEngineOfTheRegistryIsMeasured) {
  for (const StabilityTest& test : stability_suite())
    for (const EngineInfo& engine : engine_registry())
      EXPECT_TRUE(stability_cost_measured(test.name, engine.name)) << test.name << " on " << engine.name;
}

// The boundaries a spread search predicts from are the stability golden's: a re-baselined boundary
// that leaves this table behind would cost the shards their balance, unseen.
TEST(StabilityCosts, EveryStoredLastPassIsTheFullGoldensBoundary) {
  std::ifstream file(fs::path(FX2D_SOURCE_DIR) / "goldens" / "stability_full.json");
  ASSERT_TRUE(file) << "goldens/stability_full.json";
  const nlohmann::json golden = nlohmann::json::parse(file);
  for (const nlohmann::json& row : golden.at("results")) {
    const std::string test = row.at("test"), engine = row.at("engine");
    const std::optional<double> stored = stability_last_pass(test, engine);
    if (row.at("last_pass").is_null()) {
      EXPECT_FALSE(stored.has_value()) << test << " on " << engine;
    } else {
      EXPECT_EQ(stored, std::optional<double>(row.at("last_pass").get<double>())) << test << " on " << engine;
    }
  }
}

TEST(ShardSpec, ParsesKOfNAndRefusesTheRest) {
  EXPECT_EQ(parse_shard("2/3").index, 2);
  EXPECT_EQ(parse_shard("2/3").count, 3);
  for (const char* bad : {"0/3", "4/3", "3", "/3", "1/0", "a/b", "1/3x", "-1/3", ""})
    EXPECT_THROW(parse_shard(bad), InputError) << bad;
}

TEST(ShardSpec, AutoReadsTheCiMatrixThenSlurmAndRefusesWhenNeitherIsSet) {
  unsetenv("FX2D_SHARD_INDEX");
  unsetenv("FX2D_SHARD_COUNT");
  unsetenv("SLURM_ARRAY_TASK_ID");
  unsetenv("SLURM_ARRAY_TASK_COUNT");
  EXPECT_THROW(parse_shard("auto"), InputError);
  setenv("SLURM_ARRAY_TASK_ID", "0", 1);
  setenv("SLURM_ARRAY_TASK_COUNT", "4", 1);
  EXPECT_EQ(parse_shard("auto").text(), "1/4");
  setenv("FX2D_SHARD_INDEX", "2", 1);
  setenv("FX2D_SHARD_COUNT", "3", 1);
  EXPECT_EQ(parse_shard("auto").text(), "3/3");
  setenv("FX2D_SHARD_INDEX", "3", 1);
  EXPECT_THROW(parse_shard("auto"), InputError);
  unsetenv("FX2D_SHARD_INDEX");
  unsetenv("FX2D_SHARD_COUNT");
  unsetenv("SLURM_ARRAY_TASK_ID");
  unsetenv("SLURM_ARRAY_TASK_COUNT");
}

TEST(ShardSplit, EveryItemBelongsToExactlyOnePart) {
  const std::vector<double> costs{5, 1, 3, 3, 2, 8, 1, 1, 4, 2};
  std::vector<std::size_t> seen;
  for (int k = 1; k <= 3; ++k)
    for (std::size_t item : items_of({k, 3}, costs)) seen.push_back(item);
  std::ranges::sort(seen);
  std::vector<std::size_t> all(costs.size());
  std::iota(all.begin(), all.end(), std::size_t{0});
  EXPECT_EQ(seen, all);
}

TEST(ShardSplit, BalancesByCostNotByCount) {
  // One item as costly as all the others together: by count, part 1 would take it and half the
  // rest (15 of 20); by cost it stands alone, and both parts cost 10.
  const std::vector<double> costs{10, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
  const std::vector<int> parts = assign_parts(costs, 2);
  double load[2] = {0, 0};
  for (std::size_t i = 0; i < costs.size(); ++i) load[parts[i]] += costs[i];
  EXPECT_EQ(load[0], 10);
  EXPECT_EQ(load[1], 10);
  EXPECT_EQ(std::ranges::count(parts, parts[0]), 1);
}

TEST(ShardSplit, ASpreadableItemAboveAFairShareIsCutIntoPiecesOnDifferentParts) {
  // A fair share of 3 parts is 10: the first item, 25, is cut in 3 pieces of 8.33, one per part;
  // the second, as costly but not spreadable, stays whole; a cheap spreadable one stays whole.
  const std::vector<double> costs{25, 3, 1, 1};
  const std::vector<bool> spreadable{true, false, true, false};
  std::vector<std::pair<std::size_t, int>> seen;
  for (int k = 1; k <= 3; ++k) {
    const std::vector<ItemPiece> mine = pieces_of({k, 3}, costs, spreadable);
    EXPECT_EQ(std::ranges::count(mine, std::size_t{0}, &ItemPiece::item), 1) << "part " << k;
    for (const ItemPiece& piece : mine) {
      EXPECT_EQ(piece.pieces, piece.item == 0 ? 3 : 1);
      seen.emplace_back(piece.item, piece.piece);
    }
  }
  std::ranges::sort(seen);
  const std::vector<std::pair<std::size_t, int>> all{{0, 0}, {0, 1}, {0, 2}, {1, 0}, {2, 0}, {3, 0}};
  EXPECT_EQ(seen, all);
  // Unsharded, nothing is spread.
  for (const ItemPiece& piece : pieces_of({1, 1}, costs, spreadable)) EXPECT_EQ(piece.pieces, 1);
}

// The shard's command line: `command` with --shard K/3 --out <directory>/shardK.h5.
std::vector<Ending> run_three_shards(const std::vector<std::string>& command, const fs::path& directory) {
  std::vector<std::unique_ptr<BenchProcess>> shards;
  for (int k = 1; k <= 3; ++k) {
    std::vector<std::string> arguments = command;
    const fs::path place = directory / ("shard" + std::to_string(k));
    fs::create_directories(place);
    arguments.insert(arguments.end(), {"--shard", std::to_string(k) + "/3", "--out", (place / "out.h5").string()});
    shards.push_back(std::make_unique<BenchProcess>(arguments, place));
  }
  std::vector<Ending> endings;
  for (const auto& shard : shards) endings.push_back(shard->finish());
  return endings;
}

// Runs `command` whole and as three shards, merges the shards, and returns the two files.
std::pair<fs::path, fs::path> unsharded_and_merged(const std::vector<std::string>& command, const fs::path& directory) {
  std::vector<std::string> whole = command;
  whole.insert(whole.end(), {"--out", (directory / "whole.h5").string()});
  const Ending unsharded = run_bench(whole, directory);
  EXPECT_EQ(unsharded.exit_code, 0) << unsharded.err;
  for (const Ending& shard : run_three_shards(command, directory)) EXPECT_EQ(shard.exit_code, 0) << shard.err;
  const fs::path merged = directory / "merged.h5";
  // Given out of order: merge orders the shards itself.
  const Ending merging = run_bench({"merge", merged.string(), (directory / "shard3/out.h5").string(),
                                    (directory / "shard1/out.h5").string(), (directory / "shard2/out.h5").string()},
                                   directory);
  EXPECT_EQ(merging.exit_code, 0) << merging.err;
  return {directory / "whole.h5", merged};
}

const H5Column& named(const H5Table& table, const std::string& name) {
  const auto found = std::ranges::find(table.columns, name, &H5Column::name);
  if (found == table.columns.end()) throw std::runtime_error(table.path + " has no column " + name);
  return *found;
}

// Equal element by element, a NaN (a boundary the search never found) equal to a NaN.
bool same_values(const H5Column& a, const H5Column& b) {
  if (!std::holds_alternative<std::vector<double>>(a.values)) return a.values == b.values;
  const auto& x = std::get<std::vector<double>>(a.values);
  const auto& y = std::get<std::vector<double>>(b.values);
  return std::ranges::equal(x, y, [](double p, double q) { return p == q || (std::isnan(p) && std::isnan(q)); });
}

void expect_same_columns(const H5Table& whole, const H5Table& merged, const std::set<std::string>& timed) {
  ASSERT_EQ(whole.columns.size(), merged.columns.size()) << whole.path;
  for (const H5Column& column : whole.columns) {
    if (timed.contains(column.name)) continue;
    EXPECT_TRUE(same_values(column, named(merged, column.name))) << whole.path << "/" << column.name;
  }
}

TEST(Merge, ThreeStabilityShardsAsProcessesMergeToTheUnshardedSuite) {
  const fs::path directory = fresh_directory("stability");
  const auto [whole, merged] = unsharded_and_merged({"stability", "--quick"}, directory);
  // Pyramid on ODE costs more than a third of the suite: its search was spread over the shards.
  const H5Table first_shard = read_table_h5(directory / "shard1/out.h5", "/stability");
  EXPECT_TRUE(std::ranges::any_of(std::get<std::vector<std::int32_t>>(named(first_shard, "pieces").values),
                                  [](std::int32_t pieces) { return pieces == 3; }));
  expect_same_columns(read_table_h5(whole, "/stability"), read_table_h5(merged, "/stability"), {});
  expect_same_columns(read_table_h5(whole, "/stability/evaluations"), read_table_h5(merged, "/stability/evaluations"), {});
  EXPECT_GT(std::get<std::vector<std::string>>(named(read_table_h5(whole, "/stability"), "test").values).size(), 3u);
  fs::remove_all(directory);
}

TEST(Merge, ThreeSweepShardsAsProcessesMergeToTheUnshardedSweep) {
  const fs::path directory = fresh_directory("sweep");
  const auto [whole, merged] = unsharded_and_merged(
      {"sweep", "stacks", "--bodies", "10", "--steps", "20", "--repeats", "1", "--fx2d-substeps", "1,2", "--fx2d-passes",
       "1", "--box2d-velocity", "1,2", "--box2d-position", "1", "--ode-iterations", "5,10", "--dt", "0.01,0.02"},
      directory);
  expect_same_columns(
      read_table_h5(whole, "/sweep"), read_table_h5(merged, "/sweep"),
      {"ms_per_step", "ms_per_step_ci_low", "ms_per_step_ci_high", "ms_per_simulated_s", "cost_vs_default",
       "cost_vs_default_ci_low", "cost_vs_default_ci_high", "on_front", "front_rank", "dominated_by"});
  const ResultSet whole_runs = read_results_h5(whole);
  const ResultSet merged_runs = read_results_h5(merged);
  ASSERT_EQ(whole_runs.runs.size(), merged_runs.runs.size());
  for (std::size_t i = 0; i < whole_runs.runs.size(); ++i) {
    const RunRecord& a = whole_runs.runs[i];
    const RunRecord& b = merged_runs.runs[i];
    EXPECT_EQ(a.engine, b.engine);
    EXPECT_EQ(a.engine_settings, b.engine_settings);
    EXPECT_EQ(a.scene_hash, b.scene_hash);
    EXPECT_EQ(a.state_hashes, b.state_hashes);
    EXPECT_EQ(a.final_state_hash, b.final_state_hash);
    EXPECT_EQ(a.accuracy, b.accuracy);
  }
  EXPECT_TRUE(whole_runs.scenes == merged_runs.scenes);
  fs::remove_all(directory);
}

TEST(Merge, ThreeRunShardsAsProcessesMergeToTheUnshardedRunOfEveryScene) {
  const fs::path directory = fresh_directory("run");
  const auto [whole, merged] = unsharded_and_merged(
      {"run", "pile", "stacks", "settling_boxes", "--bodies", "10", "--steps", "20", "--repeats", "2"}, directory);
  const ResultSet whole_runs = read_results_h5(whole);
  const ResultSet merged_runs = read_results_h5(merged);
  EXPECT_FALSE(has_table_h5(merged, "/shard"));
  EXPECT_TRUE(whole_runs.scenes == merged_runs.scenes);
  ASSERT_EQ(whole_runs.runs.size(), 12u);  // 4 engines x 3 scenes
  ASSERT_EQ(merged_runs.runs.size(), 12u);
  for (std::size_t i = 0; i < whole_runs.runs.size(); ++i) {
    const RunRecord& a = whole_runs.runs[i];
    const RunRecord& b = merged_runs.runs[i];
    EXPECT_EQ(a.engine + " " + a.scene, b.engine + " " + b.scene);
    EXPECT_EQ(a.scene_hash, b.scene_hash);
    EXPECT_EQ(a.state_hashes, b.state_hashes);
    EXPECT_EQ(a.final_state_hash, b.final_state_hash);
    EXPECT_EQ(a.accuracy, b.accuracy);
    EXPECT_EQ(a.repeats, b.repeats);
  }
  fs::remove_all(directory);
}

// One line on stderr naming what is wrong, exit 2.
void expect_refused(const Ending& ending, const std::string& says) {
  EXPECT_EQ(ending.exit_code, 2);
  EXPECT_NE(ending.err.find(says), std::string::npos) << ending.err;
  EXPECT_EQ(std::ranges::count(ending.err, '\n'), 1) << ending.err;
}

TEST(Merge, RefusesGapsDuplicatesAndShardsOfAnotherWorkList) {
  const fs::path directory = fresh_directory("refusals");
  const std::vector<std::string> command{"stability", "--quick", "--engine", "fx2d", "--test", "friction_ramp,thin_wall,mass_ratio"};
  for (const Ending& shard : run_three_shards(command, directory)) ASSERT_EQ(shard.exit_code, 0) << shard.err;
  std::vector<std::string> other = command;
  other.back() = "friction_ramp,thin_wall";
  other.insert(other.end(), {"--shard", "2/3", "--out", (directory / "other.h5").string()});
  ASSERT_EQ(run_bench(other, directory).exit_code, 0);
  const std::string one = (directory / "shard1/out.h5").string();
  const std::string two = (directory / "shard2/out.h5").string();
  const std::string out = (directory / "merged.h5").string();
  expect_refused(run_bench({"merge", out, one, two}, directory), "shards missing: 3/3");
  expect_refused(run_bench({"merge", out, one, two, one}, directory), "given twice");
  expect_refused(run_bench({"merge", out, one, (directory / "other.h5").string()}, directory), "work list");
  EXPECT_FALSE(fs::exists(out));
  fs::remove_all(directory);
}

// One search alone is more than a shard's fair share, so two shards run a piece of it each; the
// pieces merge into the unsharded row, and one piece alone is a gap.
TEST(Merge, TheTwoPiecesOfOneSpreadSearchMergeToItAndOneAloneIsRefused) {
  const fs::path directory = fresh_directory("pieces");
  const std::vector<std::string> command{"stability", "--quick", "--engine", "ode", "--test", "pyramid"};
  std::vector<std::string> whole = command;
  whole.insert(whole.end(), {"--out", (directory / "whole.h5").string()});
  ASSERT_EQ(run_bench(whole, directory).exit_code, 0);
  std::vector<std::string> parts;
  for (const char* shard : {"1/2", "2/2"}) {
    std::vector<std::string> arguments = command;
    parts.push_back((directory / ("part" + std::string(1, shard[0]) + ".h5")).string());
    arguments.insert(arguments.end(), {"--shard", shard, "--out", parts.back()});
    const Ending part = run_bench(arguments, directory);
    ASSERT_EQ(part.exit_code, 0) << part.err;
    EXPECT_NE(part.out.find("piece " + std::string(shard)), std::string::npos) << part.out;
  }
  const std::string out = (directory / "merged.h5").string();
  ASSERT_EQ(run_bench({"merge", out, parts[1], parts[0]}, directory).exit_code, 0);
  expect_same_columns(read_table_h5(directory / "whole.h5", "/stability"), read_table_h5(out, "/stability"), {});
  expect_same_columns(read_table_h5(directory / "whole.h5", "/stability/evaluations"),
                      read_table_h5(out, "/stability/evaluations"), {});
  expect_refused(run_bench({"merge", (directory / "alone.h5").string(), parts[0]}, directory), "piece 2/2 is in no file given");
  fs::remove_all(directory);
}

}  // namespace
}  // namespace fxbench
