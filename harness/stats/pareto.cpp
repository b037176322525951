// The Pareto front; the dominance rule is stated in pareto.h.
#include "stats/pareto.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

namespace fxbench {
namespace {

double comparable_error(const ParetoPoint& point) {
  return std::isnan(point.error) ? std::numeric_limits<double>::infinity() : point.error;
}

bool dominates(const ParetoPoint& a, const ParetoPoint& b) {
  const double error_a = comparable_error(a);
  const double error_b = comparable_error(b);
  return a.group == b.group && a.cost <= b.cost && error_a <= error_b && (a.cost < b.cost || error_a < error_b);
}

// Orders by cost, then error, then index: the tie-break both fastest_dominating and
// front_by_cost promise.
bool faster(std::span<const ParetoPoint> points, std::size_t a, std::size_t b) {
  return std::tuple(points[a].cost, comparable_error(points[a]), a) <
         std::tuple(points[b].cost, comparable_error(points[b]), b);
}

}  // namespace

std::optional<std::size_t> fastest_dominating(std::span<const ParetoPoint> points, std::size_t index) {
  std::optional<std::size_t> best;
  for (std::size_t other = 0; other < points.size(); ++other) {
    if (!dominates(points[other], points[index])) continue;
    if (!best || faster(points, other, *best)) best = other;
  }
  return best;
}

std::vector<bool> pareto_front(std::span<const ParetoPoint> points) {
  std::vector<bool> on_front(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) on_front[i] = !fastest_dominating(points, i).has_value();
  return on_front;
}

std::vector<std::size_t> front_by_cost(std::span<const ParetoPoint> points, int group) {
  const std::vector<bool> on_front = pareto_front(points);
  std::vector<std::size_t> front;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (on_front[i] && points[i].group == group) front.push_back(i);
  std::ranges::sort(front, [&](std::size_t a, std::size_t b) { return faster(points, a, b); });
  return front;
}

FrontMarks mark_fronts(std::span<const ParetoPoint> points) {
  FrontMarks marks;
  marks.on_front = pareto_front(points);
  marks.front_rank.assign(points.size(), -1);
  for (std::size_t i = 0; i < points.size(); ++i) marks.dominated_by.push_back(fastest_dominating(points, i));
  std::vector<int> groups;
  for (const ParetoPoint& point : points) groups.push_back(point.group);
  std::ranges::sort(groups);
  groups.erase(std::unique(groups.begin(), groups.end()), groups.end());
  for (int group : groups) {
    marks.fronts.push_back(front_by_cost(points, group));
    const std::vector<std::size_t>& front = marks.fronts.back();
    for (std::size_t rank = 0; rank < front.size(); ++rank) marks.front_rank[front[rank]] = static_cast<int>(rank);
  }
  return marks;
}

}  // namespace fxbench
