// Determinism across processes: each canonical scene, at its smallest size, ends in the same
// state whichever process steps it and whatever ran before it in that process, on every engine;
// and Fx2D's final states match goldens/state_hashes.json, which a build with the profiler off
// (-DFX2D_PROFILE=OFF) must match too: the timers may observe the step, never change it.
//
// Two processes differ in heap addresses and in what ran before: one runs each scene once with no
// warm-up, the other after a discarded warm-up trajectory and twice. A hash that depends on an
// address, an uninitialised value or state shared between worlds (ODE's random seed did, see
// engines/ode.cpp) differs between them.
//
// The golden is regenerated, only after a deliberate change to Fx2D's physics, with
//   FX2D_UPDATE_GOLDENS=1 <build>/harness/tests/determinism_test --gtest_filter='*Golden*'
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "tests/support/bench_process.h"

namespace fxbench {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

const fs::path golden_path = fs::path(FX2D_SOURCE_DIR) / "goldens" / "state_hashes.json";

// (engine, scene) -> final state hash, for the canonical scenes at their default (smallest) sizes.
using FinalHashes = std::map<std::pair<std::string, std::string>, std::string>;

class DeterminismTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    directory_ = fs::temp_directory_path() / ("fx2d_determinism_test_" + std::to_string(getpid()));
    fs::create_directories(directory_);
    once_cold_ = final_hashes({"--repeats", "1", "--warmup", "0"});
    twice_after_warmup_ = final_hashes({"--repeats", "2"});
  }
  static void TearDownTestSuite() { fs::remove_all(directory_); }

  // Runs all three canonical scenes on all four engines in one process.
  static FinalHashes final_hashes(const std::vector<std::string>& plan) {
    std::vector<std::string> arguments{"run", "pile", "stacks", "settling_boxes", "--json"};
    arguments.insert(arguments.end(), plan.begin(), plan.end());
    const bench_test::Ending ending = bench_test::run_bench(arguments, directory_);
    EXPECT_EQ(ending.exit_code, 0) << ending.err;
    FinalHashes hashes;
    for (const Json& run : Json::parse(ending.out, nullptr, false).value("runs", Json::array())) {
      EXPECT_TRUE(run["deterministic"].get<bool>()) << run["engine"] << " " << run["scene"] << ": repeats differ";
      hashes[{run["engine"], run["scene"]}] = run["state_hash"];
    }
    EXPECT_EQ(hashes.size(), 12u) << "4 engines x 3 scenes";
    return hashes;
  }

  static inline fs::path directory_;
  static inline FinalHashes once_cold_;
  static inline FinalHashes twice_after_warmup_;
};

TEST_F(DeterminismTest, EveryEngineEndsInTheSameStateInTwoProcesses) {
  ASSERT_FALSE(once_cold_.empty());
  for (const auto& [run, hash] : once_cold_) {
    EXPECT_EQ(twice_after_warmup_[run], hash) << run.first << " on " << run.second;
  }
}

TEST_F(DeterminismTest, Fx2dFinalStatesMatchTheGoldenWhateverTheProfilerSetting) {
  Json actual = Json::object();
  for (const auto& [run, hash] : once_cold_) {
    if (run.first == "fx2d") actual[run.second] = hash;
  }
  ASSERT_EQ(actual.size(), 3u);
  if (std::getenv("FX2D_UPDATE_GOLDENS") != nullptr) {
    std::ofstream(golden_path) << actual.dump(2) << '\n';
    GTEST_SKIP() << "rewrote " << golden_path;
  }
  std::ifstream golden_file(golden_path);
  ASSERT_TRUE(golden_file) << golden_path << " is missing; see this file's first comment";
  EXPECT_EQ(actual, Json::parse(golden_file)) << "regenerate only after a deliberate physics change";
}

}  // namespace
}  // namespace fxbench
