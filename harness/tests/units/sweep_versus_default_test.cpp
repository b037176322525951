// Tests of a sweep point's cost against its default's (compare_with_defaults, sweep_grid.h) on
// hand-made runs whose rounds give known ratios: the machine's drift between rounds cancels in the
// pairs, a smaller time step costs more per simulated second, a point without its default
// measured in the same rounds gets no ratio, and the table's line on a default off its front
// quotes the paired ratio beside the medians'.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "analysis/sweep_grid.h"
#include "format/sweep_format.h"

namespace fxbench {
namespace {

constexpr double tolerance = 1e-12;

// A run of `round_ms.size()` rounds of two steps, each step of round k taking round_ms[k].
RunRecord run_of(const std::vector<double>& round_ms) {
  RunRecord run;
  run.steps = 2;
  run.repeats = static_cast<int>(round_ms.size());
  for (const double ms : round_ms) run.wall_ms.insert(run.wall_ms.end(), {ms, ms});
  return run;
}

// Adds a point measured by `run` to `sweep`.
void add_point(Sweep& sweep, const RunRecord& run, double dt, bool is_default, int group = 0) {
  sweep.results.runs.push_back(run);
  PointResult point;
  point.grid.dt = dt;
  point.grid.is_default = is_default;
  point.pareto_group = group;
  point.run = sweep.results.runs.size() - 1;
  sweep.points.push_back(point);
}

TEST(CompareWithDefaults, DriftBetweenRoundsCancelsInThePairs) {
  // The machine ran round 1 three times slower than round 0 for both points: each pair's ratio is
  // 1.5, so the estimate is 1.5 with no width at all, where the rounds' spread is threefold.
  Sweep sweep;
  add_point(sweep, run_of({2.0, 6.0, 4.0}), 0.01, true);
  add_point(sweep, run_of({3.0, 9.0, 6.0}), 0.01, false);
  compare_with_defaults(sweep);
  ASSERT_TRUE(sweep.points[0].vs_default.has_value());
  EXPECT_EQ(sweep.points[0].vs_default->ratio, 1.0);
  EXPECT_EQ(sweep.points[0].vs_default->ci.low, 1.0);
  EXPECT_EQ(sweep.points[0].vs_default->ci.high, 1.0);
  ASSERT_TRUE(sweep.points[1].vs_default.has_value());
  EXPECT_NEAR(sweep.points[1].vs_default->ratio, 1.5, tolerance);
  EXPECT_NEAR(sweep.points[1].vs_default->ci.low, 1.5, tolerance);
  EXPECT_NEAR(sweep.points[1].vs_default->ci.high, 1.5, tolerance);
}

TEST(CompareWithDefaults, ComparesCostPerSimulatedSecondNotPerStep) {
  // The same time per step at half the time step simulates a second in twice the time.
  Sweep sweep;
  add_point(sweep, run_of({1.0, 1.0}), 0.02, true);
  add_point(sweep, run_of({1.0, 1.0}), 0.01, false);
  compare_with_defaults(sweep);
  ASSERT_TRUE(sweep.points[1].vs_default.has_value());
  EXPECT_NEAR(sweep.points[1].vs_default->ratio, 2.0, tolerance);
}

TEST(CompareWithDefaults, TheMedianPairDecidesAndTheIntervalHoldsIt) {
  // Pairs 1.1, 1.2, 1.3, 1.4 and an outlier 3.0: the median pair is 1.3, and the interval, a
  // bootstrap of medians of these pairs, lies within their range.
  Sweep sweep;
  add_point(sweep, run_of({1.0, 1.0, 1.0, 1.0, 1.0}), 0.01, true);
  add_point(sweep, run_of({1.1, 1.2, 1.3, 1.4, 3.0}), 0.01, false);
  compare_with_defaults(sweep);
  const RatioEstimate& estimate = *sweep.points[1].vs_default;
  EXPECT_NEAR(estimate.ratio, 1.3, tolerance);
  EXPECT_GE(estimate.ci.low, 1.1 - tolerance);
  EXPECT_LE(estimate.ci.low, estimate.ratio);
  EXPECT_GE(estimate.ci.high, estimate.ratio);
  EXPECT_LE(estimate.ci.high, 3.0 + tolerance);
}

TEST(CompareWithDefaults, APointWithoutItsDefaultInTheSameRoundsGetsNoRatio) {
  Sweep sweep;
  add_point(sweep, run_of({1.0, 1.0}), 0.01, true, 0);
  add_point(sweep, run_of({2.0, 2.0, 2.0}), 0.01, false, 0);  // another number of rounds (interrupted)
  add_point(sweep, run_of({2.0, 2.0}), 0.01, false, 1);       // its front's default is in another shard
  compare_with_defaults(sweep);
  EXPECT_TRUE(sweep.points[0].vs_default.has_value());
  EXPECT_FALSE(sweep.points[1].vs_default.has_value());
  EXPECT_FALSE(sweep.points[2].vs_default.has_value());
}

TEST(CompareWithDefaults, TheLineOnADefaultOffItsFrontQuotesThePairedRatio) {
  // Two settings of one knob, equally accurate; the other takes half the default's time in every
  // round, so it dominates the default, and the rounds' pairs say 0.5 with no width.
  Sweep sweep;
  add_point(sweep, run_of({2.0, 4.0, 3.0}), 0.01, true);
  add_point(sweep, run_of({1.0, 2.0, 1.5}), 0.01, false);
  for (std::size_t i = 0; i < sweep.points.size(); ++i) {
    PointResult& point = sweep.points[i];
    point.scene = "stacks";
    point.engine = "fx2d";
    point.grid.knobs = {{"workers", i == 0 ? 1 : 2}};
    point.ms_median = i == 0 ? 3.0 : 1.5;
    point.cost = point.ms_median / point.grid.dt;
    point.error = 0.001;
  }
  place_on_fronts(sweep);
  compare_with_defaults(sweep);
  const std::string table = sweep_table(sweep);
  EXPECT_NE(
      table.find(
          "stacks, fx2d default (workers=1): off its front; workers=2 dt=0.01 is at least as accurate at "
          "50% of its cost (paired by round: 0.500 [0.500-0.500])\n"),
      std::string::npos)
      << table;
}

}  // namespace
}  // namespace fxbench
