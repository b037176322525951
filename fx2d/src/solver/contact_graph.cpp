// Greedy colouring of the step's contact constraints (contact_graph.h): per body a bitset of the
// colours that already hold it; the constraints are then listed colour by colour and point count
// by point count, overflow last.
#include "solver/contact_graph.h"

#include <algorithm>
#include <bit>

#include "solver/contact_solver.h"
#include "solver/lane_rows.h"

namespace fx2d::detail {

void ContactGraph::reserve(std::size_t constraints, std::size_t bodies) {
  colours_of_.reserve(bodies);
  group_of_.reserve(constraints);
  order_.reserve(constraints);
}

void ContactGraph::build(std::span<const ConstraintSource> constraints, std::span<const FxBodyState> states) {
  colours_of_.assign(states.size(), 0);
  group_of_.resize(constraints.size());
  int counts[groups] = {};
  // Locals, not members: the byte stores to group_of would otherwise make the compiler reload
  // every member after each.
  std::uint32_t* const colours_of = colours_of_.data();
  std::uint8_t* const group_of = group_of_.data();
  int colour_count = 0;

  // Only a movable body takes a place in a colour: another's bits stay clear, so it never conflicts.
  const auto places_of = [&](std::uint32_t body) -> std::uint32_t {
    return (states[body].flags & movable_flag) != 0 ? ~std::uint32_t{0} : 0;
  };
  // Invariant: colours_of[body] has bit c set when colour c already holds that body, so a
  // constraint takes the lowest colour neither of its bodies holds (max_colours: none is free).
  for (std::size_t i = 0; i < constraints.size(); ++i) {
    const std::uint32_t a = constraints[i].body_a;
    const std::uint32_t b = constraints[i].body_b;
    const int colour = std::countr_one(colours_of[a] | colours_of[b]);
    if (colour < max_colours) {
      const std::uint32_t bit = std::uint32_t{1} << colour;
      colours_of[a] |= bit & places_of(a);
      colours_of[b] |= bit & places_of(b);
      colour_count = std::max(colour_count, colour + 1);
    }
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
