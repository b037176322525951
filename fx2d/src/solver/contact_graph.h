// ContactGraph: colours the step's contact constraints so that each colour can be solved as
// independent lanes of a batch.
//
// Invariant: no two contacts in a colour share a movable body; static bodies never conflict
// (their state is never changed by a contact, so any number of lanes may read them); what fits
// no colour goes to the overflow group, solved serially. Colouring is greedy in the constraints'
// order, which is the contact cache's slot order, so the same step always gets the same colours.
// Within a colour (and the overflow), one-point contacts are listed before two-point ones, each in
// constraint order: the batches' runs (contact_batch.h). Those runs leave few lanes empty: over 200
// steps, sleeping off, the constraints fill 0.92 of their batches' lanes on settling_boxes 200
// (4 colours), 0.96 on 800, 0.95 on pile 300, 0.99 on pile 1200 and 0.78 on stacks 50 (50
// constraints in 8 batches), so a colouring that packs them tighter has little to win.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "fx2d/Constraint.h"

namespace fx2d::detail {

struct ConstraintSource;

class ContactGraph {
 public:
  static constexpr int max_colours = 16;
  static constexpr int overflow = max_colours;

  // A body is movable when its state carries movable_flag (prepare_solver sets it on the awake
  // dynamic bodies); the solver never changes any other body's state. The colours depend on
  // nothing else, so when every constraint has the bodies, point count and movability it had at
  // the last build, that build's colours stand (the usual step of a scene at rest).
  void build(std::span<const ConstraintSource> constraints, std::span<const FxBodyState> states);
  // True when every constraint has the bodies, point count and movability it had at the last build.
  bool same_as_last(std::span<const ConstraintSource> constraints, std::span<const FxBodyState> states) const;

  // Grows storage for this many constraints and bodies, so build() does not allocate up to there.
  void reserve(std::size_t constraints, std::size_t bodies);

  int colour_count() const { return colour_count_; }
  // Constraint indices of colour c (0 <= c < colour_count()), or of the overflow group (c == overflow).
  std::span<const int> members(int c) const { return listed(group(c, 1), group(c, 2) + 1); }
  // Those of them with `points` manifold points (1 or 2).
  std::span<const int> members(int c, int points) const { return listed(group(c, points), group(c, points) + 1); }

 private:
  static_assert(max_colours < 32, "a body's colours are a 32-bit set");
  // All the colouring reads of a constraint: its bodies; its point count and which of them are
  // movable, in one word (shape_of).
  struct Coloured {
    std::uint32_t body_a = 0;
    std::uint32_t body_b = 0;
    std::uint32_t shape = 0;
  };
  void colour(std::span<const ConstraintSource> constraints, std::span<const FxBodyState> states);

  std::vector<Coloured> coloured_;  // per constraint of the last build
  std::vector<std::uint32_t> colours_of_;  // per body, the colours that hold it
  std::vector<std::uint8_t> group_of_;  // per constraint, its colour's group for its point count
  static constexpr int groups = 2 * (max_colours + 1);  // per colour and the overflow, per point count
  static int group(int colour, int points) { return 2 * colour + points - 1; }
  std::span<const int> listed(int first_group, int end_group) const {
    return {order_.data() + offsets_[first_group], static_cast<std::size_t>(offsets_[end_group] - offsets_[first_group])};
  }

  std::vector<int> order_;            // constraint indices grouped by colour and point count, overflow last
  int offsets_[groups + 1] = {};
  int colour_count_ = 0;
};

}  // namespace fx2d::detail
