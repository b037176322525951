// Golden output of `fx2d-bench sweep --json` on a tiny grid: two settings of each engine's main
// knob (and each engine's default, which the sweep adds) on a ten-box stack, all three engines.
// Compared exactly: the points' order, settings, time steps, step counts, scene hash, accuracy
// figures, primary error and default flag, whether a point has a cost ratio to its default, and
// which fronts there are. Masked: what a clock decides, the timings and that ratio and, because a
// point's cost is its timing, whether it is on its front, what dominates it and the order of each
// front's points; the machine's figures.
//
// Regenerate (never by hand), after a deliberate change to an engine's physics or to the output:
//   FX2D_UPDATE_GOLDENS=1 <build>/harness/tests/sweep_golden_test
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/support/bench_process.h"
#include "tests/support/json_golden.h"

namespace fxbench {
namespace {

namespace fs = std::filesystem;
using bench_test::Ending;

void mask_timings(nlohmann::ordered_json& sweep) {
  for (auto& point : sweep["points"]) {
    for (const char* key : {"ms_per_step", "ms_per_simulated_s", "on_front", "dominated_by"}) point[key] = "<timing>";
    // Whether a point has a ratio to its default is decided by the plan; its figures by the clock.
    if (!point["cost_vs_default"].is_null()) point["cost_vs_default"] = "<timing>";
  }
  for (auto& front : sweep["fronts"]) front["points"] = "<timing>";
  for (auto& figure : sweep["machine"]) figure = "<timing>";
}

TEST(SweepGolden, TinyGridOnEveryEngineMatchesGoldenApartFromTimings) {
  const fs::path directory = fs::temp_directory_path() / ("fx2d_sweep_golden_test_" + std::to_string(getpid()));
  fs::create_directories(directory);
  const Ending ending = bench_test::run_bench(
      {"sweep", "stacks", "--bodies", "10", "--steps", "60", "--engine", "fx2d,box2d,ode", "--fx2d-substeps", "2,8",
       "--fx2d-passes", "2", "--box2d-velocity", "2,8", "--box2d-position", "3", "--ode-iterations", "5,20",
       "--repeats", "1", "--json"},
      directory);
  fs::remove_all(directory);
  ASSERT_EQ(ending.exit_code, 0) << ending.err;
  auto sweep = nlohmann::ordered_json::parse(ending.out);
  mask_timings(sweep);
  bench_test::expect_json_golden(sweep, "sweep_small.json",
                                 "FX2D_UPDATE_GOLDENS=1 <build>/harness/tests/sweep_golden_test");
}

}  // namespace
}  // namespace fxbench
