// The statistics behind `fx2d-bench compare`: medians, a bootstrap interval for a ratio of
// medians, two rank tests and a sign test, and the two-stage verdict in the manner of criterion.rs (a change
// counts only when it is significant AND its whole interval lies outside a noise band).
//
// Invariants: pure functions of their arguments, no I/O and no global state; every result is a
// deterministic function of the input values, the bootstrap included (it draws from a
// std::mt19937_64 seeded with bootstrap_seed, whose output sequence the C++ standard fixes, and
// maps draws to indices by plain modular arithmetic, never through a library distribution whose
// algorithm is implementation-defined), so the same two result files always get the same verdict.
//
// The interval is a percentile bootstrap of median(B) / median(A), not a Hodges-Lehmann
// estimate: its point estimate is then exactly the ratio of the two medians a reader sees printed
// beside it. Paired repeats (the rounds of one `fx2d-bench ab`) are instead resampled as pairs,
// with the median of the per-pair ratios as the statistic (bootstrap_paired_median_ratio).
//
// What is resampled is one figure per repeat (a round of `fx2d-bench ab`): the MEDIAN of that
// repeat's per-step times (row_medians), not their mean. On a shared machine a step that the
// scheduler preempts takes several times its own cost, and a few such steps move a repeat's mean
// by more than the 2% noise band (wall 0.55 ms/step against 0.32 ms of CPU under a load of 8 on 2 cores,
// with repeat means 26% apart), while the median of a repeat's steps moves only when more than
// half of them are disturbed. The price: a change confined to a minority of steps (the costliest
// few of a trajectory, say) moves the median less than the mean, and a time spent in fewer than
// half of the steps (a phase that runs now and then) has a median of 0.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace fxbench {

// The median; an even count takes the mean of the two middle values; empty gives 0.
double median(std::span<const double> sample);

// The spread of a sample, as the run summary reports it: an empty sample has every figure 0;
// otherwise min <= median <= max, with median() above, so `run` and `compare` report the same
// median of the same numbers.
struct Spread {
  double median = 0.0;
  double min = 0.0;
  double max = 0.0;
};

Spread spread_of(std::span<const double> sample);
double mean_of(std::span<const double> sample);  // empty gives 0

// A repeat-major matrix (index = row * columns + column, as RunRecord stores samples): the mean
// or the median of each row (one per repeat), and the median of each column (one per step,
// across repeats). A partial last row is ignored.
std::vector<double> row_means(std::span<const double> matrix, std::size_t columns);
std::vector<double> row_medians(std::span<const double> matrix, std::size_t columns);
std::vector<double> column_medians(std::span<const double> matrix, std::size_t columns);

inline constexpr std::uint64_t bootstrap_seed = 0x6678326462656e63;  // "fx2dbenc" in ASCII
inline constexpr int bootstrap_resamples = 2000;
inline constexpr double confidence_level = 0.95;

struct Interval {
  double low = 0.0;
  double high = 0.0;
};

struct RatioEstimate {
  double ratio = 1.0;  // median(b) / median(a)
  Interval ci;         // confidence_level percentile bootstrap interval of that ratio
};

// For two independent samples (two `run`s): resamples a and b independently, with replacement,
// bootstrap_resamples times; the statistic is median(b) / median(a). Both samples must be
// non-empty and positive (times, cycle counts).
RatioEstimate bootstrap_median_ratio(std::span<const double> a, std::span<const double> b);

// For paired samples, where a[k] and b[k] ran back to back (round k of A and of B in
// `fx2d-bench ab`): resamples the indices k, with replacement, bootstrap_resamples times; the
// statistic is the median over the resample of b[k] / a[k], and `ratio` is that median over all k.
//   Why: the drift of a shared machine moves A's and B's round k alike, so each pair's ratio
//   cancels it, where the independent resampling above counts it twice, once in each median. On
//   `ab` files of settling_boxes this narrowed the interval by about 40%. The ratio is then not
//   exactly median(b) / median(a), only close to it.
// a and b must have the same, non-zero size and be positive.
RatioEstimate bootstrap_paired_median_ratio(std::span<const double> a, std::span<const double> b);

// For paired rounds: the median of b_k / a_k over the half of the pairs whose mean time
// (a_k + b_k) / 2 is smallest, and over the half whose mean is largest (an odd middle pair in
// neither). Sorting by the pair's mean, not by a_k alone, keeps the halves free of the bias that
// a noisy denominator would give them: noise in a_k moves the mean and the ratio independently.
//   Why: a machine that switches between states (a neighbouring hardware thread busy or idle)
// can change the two builds unequally; then the halves disagree and no single ratio describes
// the change. a and b must have the same size, at least 2, and be positive.
struct RatiosByRoundSpeed {
  double fastest_half = 1.0;
  double slowest_half = 1.0;
};
RatiosByRoundSpeed ratios_by_round_speed(std::span<const double> a, std::span<const double> b);

struct RankTest {
  double statistic = 0.0;  // Mann-Whitney: U of a; Wilcoxon: W+, the rank sum of positive differences
  double z = 0.0;          // normal approximation, continuity-corrected; sign: b above a is positive
  double p_value = 1.0;    // two-sided
};

// Mann-Whitney U test of a against b: normal approximation with the tie correction to the
// variance and a continuity correction of 1/2. Samples with no spread at all give p = 1.
RankTest mann_whitney_u(std::span<const double> a, std::span<const double> b);

// Wilcoxon signed-rank test that `differences` are centred on 0: zero differences are dropped
// (Wilcoxon's own rule), ties among the rest take mid-ranks with the variance corrected for
// them, continuity correction 1/2. No non-zero difference gives p = 1.
RankTest wilcoxon_signed_rank(std::span<const double> differences);

// Sign test that paired figures are as often larger in b as in a: the number of pairs with
// b_i > a_i (equal pairs dropped) against half of the rest, normal approximation with continuity
// correction; z > 0 when b is larger more often. The test of a median: each pair counts once,
// however far a disturbance moved it.
RankTest paired_sign_test(std::span<const double> a, std::span<const double> b);

// The fewest pairs for which paired_sign_test can reach p < alpha at all: with fewer, even B
// larger in every pair is not significant, so an `ab` of that many rounds can never say `slower`
// or `faster` (6 at alpha 0.05). Computed from the test itself on the most extreme outcome.
int sign_test_min_pairs(double alpha);

// The paired test for two runs that stepped the same deterministic trajectory, so that step i of
// A and step i of B did the same work: Wilcoxon signed-rank on log(b_i / a_i), where a_i and b_i
// are the medians of step i across each run's repeats. Steps where either median is not positive
// carry no ratio and are left out.
//   Why this test: pairing removes the largest source of variance, the step-to-step change in
//   work as the scene evolves; the log makes the differences of cheap and costly steps alike,
//   since timing noise is proportional to the time taken; the per-step median across repeats
//   discards a step preempted in one repeat; and ranks keep one step that was slow in most
//   repeats from swaying the result as it would a mean. Neighbouring steps are not independent
//   (interference lasts longer than a step), so this p-value is optimistic; the verdict therefore
//   also demands that the bootstrap interval, taken over whole repeats, clears the noise band.
RankTest paired_log_ratio_test(std::span<const double> a_step_medians, std::span<const double> b_step_medians);

enum class Speed { faster, slower, no_change, inconclusive };

// "faster", "slower", "no change", "inconclusive".
std::string to_string(Speed speed);

struct VerdictRules {
  double noise = 0.02;   // the band [1 - noise, 1 + noise] of ratios that count as no change
  double alpha = 0.05;   // significance level of the test
  // Fewer repeats than this on either side is inconclusive whatever the numbers say: the
  // bootstrap median of one or two values takes at most two values, so its interval says
  // nothing about the spread.
  int min_repeats = 3;
};

struct SpeedVerdict {
  Speed speed = Speed::inconclusive;
  // For an inconclusive verdict, repeats per run that would likely decide it: the interval's
  // half-width shrinks as sqrt(n_now / n_needed) and |z| grows as sqrt(n_needed / n_now).
  // Empty when more repeats cannot decide (the estimate sits on a band edge, or there is no
  // difference to test) or would take more than max_repeats_needed.
  std::optional<int> repeats_needed;
};

inline constexpr int max_repeats_needed = 1'000'000;

// The two-stage verdict: `no change` when the interval lies inside the band (edges included);
// `faster` or `slower` when p < alpha and the whole interval lies strictly outside the band;
// otherwise `inconclusive`. `repeats` is the smaller repeat count of the two runs.
SpeedVerdict decide_speed(const RatioEstimate& estimate, const RankTest& test, int repeats, const VerdictRules& rules);

// The verdict on an exact figure, such as an instruction count, which has no sampling error to
// test: `no change` when |b / a - 1| <= tolerance (edges included), else `slower` when b is above
// a and `faster` when below. Evaluated as |b - a| <= tolerance * a, so that a case on the edge is
// not decided by the rounding of a quotient. a must be positive.
Speed decide_exact(double a, double b, double tolerance);

}  // namespace fxbench
