// The contact cache: one record per pair of bodies whose fat boxes overlap, kept across steps so
// that each point's impulses carry over to the next step (warm starting).
//
// Records live in a slot vector with a free list; a record's id is its slot and never changes
// while it lives. Each body keeps an intrusive doubly linked list of its contacts through
// "edges" (edge = 2 * id + side, side 0 for body_a and 1 for body_b), so "does this pair have a
// contact?" walks one short list instead of probing a hash map. Invariant: body_a < body_b (packed
// indices), and a pair has at most one live record.
#pragma once

#include <cstdint>
#include <vector>

#include "collision/collide.h"

namespace fx2d::detail {

// Where a pair stood at its last full collision, so that its manifold can be reused while the pair
// has barely moved since (narrow_phase.cpp): B's placement and the normal in A's frame, and each
// point's two surface points in its own body's frame.
struct ManifoldFrame {
  bool valid = false;  // first, beside the fields every pair reads
  FxTransform b_in_a;
  FxVec2f normal_in_a;
  FxVec2f on_a[2];
  FxVec2f on_b[2];
};

// What every step reads of every pair (ids, flags, manifold, impulses, material) comes first, in
// the record's first two cache lines; the frame only resting polygon pairs read comes last.
struct CachedContact {
  std::uint32_t body_a = 0;
  std::uint32_t body_b = 0;
  bool alive = false;
  bool touching = false;
  // Whether each body is a circle, whose point facing the other body stays on the line of centres
  // however it spins: the solver's anchors on it do not turn with it (contact_packing.cpp).
  bool round_a = false;
  bool round_b = false;
  int next_edge[2] = {-1, -1};
  int prev_edge[2] = {-1, -1};
  Manifold manifold;
  float normal_impulse[2] = {0.0f, 0.0f};
  float tangent_impulse[2] = {0.0f, 0.0f};
  // Material resolved once per pair.
  float static_friction = 0.0f;
  float dynamic_friction = 0.0f;
  float restitution = 0.0f;
  // How far B may move in A's frame after a full collision before the next one: resolved once per
  // pair (manifold_reuse_distance, narrow_phase.h), read with the frame.
  float reuse_distance = 0.0f;
  ManifoldFrame frame;
};

// What a record's points carry to the next manifold's points of the same features (ContactCache).
struct WarmStart {
  int point_count = 0;
  std::uint32_t ids[2] = {0, 0};
  float normal_impulse[2] = {0.0f, 0.0f};
  float tangent_impulse[2] = {0.0f, 0.0f};
};

class ContactCache {
 public:
  // Creates the record for (a, b), a < b, linking it into both bodies' lists.
  int create(std::uint32_t a, std::uint32_t b, int& head_a, int& head_b);
  // Unlinks and frees a record.
  void destroy(int id, int& head_a, int& head_b);
  // True when the body whose list starts at `head` has a contact with `other`.
  bool has_pair(int head, std::uint32_t other) const;
  // Scales every record's impulses: when the substep length changes (StepContext::impulse_ratio).
  void scale_impulses(float ratio);

  // A record's feature ids and impulses before its manifold is collided anew, and then the impulses
  // carried over to the new points with the same feature ids. These touch that record alone, so
  // records may be collided on several threads at once. Inline, as update_touching(): the narrow
  // phase calls them for every pair every step.
  static WarmStart warm_start_of(const CachedContact& contact) {
    WarmStart previous;
    previous.point_count = contact.manifold.point_count;
    for (int i = 0; i < 2; ++i) {
      previous.ids[i] = contact.manifold.points[i].id;
      previous.normal_impulse[i] = contact.normal_impulse[i];
      previous.tangent_impulse[i] = contact.tangent_impulse[i];
    }
    return previous;
  }
  static void carry_impulses(const WarmStart& previous, CachedContact& contact) {
    float normal_impulse[2] = {0.0f, 0.0f};
    float tangent_impulse[2] = {0.0f, 0.0f};
    for (int i = 0; i < contact.manifold.point_count; ++i) {
      for (int j = 0; j < previous.point_count; ++j) {
        if (previous.ids[j] == contact.manifold.points[i].id) {
          normal_impulse[i] = previous.normal_impulse[j];
          tangent_impulse[i] = previous.tangent_impulse[j];
          break;
        }
      }
    }
    for (int i = 0; i < 2; ++i) {
      contact.normal_impulse[i] = normal_impulse[i];
      contact.tangent_impulse[i] = tangent_impulse[i];
    }
  }
  // Sets `touching` from the record's manifold, touching that record alone (as warm_start_of()):
  // +1 if it began touching, -1 if it stopped, 0 if neither, for touching_count.
  static int update_touching(CachedContact& contact) {
    const bool touching = contact.manifold.point_count > 0;
    const int change = int(touching) - int(contact.touching);
    contact.touching = touching;
    return change;
  }

  static int contact_of(int edge) { return edge >> 1; }
  static int side_of(int edge) { return edge & 1; }
  std::uint32_t other_body(int edge) const {
    const CachedContact& c = slots[contact_of(edge)];
    return side_of(edge) == 0 ? c.body_b : c.body_a;
  }
  int next(int edge) const { return slots[contact_of(edge)].next_edge[side_of(edge)]; }

  std::vector<CachedContact> slots;
  int touching_count = 0;

 private:
  void link(int edge, int& head);
  void unlink(int edge, int& head);

  int free_head_ = -1;
};

}  // namespace fx2d::detail
