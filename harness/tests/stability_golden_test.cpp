// Golden output of `fx2d-bench stability --json` on all three engines: the whole suite at its
// defaults (about 20 s), and two tests in --quick form. Nothing in it is timed and every engine is
// deterministic, so the whole document is compared: each search's evaluations (parameter, pass,
// reason, overrides), the boundary found, the engines' versions and settings. Any boundary that
// moves fails here; moving it is a deliberate re-baseline.
//
// Regenerate (never by hand), after a deliberate change to an engine's physics, a stability test
// or the output:
//   FX2D_UPDATE_GOLDENS=1 <build>/harness/tests/stability_golden_test
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bench_process.h"
#include "json_golden.h"

namespace fxbench {
namespace {

namespace fs = std::filesystem;
using bench_test::Ending;

void expect_stability_golden(const std::vector<std::string>& arguments, const std::string& golden_name) {
  const fs::path directory = fs::temp_directory_path() / ("fx2d_stability_golden_test_" + std::to_string(getpid()));
  fs::create_directories(directory);
  const Ending ending = bench_test::run_bench(arguments, directory);
  fs::remove_all(directory);
  ASSERT_EQ(ending.exit_code, 0) << ending.err;
  bench_test::expect_json_golden(nlohmann::ordered_json::parse(ending.out), golden_name,
                                 "FX2D_UPDATE_GOLDENS=1 <build>/harness/tests/stability_golden_test");
}

TEST(StabilityGolden, ThinWallAndMassRatioOnEveryEngineMatchGolden) {
  expect_stability_golden({"stability", "--quick", "--engine", "fx2d,box2d,ode", "--test", "thin_wall,mass_ratio", "--json"},
                          "stability_small.json");
}

// `fx2d-bench stability` with no arguments: every test at its defaults on every engine, with
// Fx2D's speed tests ending at its engine limit instead of aborting.
TEST(StabilityGolden, WholeSuiteAtItsDefaultsOnEveryEngineMatchesGolden) {
  expect_stability_golden({"stability", "--json"}, "stability_full.json");
}

}  // namespace
}  // namespace fxbench
