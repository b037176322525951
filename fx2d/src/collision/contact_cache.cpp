// The contact cache's slots, free list and per-body edge lists (contact_cache.h), and the carrying
// of impulses from one manifold to the next by feature id.
#include "collision/contact_cache.h"

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

bool ContactCache::has_pair(int head, std::uint32_t other) const {
  for (int edge = head; edge >= 0; edge = next(edge)) {
    if (other_body(edge) == other) return true;
  }
  return false;
}

void ContactCache::replace_manifold(CachedContact& contact, const Manifold& manifold) {
  float normal_impulse[2] = {0.0f, 0.0f};
  float tangent_impulse[2] = {0.0f, 0.0f};
  for (int i = 0; i < manifold.point_count; ++i) {
    for (int j = 0; j < contact.manifold.point_count; ++j) {
      if (contact.manifold.points[j].id == manifold.points[i].id) {
        normal_impulse[i] = contact.normal_impulse[j];
        tangent_impulse[i] = contact.tangent_impulse[j];
        break;
      }
    }
  }
  contact.manifold = manifold;
  for (int i = 0; i < 2; ++i) {
    contact.normal_impulse[i] = normal_impulse[i];
    contact.tangent_impulse[i] = tangent_impulse[i];
  }
}

bool ContactCache::update_touching(CachedContact& contact) {
  const bool touching = contact.manifold.point_count > 0;
  const bool began = touching && !contact.touching;
  if (touching != contact.touching) touching_count += touching ? 1 : -1;
  contact.touching = touching;
  return began;
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
