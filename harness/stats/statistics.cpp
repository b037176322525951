// Medians, the bootstrap, the rank tests and the verdict; the contracts are in statistics.h.
// Samples are a few hundred values, compared once per command, so clarity wins over speed here;
// the bootstrap alone reuses its scratch buffers, since it runs thousands of resamples.
#include "stats/statistics.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <numeric>
#include <random>
#include <stdexcept>
#include <string>

namespace fxbench {
namespace {

constexpr double infinity = std::numeric_limits<double>::infinity();

double square(double x) { return x * x; }

// Reorders `values`; the caller owns the copy.
double median_in_place(std::span<double> values) {
  if (values.empty()) return 0.0;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  if (values.size() % 2 == 1) return *middle;
  return 0.5 * (*middle + *std::max_element(values.begin(), middle));
}

double two_sided_p(double z) { return std::erfc(std::abs(z) / std::numbers::sqrt2); }

// The |z| whose two-sided p is `alpha`, by bisection: two_sided_p falls monotonically in |z|.
double critical_z(double alpha) {
  double below = 0.0;
  double above = 40.0;
  for (int iteration = 0; iteration < 200; ++iteration) {
    const double mid = 0.5 * (below + above);
    (two_sided_p(mid) > alpha ? below : above) = mid;
  }
  return above;
}

// (statistic - mean) / sd, moved 1/2 towards zero because the statistic moves in whole steps
// (or half steps under ties) while the normal it is compared with is continuous.
RankTest normal_approximation(double statistic, double mean, double variance, double sign) {
  if (variance <= 0.0) return {statistic, 0.0, 1.0};
  const double deviation = statistic - mean;
  const double corrected = std::max(0.0, std::abs(deviation) - 0.5);
  const double z = sign * std::copysign(corrected, deviation) / std::sqrt(variance);
  return {statistic, z, two_sided_p(z)};
}

struct Ranking {
  std::vector<double> ranks;  // 1-based mid-ranks, in the order of the input values
  double tie_term = 0.0;      // sum over groups of t tied values of t^3 - t
};

Ranking rank(std::span<const double> values) {
  std::vector<std::size_t> order(values.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::ranges::stable_sort(order, {}, [&](std::size_t i) { return values[i]; });
  Ranking ranking{std::vector<double>(values.size()), 0.0};
  for (std::size_t first = 0; first < order.size();) {
    std::size_t last = first;
    while (last + 1 < order.size() && values[order[last + 1]] == values[order[first]]) ++last;
    const double mid_rank = 0.5 * static_cast<double>(first + last) + 1.0;
    for (std::size_t k = first; k <= last; ++k) ranking.ranks[order[k]] = mid_rank;
    const auto tied = static_cast<double>(last - first + 1);
    ranking.tie_term += tied * tied * tied - tied;
    first = last + 1;
  }
  return ranking;
}

// How many times the present repeats would decide: the side of the interval that must clear a
// band edge shrinks as 1/sqrt(n), so its width must fall to the room left to that edge; and
// |z| grows as sqrt(n), so it must reach the critical value.
double repeat_growth_factor(const RatioEstimate& estimate, const RankTest& test, const VerdictRules& rules) {
  const double low_edge = 1.0 - rules.noise;
  const double high_edge = 1.0 + rules.noise;
  const double ratio = estimate.ratio;
  const auto shrink = [](double width, double room) { return room > 0.0 ? square(std::max(width, 0.0) / room) : infinity; };
  const double significance =
      test.p_value < rules.alpha ? 0.0 : (test.z == 0.0 ? infinity : square(critical_z(rules.alpha) / test.z));
  if (ratio > high_edge) return std::max(shrink(ratio - estimate.ci.low, ratio - high_edge), significance);
  if (ratio < low_edge) return std::max(shrink(estimate.ci.high - ratio, low_edge - ratio), significance);
  return std::max(shrink(ratio - estimate.ci.low, ratio - low_edge), shrink(estimate.ci.high - ratio, high_edge - ratio));
}

std::optional<int> repeats_to_decide(const RatioEstimate& estimate, const RankTest& test, int repeats,
                                     const VerdictRules& rules) {
  const double needed = std::ceil(static_cast<double>(repeats) * repeat_growth_factor(estimate, test, rules));
  if (!(needed <= max_repeats_needed)) return std::nullopt;
  return std::max({static_cast<int>(needed), repeats + 1, rules.min_repeats});
}

// The machinery both bootstraps share: `resampled_statistic` draws one resample from the engine
// and returns its statistic; this calls it bootstrap_resamples times from the fixed seed and
// returns the central confidence_level of the statistics. engine() % n, which the statistics use
// to pick an index, is biased by at most n / 2^64, far below anything a few thousand resamples see.
Interval percentile_bootstrap(const std::function<double(std::mt19937_64&)>& resampled_statistic) {
  std::mt19937_64 engine(bootstrap_seed);
  std::vector<double> statistics(bootstrap_resamples);
  for (double& statistic : statistics) statistic = resampled_statistic(engine);
  std::ranges::sort(statistics);
  const auto tail = static_cast<std::size_t>(std::lround(bootstrap_resamples * (1.0 - confidence_level) / 2.0));
  return {statistics[tail], statistics[statistics.size() - 1 - tail]};
}

}  // namespace

double median(std::span<const double> sample) {
  std::vector<double> copy(sample.begin(), sample.end());
  return median_in_place(copy);
}

Spread spread_of(std::span<const double> sample) {
  if (sample.empty()) return {};
  const auto [min, max] = std::minmax_element(sample.begin(), sample.end());
  return {median(sample), *min, *max};
}

double mean_of(std::span<const double> sample) {
  if (sample.empty()) return 0.0;
  return std::accumulate(sample.begin(), sample.end(), 0.0) / static_cast<double>(sample.size());
}

std::vector<double> row_means(std::span<const double> matrix, std::size_t columns) {
  std::vector<double> means;
  if (columns == 0) return means;
  for (std::size_t start = 0; start + columns <= matrix.size(); start += columns) {
    const auto row = matrix.subspan(start, columns);
    means.push_back(std::accumulate(row.begin(), row.end(), 0.0) / static_cast<double>(columns));
  }
  return means;
}

std::vector<double> row_medians(std::span<const double> matrix, std::size_t columns) {
  std::vector<double> medians;
  if (columns == 0) return medians;
  for (std::size_t start = 0; start + columns <= matrix.size(); start += columns)
    medians.push_back(median(matrix.subspan(start, columns)));
  return medians;
}

std::vector<double> column_medians(std::span<const double> matrix, std::size_t columns) {
  std::vector<double> medians;
  if (columns == 0) return medians;
  const std::size_t rows = matrix.size() / columns;
  std::vector<double> column(rows);
  for (std::size_t c = 0; c < columns; ++c) {
    for (std::size_t r = 0; r < rows; ++r) column[r] = matrix[r * columns + c];
    medians.push_back(median_in_place(column));
  }
  return medians;
}

RatioEstimate bootstrap_median_ratio(std::span<const double> a, std::span<const double> b) {
  std::vector<double> scratch(std::max(a.size(), b.size()));
  const auto resampled_median = [&](std::mt19937_64& engine, std::span<const double> sample) {
    const std::span<double> resample(scratch.data(), sample.size());
    for (double& value : resample) value = sample[engine() % sample.size()];
    return median_in_place(resample);
  };
  const Interval interval = percentile_bootstrap([&](std::mt19937_64& engine) {
    // Two statements, so that A is always drawn before B: the order of evaluation of a / b's
    // operands is unspecified, and the draws must not depend on the compiler.
    const double a_median = resampled_median(engine, a);
    return resampled_median(engine, b) / a_median;
  });
  return {median(b) / median(a), interval};
}

RatioEstimate bootstrap_paired_median_ratio(std::span<const double> a, std::span<const double> b) {
  std::vector<double> pair_ratios(a.size());
  for (std::size_t k = 0; k < a.size(); ++k) pair_ratios[k] = b[k] / a[k];
  std::vector<double> scratch(pair_ratios.size());
  const Interval interval = percentile_bootstrap([&](std::mt19937_64& engine) {
    for (double& value : scratch) value = pair_ratios[engine() % pair_ratios.size()];
    return median_in_place(scratch);
  });
  return {median(pair_ratios), interval};
}

RatiosByRoundSpeed ratios_by_round_speed(std::span<const double> a, std::span<const double> b) {
  std::vector<std::size_t> order(a.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::ranges::stable_sort(order, {}, [&](std::size_t k) { return a[k] + b[k]; });
  const std::size_t half = order.size() / 2;
  auto median_ratio = [&](std::span<const std::size_t> pairs) {
    std::vector<double> ratios;
    for (const std::size_t k : pairs) ratios.push_back(b[k] / a[k]);
    return median(ratios);
  };
  const std::span<const std::size_t> sorted(order);
  return {median_ratio(sorted.first(half)), median_ratio(sorted.last(half))};
}

RankTest mann_whitney_u(std::span<const double> a, std::span<const double> b) {
  if (a.empty() || b.empty()) return {};
  std::vector<double> pooled(a.begin(), a.end());
  pooled.insert(pooled.end(), b.begin(), b.end());
  const Ranking ranking = rank(pooled);
  const auto n_a = static_cast<double>(a.size());
  const auto n_b = static_cast<double>(b.size());
  const double n = n_a + n_b;
  const double rank_sum_a = std::accumulate(ranking.ranks.begin(), ranking.ranks.begin() + static_cast<std::ptrdiff_t>(a.size()), 0.0);
  const double u_a = rank_sum_a - n_a * (n_a + 1.0) / 2.0;
  const double variance = n_a * n_b / 12.0 * ((n + 1.0) - ranking.tie_term / (n * (n - 1.0)));
  // U of a is small when b lies above a: negate so that z > 0 means b is larger.
  return normal_approximation(u_a, n_a * n_b / 2.0, variance, -1.0);
}

RankTest wilcoxon_signed_rank(std::span<const double> differences) {
  std::vector<double> magnitudes;
  std::vector<bool> positive;
  for (const double difference : differences) {
    if (difference == 0.0) continue;
    magnitudes.push_back(std::abs(difference));
    positive.push_back(difference > 0.0);
  }
  if (magnitudes.empty()) return {};
  const Ranking ranking = rank(magnitudes);
  double w_plus = 0.0;
  for (std::size_t i = 0; i < magnitudes.size(); ++i)
    if (positive[i]) w_plus += ranking.ranks[i];
  const auto n = static_cast<double>(magnitudes.size());
  const double variance = n * (n + 1.0) * (2.0 * n + 1.0) / 24.0 - ranking.tie_term / 48.0;
  return normal_approximation(w_plus, n * (n + 1.0) / 4.0, variance, 1.0);
}

RankTest paired_sign_test(std::span<const double> a, std::span<const double> b) {
  double larger_in_b = 0.0;
  double unequal = 0.0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    if (a[i] == b[i]) continue;
    unequal += 1.0;
    larger_in_b += b[i] > a[i] ? 1.0 : 0.0;
  }
  return normal_approximation(larger_in_b, unequal / 2.0, unequal / 4.0, 1.0);
}

int sign_test_min_pairs(double alpha) {
  std::vector<double> a;
  std::vector<double> b;
  // The p-value of n pairs all one way halves about every two pairs, so any alpha the policy
  // accepts (>= 1e-9) is reached long before this bound.
  for (int pairs = 1; pairs < 1000; ++pairs) {
    a.push_back(0.0);
    b.push_back(1.0);
    if (paired_sign_test(a, b).p_value < alpha) return pairs;
  }
  throw std::invalid_argument("sign_test_min_pairs: alpha " + std::to_string(alpha) + " is beyond reach");
}

RankTest paired_log_ratio_test(std::span<const double> a_step_medians, std::span<const double> b_step_medians) {
  std::vector<double> log_ratios;
  const std::size_t steps = std::min(a_step_medians.size(), b_step_medians.size());
  for (std::size_t step = 0; step < steps; ++step)
    if (a_step_medians[step] > 0.0 && b_step_medians[step] > 0.0)
      log_ratios.push_back(std::log(b_step_medians[step]) - std::log(a_step_medians[step]));
  return wilcoxon_signed_rank(log_ratios);
}

std::string to_string(Speed speed) {
  switch (speed) {
    case Speed::faster: return "faster";
    case Speed::slower: return "slower";
    case Speed::no_change: return "no change";
    case Speed::inconclusive: return "inconclusive";
  }
  return "inconclusive";
}

SpeedVerdict decide_speed(const RatioEstimate& estimate, const RankTest& test, int repeats, const VerdictRules& rules) {
  const double low_edge = 1.0 - rules.noise;
  const double high_edge = 1.0 + rules.noise;
  if (repeats >= rules.min_repeats) {
    if (estimate.ci.low >= low_edge && estimate.ci.high <= high_edge) return {Speed::no_change, std::nullopt};
    const bool significant = test.p_value < rules.alpha;
    if (significant && estimate.ci.low > high_edge) return {Speed::slower, std::nullopt};
    if (significant && estimate.ci.high < low_edge) return {Speed::faster, std::nullopt};
  }
  return {Speed::inconclusive, repeats_to_decide(estimate, test, repeats, rules)};
}

Speed decide_exact(double a, double b, double tolerance) {
  if (std::abs(b - a) <= tolerance * a) return Speed::no_change;
  return b > a ? Speed::slower : Speed::faster;
}

}  // namespace fxbench
