// The contact cache's slots, free list and per-body edge lists (contact_cache.h).
#include "collision/contact_cache.h"

#include "fx2d/Constraint.h"

namespace fx2d::detail {

int ContactCache::create(std::uint32_t a, std::uint32_t b, int& head_a, int& head_b) {
  int id = free_head_;
  if (id >= 0) {
    free_head_ = slots[id].next_edge[0];
    slots[id] = CachedContact{};
  } else {
    id = static_cast<int>(slots.size());
    slots.emplace_back();
  }
  CachedContact& contact = slots[id];
  contact.body_a = a;
  contact.body_b = b;
  contact.alive = true;
  link(2 * id, head_a);
  link(2 * id + 1, head_b);
  return id;
}

void ContactCache::destroy(int id, int& head_a, int& head_b) {
  unlink(2 * id, head_a);
  unlink(2 * id + 1, head_b);
  CachedContact& contact = slots[id];
  if (contact.touching) --touching_count;
  contact.alive = false;
  contact.touching = false;
  contact.next_edge[0] = free_head_;
  free_head_ = id;
}

void ContactCache::scale_impulses(float ratio) {
  for (CachedContact& contact : slots) {
    for (int i = 0; i < 2; ++i) {
      contact.normal_impulse[i] = fx_carried_impulse(contact.normal_impulse[i], ratio);
      contact.tangent_impulse[i] = fx_carried_impulse(contact.tangent_impulse[i], ratio);
    }
  }
}

bool ContactCache::has_pair(int head, std::uint32_t other) const {
  for (int edge = head; edge >= 0; edge = next(edge)) {
    if (other_body(edge) == other) return true;
  }
  return false;
}

void ContactCache::link(int edge, int& head) {
  CachedContact& contact = slots[contact_of(edge)];
  const int side = side_of(edge);
  contact.prev_edge[side] = -1;
  contact.next_edge[side] = head;
  if (head >= 0) slots[contact_of(head)].prev_edge[side_of(head)] = edge;
  head = edge;
}

void ContactCache::unlink(int edge, int& head) {
  CachedContact& contact = slots[contact_of(edge)];
  const int side = side_of(edge);
  const int prev = contact.prev_edge[side];
  const int next_e = contact.next_edge[side];
  if (prev >= 0) {
    slots[contact_of(prev)].next_edge[side_of(prev)] = next_e;
  } else {
    head = next_e;
  }
  if (next_e >= 0) slots[contact_of(next_e)].prev_edge[side_of(next_e)] = prev;
}

}  // namespace fx2d::detail
