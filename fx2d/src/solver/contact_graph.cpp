// Greedy colouring of the step's contact constraints (contact_graph.h): per body a bitset of the
// colours that already hold it; the constraints are then listed colour by colour and point count
// by point count, overflow last.
#include "solver/contact_graph.h"

#include <algorithm>
#include <bit>

#include "solver/contact_solver.h"
#include "solver/lane_rows.h"

namespace fx2d::detail {
namespace {

// Only a movable body takes a place in a colour: another's bits stay clear, so it never conflicts.
std::uint32_t places_of(std::span<const FxBodyState> states, std::uint32_t body) {
  return (states[body].flags & movable_flag) != 0 ? ~std::uint32_t{0} : 0;
}

// A constraint's point count, with bit 2 set when body a is movable and bit 3 when body b is.
std::uint32_t shape_of(int point_count, std::uint32_t places_a, std::uint32_t places_b) {
  return static_cast<std::uint32_t>(point_count) | (places_a & 4u) | (places_b & 8u);
}

}  // namespace

void ContactGraph::reserve(std::size_t constraints, std::size_t bodies) {
  colours_of_.reserve(bodies);
  group_of_.reserve(constraints);
  order_.reserve(constraints);
  coloured_.reserve(constraints);
}

void ContactGraph::build(std::span<const ConstraintSource> constraints, std::span<const FxBodyState> states) {
  if (!same_as_last(constraints, states)) colour(constraints, states);
}

// Field by field in a loop that stops at the first difference, not memcmp: libc's compare and
// copy routines take a path by the buffers' alignment, and an instruction count must not depend
// on where the heap put them (fx2d-bench ab --counter instructions).
bool ContactGraph::same_as_last(std::span<const ConstraintSource> constraints,
                                std::span<const FxBodyState> states) const {
  if (constraints.size() != coloured_.size()) return false;
  for (std::size_t i = 0; i < constraints.size(); ++i) {
    const ConstraintSource& constraint = constraints[i];
    const Coloured& last = coloured_[i];
    const std::uint32_t a = constraint.body_a, b = constraint.body_b;
    if (a != last.body_a || b != last.body_b) return false;
    const std::uint32_t shape = shape_of(constraint.point_count, places_of(states, a), places_of(states, b));
    if (shape != last.shape) return false;
  }
  return true;
}

void ContactGraph::colour(std::span<const ConstraintSource> constraints, std::span<const FxBodyState> states) {
  colours_of_.assign(states.size(), 0);
  group_of_.resize(constraints.size());
  coloured_.resize(constraints.size());
  int counts[groups] = {};
  // Locals, not members: the byte stores to group_of would otherwise make the compiler reload
  // every member after each.
  std::uint32_t* const colours_of = colours_of_.data();
  std::uint8_t* const group_of = group_of_.data();
  Coloured* const coloured = coloured_.data();
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
    coloured[i] = {a, b, shape_of(constraints[i].point_count, places_a, places_b)};
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
