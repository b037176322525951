// Golden output of `fx2d-bench stability --json` on every engine (Fx2D, Box2D, ODE, Chipmunk2D):
// the whole suite in --quick form (about 5 s), and at its defaults (minutes: ODE's pyramids of up to 128
// boxes a side), which runs only with FX2D_STABILITY_FULL=1 (ci/nightly checks the same golden on every
// night). Nothing in it is timed and every engine is deterministic, so the whole document is compared: each
// search's evaluations (parameter, verdict, criterion, step, overrides), the boundary found, the
// engines' versions and settings. Any boundary that moves fails here; moving it is a deliberate
// re-baseline.
//
// Regenerate (never by hand), after a deliberate change to an engine's physics, a stability test
// or the output:
//   FX2D_UPDATE_GOLDENS=1 <build>/harness/tests/stability_golden_test
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tests/support/bench_process.h"
#include "tests/support/json_golden.h"

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

TEST(StabilityGolden, WholeSuiteQuickOnEveryEngineMatchesGolden) {
  expect_stability_golden({"stability", "--quick", "--json"}, "stability_quick.json");
}

// `fx2d-bench stability` with no arguments: every test at its defaults on every engine. An engine
// that refuses a stress would end that test as "engine limit at X" instead of aborting; none does
// today (Fx2D's speed limit, 1000 m/s, is the speed tests' own).
TEST(StabilityGolden, WholeSuiteAtItsDefaultsOnEveryEngineMatchesGolden) {
  const char* full = std::getenv("FX2D_STABILITY_FULL");
  if (full == nullptr || std::string(full) != "1") GTEST_SKIP() << "minutes long: set FX2D_STABILITY_FULL=1 to run it";
  expect_stability_golden({"stability", "--json"}, "stability_full.json");
}

}  // namespace
}  // namespace fxbench
