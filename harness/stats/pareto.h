// The speed-versus-accuracy Pareto front of a sweep: which settings of an engine are worth using.
//
// Invariant: a point is on its group's front exactly when no other point of the same group
// dominates it, where `a` dominates `b` when a is at least as fast and at least as accurate
// (lower cost and lower error are better) and strictly better in one. Equal points do not
// dominate each other, so both stay on the front. A NaN error counts as +infinity: a setting
// whose run blew up is never more accurate than one that did not. Pure functions, no I/O.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <vector>

namespace fxbench {

struct ParetoPoint {
  int group = 0;       // points are compared only within a group (one engine on one scene)
  double cost = 0.0;   // e.g. ms per simulated second; lower is better
  double error = 0.0;  // e.g. max penetration in metres; lower is better
};

// One flag per point, in input order: true when the point is on its group's front.
std::vector<bool> pareto_front(std::span<const ParetoPoint> points);

// For a point off its front, the point of its group that dominates it at the lowest cost (ties:
// lower error, then lower index): the fastest setting that is at least as good in every way.
// Nothing for a point on its front.
std::optional<std::size_t> fastest_dominating(std::span<const ParetoPoint> points, std::size_t index);

// The indices of `group`'s front, fastest first (ties: lower error, then lower index): read in
// this order, the errors never increase, which is the staircase a chart draws.
std::vector<std::size_t> front_by_cost(std::span<const ParetoPoint> points, int group);

// Every point's place in its group's front, as a sweep file's /sweep table stores it (and merge
// recomputes over the merged points): on it or not, its rank along it (fastest first; -1 off
// it), and the point that dominates it at the lowest cost. `fronts` holds each non-empty group's
// front, groups in increasing order.
struct FrontMarks {
  std::vector<bool> on_front;
  std::vector<int> front_rank;
  std::vector<std::optional<std::size_t>> dominated_by;
  std::vector<std::vector<std::size_t>> fronts;
};
FrontMarks mark_fronts(std::span<const ParetoPoint> points);

}  // namespace fxbench
