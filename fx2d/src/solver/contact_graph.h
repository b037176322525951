// ContactGraph: colours the step's contact constraints so that each colour can be solved as
// independent lanes of a batch.
//
// Invariant: no two contacts in a colour share a movable body; static bodies never conflict
// (their state is never changed by a contact, so any number of lanes may read them); what fits
// no colour goes to the overflow group, solved serially. Colouring is greedy in the constraints'
// order, which is the contact cache's slot order, so the same step always gets the same colours.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "fx2d/Constraint.h"

namespace fx2d::detail {

struct ContactConstraint;

class ContactGraph {
 public:
  static constexpr int max_colours = 16;
  static constexpr int overflow = max_colours;

  // A body is movable when its state carries movable_flag (prepare_solver sets it on the awake
  // dynamic bodies); the solver never changes any other body's state.
  void build(std::span<const ContactConstraint> constraints, std::span<const FxBodyState> states);

  // Grows storage for this many constraints and bodies, so build() does not allocate up to there.
  void reserve(std::size_t constraints, std::size_t bodies);

  int colour_count() const { return colour_count_; }
  // Constraint indices of colour c (0 <= c < colour_count()), or of the overflow group (c == overflow).
  std::span<const int> members(int c) const {
    return {order_.data() + offsets_[c], static_cast<std::size_t>(offsets_[c + 1] - offsets_[c])};
  }

 private:
  std::vector<std::uint64_t> used_;   // per colour, a bitset over bodies
  std::vector<std::uint8_t> colour_of_;
  std::vector<int> order_;            // constraint indices grouped by colour, overflow last
  int offsets_[max_colours + 2] = {};
  int colour_count_ = 0;
};

}  // namespace fx2d::detail
