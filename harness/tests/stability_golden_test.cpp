// Golden output of `fx2d-bench stability --json` for two of the suite's tests on all three
// engines. Nothing in it is timed and every engine is deterministic, so the whole document is
// compared: each search's evaluations (parameter, pass, reason, overrides), the boundary found,
// the engines' versions and settings. The two tests are the quickest (about a second each with
// --quick): the thin wall (a fast circle, tunnelling) and the mass ratio (a heavy box on light ones).
//
// Regenerate (never by hand), after a deliberate change to an engine's physics, a stability test
// or the output:
//   FX2D_UPDATE_GOLDENS=1 <build>/harness/tests/stability_golden_test
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "bench_process.h"
#include "json_golden.h"

namespace fxbench {
namespace {

namespace fs = std::filesystem;
using bench_test::Ending;

TEST(StabilityGolden, ThinWallAndMassRatioOnEveryEngineMatchGolden) {
  const fs::path directory = fs::temp_directory_path() / ("fx2d_stability_golden_test_" + std::to_string(getpid()));
  fs::create_directories(directory);
  const Ending ending = bench_test::run_bench(
      {"stability", "--quick", "--engine", "fx2d,box2d,ode", "--test", "thin_wall,mass_ratio", "--json"}, directory);
  fs::remove_all(directory);
  ASSERT_EQ(ending.exit_code, 0) << ending.err;
  bench_test::expect_json_golden(nlohmann::ordered_json::parse(ending.out), "stability_small.json",
                                 "FX2D_UPDATE_GOLDENS=1 <build>/harness/tests/stability_golden_test");
}

}  // namespace
}  // namespace fxbench
