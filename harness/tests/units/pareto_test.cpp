// Tests of the speed-versus-accuracy Pareto front (pareto.h) on hand-made points whose front can
// be read off by eye: dominance, ties, groups, NaN errors, the staircase order, and where a
// default setting stands.
#include "stats/pareto.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace fxbench {
namespace {

TEST(Pareto, SinglePointIsOnItsFront) {
  const std::vector<ParetoPoint> points{{0, 3.0, 0.01}};
  EXPECT_EQ(pareto_front(points), std::vector<bool>{true});
  EXPECT_FALSE(fastest_dominating(points, 0).has_value());
}

TEST(Pareto, SlowerAndLessAccuratePointIsOffTheFront) {
  const std::vector<ParetoPoint> points{{0, 1.0, 1.0}, {0, 2.0, 2.0}, {0, 3.0, 0.5}};
  EXPECT_EQ(pareto_front(points), (std::vector<bool>{true, false, true}));
  EXPECT_EQ(fastest_dominating(points, 1), 0u);
}

TEST(Pareto, EqualPointsDoNotDominateEachOther) {
  const std::vector<ParetoPoint> points{{0, 2.0, 0.1}, {0, 2.0, 0.1}};
  EXPECT_EQ(pareto_front(points), (std::vector<bool>{true, true}));
}

TEST(Pareto, EqualCostKeepsOnlyTheMoreAccurate) {
  const std::vector<ParetoPoint> points{{0, 2.0, 0.5}, {0, 2.0, 0.2}};
  EXPECT_EQ(pareto_front(points), (std::vector<bool>{false, true}));
}

TEST(Pareto, EqualErrorKeepsOnlyTheFaster) {
  const std::vector<ParetoPoint> points{{0, 5.0, 0.3}, {0, 4.0, 0.3}};
  EXPECT_EQ(pareto_front(points), (std::vector<bool>{false, true}));
}

TEST(Pareto, GroupsAreJudgedSeparately) {
  // The second point would be dominated by the first were they the same engine.
  const std::vector<ParetoPoint> points{{0, 1.0, 0.1}, {1, 2.0, 0.2}};
  EXPECT_EQ(pareto_front(points), (std::vector<bool>{true, true}));
}

TEST(Pareto, NanErrorLosesToAnyFiniteErrorAtTheSameCost) {
  const std::vector<ParetoPoint> points{{0, 1.0, std::nan("")}, {0, 1.0, 5.0}};
  EXPECT_EQ(pareto_front(points), (std::vector<bool>{false, true}));
}

TEST(Pareto, FrontByCostIsAStaircaseOfFallingErrors) {
  const std::vector<ParetoPoint> points{
      {0, 8.0, 0.02}, {0, 1.0, 0.9}, {0, 3.0, 0.5}, {0, 4.0, 0.6}, {0, 2.0, 0.5}, {1, 0.5, 0.0}, {0, 16.0, 0.02}};
  const std::vector<std::size_t> front = front_by_cost(points, 0);
  EXPECT_EQ(front, (std::vector<std::size_t>{1, 4, 0}));
  for (std::size_t i = 1; i < front.size(); ++i) {
    EXPECT_GT(points[front[i]].cost, points[front[i - 1]].cost);
    EXPECT_LT(points[front[i]].error, points[front[i - 1]].error);
  }
}

TEST(Pareto, DefaultOffItsFrontPointsToTheFastestSettingAtLeastAsGood) {
  // The default (index 0) is beaten by both 1 and 2; 1 is the cheaper of them.
  const std::vector<ParetoPoint> points{{0, 10.0, 1.0}, {0, 4.0, 1.0}, {0, 6.0, 0.5}, {0, 12.0, 0.1}};
  EXPECT_EQ(fastest_dominating(points, 0), 1u);
  EXPECT_FALSE(fastest_dominating(points, 3).has_value());
}

TEST(Pareto, DefaultOnItsFrontHasNothingBetter) {
  const std::vector<ParetoPoint> points{{0, 10.0, 0.1}, {0, 4.0, 1.0}, {0, 20.0, 0.1}};
  EXPECT_FALSE(fastest_dominating(points, 0).has_value());
  EXPECT_EQ(fastest_dominating(points, 2), 0u);
}

}  // namespace
}  // namespace fxbench
