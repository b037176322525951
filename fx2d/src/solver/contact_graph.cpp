// Greedy colouring of the step's contact constraints (contact_graph.h): per colour a bitset over
// the bodies it already holds; the constraints are then listed colour by colour and point count
// by point count, overflow last.
#include "solver/contact_graph.h"

#include <algorithm>

#include "solver/contact_solver.h"
#include "solver/lane_rows.h"

namespace fx2d::detail {

void ContactGraph::reserve(std::size_t constraints, std::size_t bodies) {
  used_.reserve(((bodies + 63) / 64) * max_colours);
  group_of_.reserve(constraints);
  order_.reserve(constraints);
}

void ContactGraph::build(std::span<const ConstraintSource> constraints, std::span<const FxBodyState> states) {
  const std::size_t words = (states.size() + 63) / 64;
  used_.assign(words * max_colours, 0);
  group_of_.resize(constraints.size());
  int counts[groups] = {};
  // Locals, not members: the byte stores to group_of would otherwise make the compiler reload
  // every member after each.
  std::uint64_t* const used = used_.data();
  std::uint8_t* const group_of = group_of_.data();
  int colour_count = 0;

  // A body that is not movable takes no place in a colour: its bit is never set nor tested.
  const auto bit_of = [&](std::uint32_t body) {
    return (states[body].flags & movable_flag) != 0 ? std::uint64_t{1} << (body % 64) : std::uint64_t{0};
  };
  // Invariant: used[colour * words + w] holds the movable bodies colour already has, so a
  // constraint takes the first colour where neither of its bodies' bits is set.
  for (std::size_t i = 0; i < constraints.size(); ++i) {
    const std::uint32_t a = constraints[i].body_a;
    const std::uint32_t b = constraints[i].body_b;
    const std::uint64_t bit_a = bit_of(a), bit_b = bit_of(b);
    std::size_t word_a = a / 64, word_b = b / 64;
    int colour = 0;
    while (colour < max_colours && ((used[word_a] & bit_a) | (used[word_b] & bit_b)) != 0) {
      ++colour;
      word_a += words;
      word_b += words;
    }
    if (colour < max_colours) {
      used[word_a] |= bit_a;
      used[word_b] |= bit_b;
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
