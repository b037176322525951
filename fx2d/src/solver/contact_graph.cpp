// Greedy colouring of the step's contact constraints (contact_graph.h): per colour a bitset over
// the bodies it already holds; the constraints are then listed colour by colour, overflow last.
#include "solver/contact_graph.h"

#include <algorithm>

#include "solver/contact_solver.h"
#include "solver/lane_rows.h"

namespace fx2d::detail {

void ContactGraph::reserve(std::size_t constraints, std::size_t bodies) {
  used_.reserve(((bodies + 63) / 64) * max_colours);
  colour_of_.reserve(constraints);
  order_.reserve(constraints);
}

void ContactGraph::build(std::span<const ContactConstraint> constraints, std::span<const FxBodyState> states) {
  const std::size_t words = (states.size() + 63) / 64;
  const auto movable = [&](std::uint32_t body) { return (states[body].flags & movable_flag) != 0; };
  used_.assign(words * max_colours, 0);
  colour_of_.resize(constraints.size());
  int counts[max_colours + 1] = {};
  colour_count_ = 0;

  auto taken = [&](int colour, std::uint32_t body) {
    return movable(body) && (used_[colour * words + body / 64] >> (body % 64) & 1u);
  };
  auto take = [&](int colour, std::uint32_t body) {
    if (movable(body)) used_[colour * words + body / 64] |= std::uint64_t{1} << (body % 64);
  };
  for (std::size_t i = 0; i < constraints.size(); ++i) {
    const std::uint32_t a = constraints[i].body_a;
    const std::uint32_t b = constraints[i].body_b;
    int colour = 0;
    while (colour < max_colours && (taken(colour, a) || taken(colour, b))) ++colour;
    if (colour < max_colours) {
      take(colour, a);
      take(colour, b);
      colour_count_ = std::max(colour_count_, colour + 1);
    }
    colour_of_[i] = static_cast<std::uint8_t>(colour);
    ++counts[colour];
  }

  offsets_[0] = 0;
  for (int c = 0; c < max_colours + 1; ++c) offsets_[c + 1] = offsets_[c] + counts[c];
  order_.resize(constraints.size());
  int cursor[max_colours + 1];
  std::copy(offsets_, offsets_ + max_colours + 1, cursor);
  for (std::size_t i = 0; i < constraints.size(); ++i) order_[cursor[colour_of_[i]]++] = static_cast<int>(i);
}

}  // namespace fx2d::detail
