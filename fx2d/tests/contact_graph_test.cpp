// The contact graph's invariant, checked exhaustively: within a colour no movable body appears
// twice; every constraint is in exactly one group; static bodies never force a new colour.
#include <gtest/gtest.h>

#include <random>
#include <set>
#include <vector>

#include "solver/contact_graph.h"
#include "solver/contact_solver.h"
#include "solver/lane_rows.h"

namespace fx2d::detail {
namespace {

std::vector<ConstraintSource> pairs_to_constraints(const std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs) {
  std::vector<ConstraintSource> constraints(pairs.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    constraints[i].body_a = pairs[i].first;
    constraints[i].body_b = pairs[i].second;
  }
  return constraints;
}

// Solver states with movable_flag set where `movable` says so, as prepare_solver flags them.
std::vector<FxBodyState> flagged_states(const std::vector<std::uint8_t>& movable) {
  std::vector<FxBodyState> states(movable.size());
  for (std::size_t i = 0; i < movable.size(); ++i) states[i].flags = movable[i] ? movable_flag : 0u;
  return states;
}

// Checks the invariant and returns how many constraints the groups hold in all.
std::size_t check_colouring(const ContactGraph& graph, const std::vector<ConstraintSource>& constraints,
                            const std::vector<std::uint8_t>& movable) {
  std::vector<int> seen(constraints.size(), 0);
  std::size_t total = 0;
  for (int colour = 0; colour < graph.colour_count(); ++colour) {
    std::set<std::uint32_t> bodies;
    for (const int index : graph.members(colour)) {
      ++seen[index];
      ++total;
      for (const std::uint32_t body : {constraints[index].body_a, constraints[index].body_b}) {
        if (!movable[body]) continue;
        EXPECT_TRUE(bodies.insert(body).second) << "body " << body << " twice in colour " << colour;
      }
    }
  }
  for (const int index : graph.members(ContactGraph::overflow)) {
    ++seen[index];
    ++total;
  }
  for (std::size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i], 1) << "constraint " << i;
  return total;
}

TEST(ContactGraph, RandomGraphsNeverShareAMovableBodyWithinAColour) {
  std::mt19937 engine(12345);
  auto random = [&engine] { return static_cast<std::uint32_t>(engine()); };
  for (int trial = 0; trial < 200; ++trial) {
    const std::uint32_t bodies = 2 + random() % 300;
    std::vector<std::uint8_t> movable(bodies);
    for (auto& m : movable) m = (random() % 5) != 0;  // a fifth static
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
    const std::size_t count = random() % (4 * bodies);
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint32_t a = random() % bodies;
      const std::uint32_t b = random() % bodies;
      if (a != b) pairs.emplace_back(std::min(a, b), std::max(a, b));
    }
    const auto constraints = pairs_to_constraints(pairs);
    ContactGraph graph;
    graph.build(constraints, flagged_states(movable));
    EXPECT_EQ(check_colouring(graph, constraints, movable), constraints.size()) << "trial " << trial;
  }
}

TEST(ContactGraph, StaticBodiesNeverConflict) {
  // Forty boxes all resting on one static ground: one colour suffices.
  std::vector<std::uint8_t> movable(41, 1);
  movable[0] = 0;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  for (std::uint32_t i = 1; i <= 40; ++i) pairs.emplace_back(0, i);
  const auto constraints = pairs_to_constraints(pairs);
  ContactGraph graph;
  graph.build(constraints, flagged_states(movable));
  EXPECT_EQ(graph.colour_count(), 1);
  EXPECT_TRUE(graph.members(ContactGraph::overflow).empty());
}

TEST(ContactGraph, WhatFitsNoColourGoesToOverflow) {
  // A hub body touching more bodies than there are colours: the rest overflows, in order.
  const std::uint32_t spokes = ContactGraph::max_colours + 5;
  std::vector<std::uint8_t> movable(spokes + 1, 1);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  for (std::uint32_t i = 1; i <= spokes; ++i) pairs.emplace_back(0, i);
  const auto constraints = pairs_to_constraints(pairs);
  ContactGraph graph;
  graph.build(constraints, flagged_states(movable));
  EXPECT_EQ(graph.colour_count(), ContactGraph::max_colours);
  ASSERT_EQ(graph.members(ContactGraph::overflow).size(), 5u);
  EXPECT_EQ(graph.members(ContactGraph::overflow)[0], ContactGraph::max_colours);
  check_colouring(graph, constraints, movable);
}

// Whether two graphs list the same constraints in every colour and in the overflow.
void expect_same_colours(const ContactGraph& built, const ContactGraph& fresh) {
  ASSERT_EQ(built.colour_count(), fresh.colour_count());
  std::vector<int> groups;
  for (int colour = 0; colour < fresh.colour_count(); ++colour) groups.push_back(colour);
  groups.push_back(ContactGraph::overflow);
  for (const int colour : groups) {
    for (int points = 1; points <= 2; ++points) {
      const std::span<const int> a = built.members(colour, points), b = fresh.members(colour, points);
      EXPECT_EQ(std::vector<int>(a.begin(), a.end()), std::vector<int>(b.begin(), b.end())) << "colour " << colour;
    }
  }
}

TEST(ContactGraph, ABuildKeepsTheLastColoursOnlyWhileConstraintsAndMovabilityStay) {
  // A chain 0-1-2-3 of movable bodies takes two colours; with 1 and 2 static, one.
  auto constraints = pairs_to_constraints({{0, 1}, {1, 2}, {2, 3}});
  const std::vector<std::uint8_t> chain = {1, 1, 1, 1}, ends_only = {1, 0, 0, 1};
  ContactGraph graph;
  graph.build(constraints, flagged_states(chain));
  EXPECT_EQ(graph.colour_count(), 2);
  graph.build(constraints, flagged_states(chain));
  EXPECT_EQ(graph.colour_count(), 2);
  graph.build(constraints, flagged_states(ends_only));
  EXPECT_EQ(graph.colour_count(), 1);
  check_colouring(graph, constraints, ends_only);
  // Same bodies, another point count: the groups move.
  constraints[1].point_count = 2;
  graph.build(constraints, flagged_states(ends_only));
  ContactGraph fresh;
  fresh.build(constraints, flagged_states(ends_only));
  expect_same_colours(graph, fresh);
  // Another list of the same length.
  constraints[2].body_b = 0;
  graph.build(constraints, flagged_states(chain));
  ContactGraph fresh_chain;
  fresh_chain.build(constraints, flagged_states(chain));
  expect_same_colours(graph, fresh_chain);
  check_colouring(graph, constraints, chain);
}

}  // namespace
}  // namespace fx2d::detail
