// Tests of compare's statistics on synthetic samples with known answers: medians, the bootstrap
// interval (its bounds, its determinism, a known shift found, paired rounds against independent
// ones), the rank tests against examples worked by hand, and the two-stage verdict at each of its
// boundaries.
#include "stats/statistics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace fxbench {
namespace {

// n values spread evenly over [centre * (1 - spread), centre * (1 + spread)], in a scrambled
// order (7 is coprime with the counts used) so that no test depends on sorted input.
std::vector<double> noisy(double centre, double spread, int n) {
  std::vector<double> values;
  for (int i = 0; i < n; ++i) {
    const int slot = (7 * i) % n;
    values.push_back(centre * (1.0 + spread * (2.0 * slot / (n - 1) - 1.0)));
  }
  return values;
}

TEST(Median, OddCountTakesTheMiddleValueAndEvenCountTheMeanOfTheTwo) {
  EXPECT_EQ(median(std::vector<double>{3.0, 1.0, 2.0}), 2.0);
  EXPECT_EQ(median(std::vector<double>{4.0, 1.0, 3.0, 2.0}), 2.5);
  EXPECT_EQ(median(std::vector<double>{}), 0.0);
}

TEST(Median, RowMeansAndColumnMediansReadARepeatMajorMatrix) {
  // 3 repeats x 2 steps.
  const std::vector<double> matrix = {1.0, 3.0,   // repeat 0
                                      2.0, 9.0,   // repeat 1
                                      6.0, 4.0};  // repeat 2
  EXPECT_EQ(row_means(matrix, 2), (std::vector<double>{2.0, 5.5, 5.0}));
  EXPECT_EQ(column_medians(matrix, 2), (std::vector<double>{2.0, 4.0}));
}

TEST(Median, RowMediansIgnoreAMinorityOfHugeStepsAndAPartialLastRow) {
  // 2 repeats x 5 steps and one stray value: the 40.0 and 90.0 (preempted steps) do not move the
  // medians 3.0 and 5.0, where they raise the means to 10.2 and 22.2.
  const std::vector<double> matrix = {1.0, 40.0, 3.0, 2.0, 5.0,   // repeat 0
                                      5.0, 4.0, 90.0, 6.0, 6.0,   // repeat 1
                                      7.0};
  EXPECT_EQ(row_medians(matrix, 5), (std::vector<double>{3.0, 6.0}));
  EXPECT_EQ(row_means(matrix, 5), (std::vector<double>{10.2, 22.2}));
  EXPECT_TRUE(row_medians(matrix, 0).empty());
}

TEST(Bootstrap, IdenticalSamplesGiveRatioExactlyOneAndNoChange) {
  const std::vector<double> a = noisy(1.0, 0.008, 10);
  const RatioEstimate estimate = bootstrap_median_ratio(a, a);
  EXPECT_EQ(estimate.ratio, 1.0);
  // Every resampled median lies in [0.992, 1.008], so every resampled ratio lies within
  // [0.992 / 1.008, 1.008 / 0.992] = [0.984, 1.016], inside the 2% band whatever the draws.
  EXPECT_GE(estimate.ci.low, 0.992 / 1.008);
  EXPECT_LE(estimate.ci.high, 1.008 / 0.992);
  const RankTest test = mann_whitney_u(a, a);
  EXPECT_EQ(test.p_value, 1.0);
  EXPECT_EQ(decide_speed(estimate, test, 10, {}).speed, Speed::no_change);
}

TEST(Bootstrap, KnownTenPercentSlowdownIsSlowerWithIntervalContainingIt) {
  const std::vector<double> a = noisy(1.0, 0.005, 10);
  const std::vector<double> b = noisy(1.1, 0.005, 11);
  const RatioEstimate estimate = bootstrap_median_ratio(a, b);
  EXPECT_NEAR(estimate.ratio, 1.1, 1e-12);
  // Resampled ratios lie in [1.1 * 0.995 / 1.005, 1.1 * 1.005 / 0.995] = [1.089, 1.111]: the
  // interval clears the band's upper edge 1.02 for any draws.
  EXPECT_LE(estimate.ci.low, 1.1);
  EXPECT_GE(estimate.ci.high, 1.1);
  EXPECT_GE(estimate.ci.low, 1.1 * 0.995 / 1.005);
  EXPECT_LE(estimate.ci.high, 1.1 * 1.005 / 0.995);
  const RankTest test = mann_whitney_u(a, b);
  EXPECT_GT(test.z, 0.0);  // b above a
  EXPECT_LT(test.p_value, 0.001);
  EXPECT_EQ(decide_speed(estimate, test, 10, {}).speed, Speed::slower);
}

TEST(Bootstrap, KnownTenPercentSpeedupIsFaster) {
  const std::vector<double> a = noisy(1.1, 0.005, 10);
  const std::vector<double> b = noisy(1.0, 0.005, 10);
  const RatioEstimate estimate = bootstrap_median_ratio(a, b);
  EXPECT_NEAR(estimate.ratio, 1.0 / 1.1, 1e-12);
  EXPECT_LE(estimate.ci.low, 1.0 / 1.1);
  EXPECT_GE(estimate.ci.high, 1.0 / 1.1);
  EXPECT_EQ(decide_speed(estimate, mann_whitney_u(a, b), 10, {}).speed, Speed::faster);
}

TEST(Bootstrap, SameInputGivesTheSameIntervalBitForBit) {
  const std::vector<double> a = {1.3, 0.9, 1.1, 1.7, 1.0, 1.2};
  const std::vector<double> b = {1.4, 1.0, 1.5, 1.1, 0.95, 1.25, 1.3};
  const RatioEstimate first = bootstrap_median_ratio(a, b);
  const RatioEstimate second = bootstrap_median_ratio(a, b);
  EXPECT_EQ(first.ci.low, second.ci.low);
  EXPECT_EQ(first.ci.high, second.ci.high);
  // A real interval: wide samples must not collapse it to a point.
  EXPECT_LT(first.ci.low, first.ratio);
  EXPECT_GT(first.ci.high, first.ratio);
}

TEST(Bootstrap, IntervalLiesWithinTheExtremeRatiosOfTheSamples) {
  const std::vector<double> a = {2.0, 2.6, 2.2, 3.1, 2.4};
  const std::vector<double> b = {1.9, 2.8, 2.5, 2.0, 3.3};
  const RatioEstimate estimate = bootstrap_median_ratio(a, b);
  EXPECT_GE(estimate.ci.low, *std::ranges::min_element(b) / *std::ranges::max_element(a));
  EXPECT_LE(estimate.ci.high, *std::ranges::max_element(b) / *std::ranges::min_element(a));
  EXPECT_LE(estimate.ci.low, estimate.ci.high);
}

// Rounds of an `ab` run on a drifting machine: round k of both builds runs at the machine's speed
// of the moment, drift(k) spread over +-15% in a scrambled order, and B costs exactly `ratio`
// times A apart from a per-pair jitter of at most +-0.2%.
struct DriftingRounds {
  std::vector<double> a;
  std::vector<double> b;
};

DriftingRounds drifting_rounds(double ratio, int n) {
  const std::vector<double> drift = noisy(1.0, 0.15, n);
  const std::vector<double> jitter = noisy(1.0, 0.002, n);
  DriftingRounds rounds;
  for (int k = 0; k < n; ++k) {
    rounds.a.push_back(drift[k]);
    rounds.b.push_back(drift[k] * ratio * jitter[(k + 3) % n]);
  }
  return rounds;
}

TEST(PairedBootstrap, CommonDriftPerRoundCancelsInPairsButWidensTheUnpairedInterval) {
  const DriftingRounds rounds = drifting_rounds(1.05, 30);
  const RatioEstimate paired = bootstrap_paired_median_ratio(rounds.a, rounds.b);
  // Every pair's ratio lies in 1.05 * [0.998, 1.002], so its median and every resampled median do.
  EXPECT_GE(paired.ratio, 1.05 * 0.998);
  EXPECT_LE(paired.ratio, 1.05 * 1.002);
  EXPECT_GE(paired.ci.low, 1.05 * 0.998);
  EXPECT_LE(paired.ci.high, 1.05 * 1.002);
  EXPECT_LE(paired.ci.low, paired.ratio);
  EXPECT_GE(paired.ci.high, paired.ratio);
  EXPECT_LT(paired.ci.low, paired.ci.high);  // the jitter leaves a real interval
  // Resampled independently, the drift lands in each side's median: the interval is wide enough
  // to hold both edges of the 2% band around the same true ratio, so it cannot decide.
  const RatioEstimate unpaired = bootstrap_median_ratio(rounds.a, rounds.b);
  EXPECT_LT(unpaired.ci.low, 1.05 - 0.02);
  EXPECT_GT(unpaired.ci.high, 1.05 + 0.02);
  EXPECT_GT(unpaired.ci.high - unpaired.ci.low, 10.0 * (paired.ci.high - paired.ci.low));
  const RankTest test{0.0, 4.0, 1e-4};
  EXPECT_EQ(decide_speed(paired, test, 30, {}).speed, Speed::slower);
  EXPECT_EQ(decide_speed(unpaired, test, 30, {}).speed, Speed::inconclusive);
}

TEST(PairedBootstrap, TheSameBuildTwiceIsNoChangeAndExactlyOneWithoutJitter) {
  const std::vector<double> drift = noisy(1.0, 0.15, 30);
  const RatioEstimate same = bootstrap_paired_median_ratio(drift, drift);
  EXPECT_EQ(same.ratio, 1.0);
  EXPECT_EQ(same.ci.low, 1.0);
  EXPECT_EQ(same.ci.high, 1.0);
  const DriftingRounds rounds = drifting_rounds(1.0, 30);
  EXPECT_EQ(decide_speed(bootstrap_paired_median_ratio(rounds.a, rounds.b), {0.0, 0.5, 0.6}, 30, {}).speed,
            Speed::no_change);
}

TEST(PairedBootstrap, RatioIsTheMedianOfPerPairRatiosAndTheIntervalIsDeterministic) {
  // Per-pair ratios 1.5, 0.5, 2.0, 1.0, 1.2: their median is 1.2, while median(b) / median(a) = 1.
  const std::vector<double> a = {2.0, 4.0, 1.0, 3.0, 5.0};
  const std::vector<double> b = {3.0, 2.0, 2.0, 3.0, 6.0};
  const RatioEstimate first = bootstrap_paired_median_ratio(a, b);
  EXPECT_DOUBLE_EQ(first.ratio, 1.2);
  EXPECT_GE(first.ci.low, 0.5);
  EXPECT_LE(first.ci.high, 2.0);
  EXPECT_LT(first.ci.low, first.ratio);
  EXPECT_GT(first.ci.high, first.ratio);
  const RatioEstimate second = bootstrap_paired_median_ratio(a, b);
  EXPECT_EQ(first.ci.low, second.ci.low);
  EXPECT_EQ(first.ci.high, second.ci.high);
}

// Rounds alternate between a free core (A 0.39 ms, B 0.33 ms: B's gain is there) and a busy one
// (both 0.46 ms: it is not). Drift that moves both builds alike splits nothing.
TEST(RatiosByRoundSpeed, TwoMachineStatesGiveTwoRatiosAndACommonDriftOne) {
  std::vector<double> a, b;
  for (int k = 0; k < 20; ++k) {
    const bool free_core = k % 2 == 0;
    a.push_back(free_core ? 0.39 : 0.46);
    b.push_back(free_core ? 0.33 : 0.46);
  }
  const RatiosByRoundSpeed states = ratios_by_round_speed(a, b);
  EXPECT_DOUBLE_EQ(states.fastest_half, 0.33 / 0.39);
  EXPECT_DOUBLE_EQ(states.slowest_half, 1.0);

  const DriftingRounds rounds = drifting_rounds(1.05, 30);
  const RatiosByRoundSpeed drift = ratios_by_round_speed(rounds.a, rounds.b);
  EXPECT_NEAR(drift.fastest_half, 1.05, 0.002);
  EXPECT_NEAR(drift.slowest_half, 1.05, 0.002);
}

TEST(MannWhitney, MatchesAWorkedExampleWithTies) {
  // Pooled and ranked: 1(a)=1, 2(a) 2(a) 2(b)=3 each (mid-rank of 2..4), 3(b)=5, 4(b)=6, 5(a)=7,
  // 6(b)=8, 7(b)=9. Rank sum of a = 1 + 3 + 3 + 7 = 14, U_a = 14 - 4*5/2 = 4, mean 4*5/2 = 10.
  // One tie of 3: variance = 20/12 * (10 - (27 - 3) / (9*8)) = 145/9.
  // z = (|4 - 10| - 1/2) / sqrt(145/9) = 16.5 / sqrt(145), positive because b lies above a.
  const RankTest test = mann_whitney_u(std::vector<double>{1.0, 2.0, 2.0, 5.0}, std::vector<double>{2.0, 3.0, 4.0, 6.0, 7.0});
  EXPECT_EQ(test.statistic, 4.0);
  EXPECT_NEAR(test.z, 16.5 / std::sqrt(145.0), 1e-12);
  EXPECT_NEAR(test.p_value, 0.170609, 1e-6);  // erfc(z / sqrt 2), from a table of the normal
}

TEST(MannWhitney, SamplesWithNoSpreadGivePOne) {
  const RankTest test = mann_whitney_u(std::vector<double>{2.0, 2.0}, std::vector<double>{2.0, 2.0, 2.0});
  EXPECT_EQ(test.p_value, 1.0);
  EXPECT_EQ(test.z, 0.0);
}

TEST(SignTest, CountsPairsLargerInBAndDropsEqualOnes) {
  // 11 pairs, one equal: n = 10, 8 larger in b. Mean 5, variance 10/4; z = (3 - 1/2) / sqrt(2.5).
  const std::vector<double> a = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
  const std::vector<double> b = {2, 3, 1.5, 9, 1.1, 4, 2, 8, 0.5, 0.9, 1};
  const RankTest test = paired_sign_test(a, b);
  EXPECT_EQ(test.statistic, 8.0);
  EXPECT_NEAR(test.z, 2.5 / std::sqrt(2.5), 1e-12);
  EXPECT_NEAR(test.p_value, 0.113846, 1e-6);  // erfc(z / sqrt 2)
  EXPECT_NEAR(paired_sign_test(b, a).z, -test.z, 1e-12);
  EXPECT_EQ(paired_sign_test(a, a).p_value, 1.0);
}

TEST(Wilcoxon, MatchesAWorkedExampleWithAZeroAndATie) {
  // The zero is dropped: n = 6, |d| = 1 2 3 3 4 5 ranked 1 2 3.5 3.5 5 6; W+ = 1 + 3.5 + 3.5 + 5 = 13.
  // Mean 6*7/4 = 10.5; variance 6*7*13/24 - (8 - 2)/48 = 22.625; z = (2.5 - 0.5) / sqrt(22.625).
  const RankTest test = wilcoxon_signed_rank(std::vector<double>{0.0, 1.0, -2.0, 3.0, 3.0, 4.0, -5.0});
  EXPECT_EQ(test.statistic, 13.0);
  EXPECT_NEAR(test.z, 2.0 / std::sqrt(22.625), 1e-12);
  EXPECT_NEAR(test.p_value, 0.674142, 1e-6);
}

TEST(PairedTest, UniformOnePercentShiftAcrossStepsOfVeryDifferentCostIsSignificant) {
  // Step costs vary by a factor of 3 along the trajectory; B is 1% slower on every step, plus a
  // drift of 0.001% a step that keeps the 200 log ratios distinct (no ties) and all positive:
  // W+ = 200*201/2 = 20100, mean 10050, sd sqrt(200*201*401/24) = 819.6, z = 12.26.
  std::vector<double> a;
  std::vector<double> b;
  for (int step = 0; step < 200; ++step) {
    const double cost = 1.0 + 0.3 * (step % 7);
    a.push_back(cost);
    b.push_back(cost * 1.01 * (1.0 + 1e-5 * step));
  }
  const RankTest test = paired_log_ratio_test(a, b);
  EXPECT_EQ(test.statistic, 20100.0);
  EXPECT_NEAR(test.z, 10049.5 / std::sqrt(200.0 * 201.0 * 401.0 / 24.0), 1e-9);
  EXPECT_LT(test.p_value, 1e-30);
}

TEST(PairedTest, IdenticalStepsAndStepsWithoutTimeGivePOne) {
  EXPECT_EQ(paired_log_ratio_test(std::vector<double>{1.0, 2.0, 3.0}, std::vector<double>{1.0, 2.0, 3.0}).p_value, 1.0);
  // A step with a zero median carries no ratio: only the equal steps remain.
  EXPECT_EQ(paired_log_ratio_test(std::vector<double>{0.0, 1.0, 2.0}, std::vector<double>{5.0, 1.0, 2.0}).p_value, 1.0);
}

// --- preemption: what compare does with a run's [repeats x steps] samples ------------------------

// `rounds` x `steps` step times as a loaded machine records them: step s costs
// scale * (0.2 + 0.002 s) ms (a scene whose steps grow dearer), times +-0.5% per round (machine
// state) and +-0.5% per step; and in round r the scheduler preempts (r + phase) % 4 steps, each
// of which then takes 3 ms more, 7 to 14 times its own cost, as a time slice given to another
// process does. `phase` shifts every pattern, so two runs never share their noise.
std::vector<double> preempted_steps(double scale, int phase, int rounds = 30, int steps = 60) {
  std::vector<double> matrix;
  for (int r = 0; r < rounds; ++r) {
    const double round_factor = 1.0 + 0.005 * (((r * 5 + phase) % 7) - 3) / 3.0;
    const int preempted = (r + phase) % 4;
    for (int s = 0; s < steps; ++s) {
      const double step_factor = 1.0 + 0.005 * (((r * 7 + s * 3 + phase) % 11) - 5) / 5.0;
      const bool is_preempted = ((s * 13 + r * 17 + phase) % steps) < preempted;
      matrix.push_back(scale * (0.2 + 0.002 * s) * round_factor * step_factor + (is_preempted ? 3.0 : 0.0));
    }
  }
  return matrix;
}

struct Judged {
  RatioEstimate estimate;
  Speed speed = Speed::inconclusive;
};

// compare's speed row (compare.cpp): the bootstrap over one figure per round, and the paired test
// of the per-step medians across rounds.
Judged judge(const std::vector<double>& a, const std::vector<double>& b, bool by_median, int steps = 60) {
  const auto per_round = [&](const std::vector<double>& matrix) {
    return by_median ? row_medians(matrix, steps) : row_means(matrix, steps);
  };
  const RatioEstimate estimate = bootstrap_median_ratio(per_round(a), per_round(b));
  const RankTest test = paired_log_ratio_test(column_medians(a, steps), column_medians(b, steps));
  return {estimate, decide_speed(estimate, test, static_cast<int>(per_round(a).size()), VerdictRules{}).speed};
}

TEST(Preemption, RoundMeansAreThrownOutOfTheBandButRoundMediansSeeNoChange) {
  const std::vector<double> a = preempted_steps(1.0, 0);
  const std::vector<double> b = preempted_steps(1.0, 1);
  // 0 to 3 steps of 3 ms in a round of 60 add 0 to 0.15 ms to a mean of 0.259 ms: round means
  // spread over +-29%, and the interval of their medians' ratio leaves the 2% band.
  EXPECT_EQ(judge(a, b, false).speed, Speed::inconclusive);
  // At most 3 of 60 steps preempted move a round's median at most 3 places up the sorted steps,
  // 3 * 0.002 = 0.006 ms on a median near 0.26 ms (2.3%), and equally often in A and B; with
  // the +-0.5% factors, the 30 round medians of each run lie within 3.3% and their ratio's
  // interval within the band.
  const Judged same = judge(a, b, true);
  EXPECT_EQ(same.speed, Speed::no_change);
  EXPECT_NEAR(same.estimate.ratio, 1.0, 0.01);
}

TEST(Preemption, RoundMediansFindAFivePercentSlowdownThroughThePreemptions) {
  const Judged slower = judge(preempted_steps(1.0, 0), preempted_steps(1.05, 1), true);
  EXPECT_EQ(slower.speed, Speed::slower);
  EXPECT_NEAR(slower.estimate.ratio, 1.05, 0.01);
  EXPECT_GT(slower.estimate.ci.low, 1.02);
  EXPECT_LT(slower.estimate.ci.high, 1.08);
}

// --- the verdict at its boundaries ---------------------------------------------------------------

constexpr double significant = 0.001;
constexpr double not_significant = 0.5;
const VerdictRules rules{};
const double low_edge = 1.0 - rules.noise;
const double high_edge = 1.0 + rules.noise;

double above(double x) { return std::nextafter(x, 10.0); }
double below(double x) { return std::nextafter(x, 0.0); }

Speed verdict(double ratio, double low, double high, double p, int repeats = 10) {
  return decide_speed({ratio, {low, high}}, {0.0, 3.0, p}, repeats, rules).speed;
}

TEST(Verdict, IntervalOnTheBandEdgesIsNoChange) {
  EXPECT_EQ(verdict(1.0, low_edge, high_edge, not_significant), Speed::no_change);
  EXPECT_EQ(verdict(1.0, low_edge, high_edge, significant), Speed::no_change);  // significant, but within noise
}

TEST(Verdict, IntervalJustPastAnEdgeIsInconclusive) {
  EXPECT_EQ(verdict(1.0, below(low_edge), high_edge, not_significant), Speed::inconclusive);
  EXPECT_EQ(verdict(1.0, low_edge, above(high_edge), significant), Speed::inconclusive);
}

TEST(Verdict, IntervalJustOutsideTheBandWithSignificanceIsSlowerOrFaster) {
  EXPECT_EQ(verdict(1.1, above(high_edge), 1.2, significant), Speed::slower);
  EXPECT_EQ(verdict(0.9, 0.8, below(low_edge), significant), Speed::faster);
}

TEST(Verdict, IntervalTouchingTheBandEdgeFromOutsideIsInconclusive) {
  EXPECT_EQ(verdict(1.1, high_edge, 1.2, significant), Speed::inconclusive);
  EXPECT_EQ(verdict(0.9, 0.8, low_edge, significant), Speed::inconclusive);
}

TEST(Verdict, PJustBelowAlphaDecidesAndPAtAlphaDoesNot) {
  EXPECT_EQ(verdict(1.1, 1.05, 1.15, below(rules.alpha)), Speed::slower);
  EXPECT_EQ(verdict(1.1, 1.05, 1.15, rules.alpha), Speed::inconclusive);
}

TEST(Verdict, FewerThanMinimumRepeatsIsInconclusiveWhateverTheNumbers) {
  EXPECT_EQ(verdict(1.0, 1.0, 1.0, not_significant, rules.min_repeats - 1), Speed::inconclusive);
  EXPECT_EQ(verdict(1.5, 1.4, 1.6, significant, rules.min_repeats - 1), Speed::inconclusive);
  EXPECT_EQ(verdict(1.5, 1.4, 1.6, significant, rules.min_repeats), Speed::slower);
}

TEST(Verdict, TinySamplesAreInconclusiveAndSayHowManyRepeatsWouldDecide) {
  // Two repeats, clearly apart: U_a = 0, mean 2, variance 2*2*5/12, z = 1.5 / 1.291 = 1.162,
  // p = 0.245. |z| must reach 1.960: (1.960 / 1.162)^2 * 2 = 5.69, so 6 repeats.
  const std::vector<double> a = {1.0, 1.01};
  const std::vector<double> b = {1.2, 1.21};
  const RankTest test = mann_whitney_u(a, b);
  const SpeedVerdict result = decide_speed(bootstrap_median_ratio(a, b), test, 2, rules);
  EXPECT_EQ(result.speed, Speed::inconclusive);
  EXPECT_EQ(result.repeats_needed, 6);
}

TEST(Verdict, ThreeRepeatsCannotBeSignificantUnpairedAndFourCan) {
  // All of b above all of a: n = 3 gives z = 4 / sqrt(5.25) = 1.746, p = 0.081, and
  // (1.960 / 1.746)^2 * 3 = 3.78, so 4 repeats; n = 4 gives z = 7.5 / sqrt(12) = 2.165, p = 0.030.
  const std::vector<double> a3 = {1.0, 1.01, 1.02};
  const std::vector<double> b3 = {1.2, 1.21, 1.22};
  const SpeedVerdict three = decide_speed(bootstrap_median_ratio(a3, b3), mann_whitney_u(a3, b3), 3, rules);
  EXPECT_EQ(three.speed, Speed::inconclusive);
  EXPECT_EQ(three.repeats_needed, 4);
  const std::vector<double> a4 = {1.0, 1.01, 1.02, 1.03};
  const std::vector<double> b4 = {1.2, 1.21, 1.22, 1.23};
  EXPECT_EQ(decide_speed(bootstrap_median_ratio(a4, b4), mann_whitney_u(a4, b4), 4, rules).speed, Speed::slower);
}

TEST(Verdict, RepeatsNeededScaleTheIntervalHalfWidthAsTheSquareRootOfTheCount) {
  // Ratio 1.05 with its lower half-width 0.04 must clear 1.02, leaving room 0.03:
  // 10 * (0.04 / 0.03)^2 = 17.8, so 18 repeats.
  EXPECT_EQ(decide_speed({1.05, {1.01, 1.09}}, {0.0, 5.0, significant}, 10, rules).repeats_needed, 18);
  // Ratio 1.0 with half-width 0.03 must fit within the band's 0.02: 10 * (0.03 / 0.02)^2 = 22.5.
  EXPECT_EQ(decide_speed({1.0, {0.97, 1.03}}, {0.0, 0.1, not_significant}, 10, rules).repeats_needed, 23);
  // Mirrored: ratio 0.95 with upper half-width 0.04 must clear 0.98.
  EXPECT_EQ(decide_speed({0.95, {0.91, 0.99}}, {0.0, -5.0, significant}, 10, rules).repeats_needed, 18);
}

TEST(Verdict, RatioOnABandEdgeCannotBeDecidedByMoreRepeats) {
  const SpeedVerdict result = decide_speed({high_edge, {1.0, 1.04}}, {0.0, 5.0, significant}, 10, rules);
  EXPECT_EQ(result.speed, Speed::inconclusive);
  EXPECT_FALSE(result.repeats_needed.has_value());
}

TEST(Verdict, NamesReadAsPrinted) {
  EXPECT_EQ(to_string(Speed::faster), "faster");
  EXPECT_EQ(to_string(Speed::slower), "slower");
  EXPECT_EQ(to_string(Speed::no_change), "no change");
  EXPECT_EQ(to_string(Speed::inconclusive), "inconclusive");
}

}  // namespace
}  // namespace fxbench
