// Greedy colouring of the step's contact constraints (contact_graph.h): per body a bitset of the
// colours that already hold it; the constraints are then listed colour by colour and point count
// by point count, overflow last.
#include "solver/contact_graph.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <type_traits>

#include "solver/contact_solver.h"
#include "solver/lane_rows.h"

namespace fx2d::detail {
namespace {

// The colours a body may take a place in: all when it is movable; none (its bits stay clear, so
// it never conflicts) when it is not.
std::uint32_t places_of(std::span<const FxBodyState> states, std::uint32_t body) {
  return (states[body].flags & movable_flag) != 0 ? ~std::uint32_t{0} : 0;
}

// Of a constraint's bodies' places: bit 0, body a is movable; bit 1, body b.
std::uint8_t movability(std::uint32_t places_a, std::uint32_t places_b) {
  return static_cast<std::uint8_t>((places_a & 1u) | (places_b & 2u));
}

}  // namespace

void ContactGraph::reserve(std::size_t constraints, std::size_t bodies) {
  colours_of_.reserve(bodies);
  group_of_.reserve(constraints);
  order_.reserve(constraints);
  last_constraints_.reserve(constraints);
  last_movable_.reserve(constraints);
}

bool ContactGraph::same_as_last(std::span<const ConstraintSource> constraints,
                                std::span<const FxBodyState> states) const {
  static_assert(std::has_unique_object_representations_v<ConstraintSource>, "compared as bytes");
  // The list first, in one bytewise compare, so that a step whose contacts changed pays little;
  // the bodies' flags, scattered reads, only when it matches.
  if (constraints.size() != last_constraints_.size()) return false;
  if (constraints.empty()) return true;
  if (std::memcmp(constraints.data(), last_constraints_.data(), constraints.size_bytes()) != 0) return false;
  for (std::size_t i = 0; i < constraints.size(); ++i) {
    const ConstraintSource& constraint = constraints[i];
    if (movability(places_of(states, constraint.body_a), places_of(states, constraint.body_b)) != last_movable_[i]) {
      return false;
    }
  }
  return true;
}

void ContactGraph::build(std::span<const ConstraintSource> constraints, std::span<const FxBodyState> states) {
  if (same_as_last(constraints, states)) return;
  colour(constraints, states);
  last_constraints_.assign(constraints.begin(), constraints.end());
}

void ContactGraph::colour(std::span<const ConstraintSource> constraints, std::span<const FxBodyState> states) {
  colours_of_.assign(states.size(), 0);
  group_of_.resize(constraints.size());
  last_movable_.resize(constraints.size());
  int counts[groups] = {};
  // Locals, not members: the byte stores to group_of would otherwise make the compiler reload
  // every member after each.
  std::uint32_t* const colours_of = colours_of_.data();
  std::uint8_t* const group_of = group_of_.data();
  std::uint8_t* const last_movable = last_movable_.data();
  int colour_count = 0;

  // Invariant: colours_of[body] has bit c set when colour c already holds that body, so a
  // constraint takes the lowest colour neither of its bodies holds (max_colours: none is free).
  for (std::size_t i = 0; i < constraints.size(); ++i) {
    const std::uint32_t a = constraints[i].body_a;
    const std::uint32_t b = constraints[i].body_b;
    const std::uint32_t places_a = places_of(states, a), places_b = places_of(states, b);
    const int colour = std::countr_one(colours_of[a] | colours_of[b]);
    if (colour < max_colours) {
      const std::uint32_t bit = std::uint32_t{1} << colour;
      colours_of[a] |= bit & places_a;
      colours_of[b] |= bit & places_b;
      colour_count = std::max(colour_count, colour + 1);
    }
    last_movable[i] = movability(places_a, places_b);
    const int g = group(colour, constraints[i].point_count);
    group_of[i] = static_cast<std::uint8_t>(g);
    ++counts[g];
  }
  colour_count_ = colour_count;

  offsets_[0] = 0;
  for (int g = 0; g < groups; ++g) offsets_[g + 1] = offsets_[g] + counts[g];
  order_.resize(constraints.size());
  int cursor[groups];
  std::copy(offsets_, offsets_ + groups, cursor);
  for (std::size_t i = 0; i < constraints.size(); ++i) order_[cursor[group_of[i]]++] = static_cast<int>(i);
}

}  // namespace fx2d::detail
