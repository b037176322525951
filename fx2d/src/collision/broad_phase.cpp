// Broad phase: keep each body's proxy in the tree and find the pairs whose fat boxes begin to
// overlap. Runs once per step. A proxy's fat box is its tight box enlarged by a margin and swept
// by a few steps of its motion, so a body that moves a little, or moves steadily, stays inside it
// and is not reinserted; only bodies whose tight box left their fat box are searched for new pairs.
#include "collision/broad_phase.h"

#include <algorithm>
#include <cmath>

#include "collision/narrow_phase.h"
#include "world/step_context.h"

namespace fx2d::detail {
namespace {

// Metres. At 0.05 the narrow phase had fewer pairs apart (collide 0.86-0.90 of the time on
// settling_boxes 800 and 200) but the broad phase moved more proxies (1.4-4.1 times its time): the
// step took 0.98-1.04, and pile 300 and settling_boxes 800 penetrated deeper (their pairs found
// later: 2.07 -> 2.33 and 4.07 -> 4.60 mm).
constexpr float proxy_margin = 0.1f;
// A fat box covers this many steps of the body's current motion. One step made a steadily falling
// body leave its box every other step (a third of the broad phase's time went to reinserting
// proxies on settling_boxes 3000); four cost some extra narrow-phase pairs and save more. Against
// four (`ab`, sleeping off): two took settling_boxes 3000's step to 1.030 (broad phase 3.2 times
// as long) and pile 1200's penetration from 8.3 to 13.4 mm; eight took settling_boxes 3000's to
// 1.020 (broad phase 0.53, collide 1.31). Re-measured once pairs apart cost less to collide (the
// narrow phase's surely_apart), eight still did not pay: settling_boxes 3000 0.979 [0.963, 1.000],
// 800 1.018, pile 800 0.969 [0.953, 1.010], and less accurate. Nor did sweeping a dynamic body's
// box by gravity's fall over those four steps too, which a falling body leaves a step later:
// settling_boxes 3000 0.993 [0.964, 1.003] (broad phase 0.90), 800 0.990, pile 800 1.002, and
// settling_boxes 800 penetrated 6.13 mm instead of 5.36 (pairs found in another order).
constexpr float proxy_sweep_steps = 4.0f;
// When more than one proxy in this many moves in a step, their boxes are set in place and the
// tree refitted, or rebuilt if that leaves it this much worse than when last rebuilt
// (AabbTree::refit_or_rebuild), rather than each proxy moved. A refit is one pass over the nodes,
// a move a walk down and up the tree: one in 2, 4, 8, 16, 64 gave 13.17, 12.95, 12.94, 12.91,
// 12.90 M instructions a step on settling_boxes 3000 and 3.50, 3.48, 3.48, 3.48, 3.50 M on 800.
constexpr std::size_t refit_fraction_inverse = 16;
constexpr float refit_growth_allowed = 1.25f;
// When more than three proxies in four move in a step, one walk of the tree against itself finds
// the new pairs (find_pairs_at_once), on one thread. Against a query per moved body, the mean
// step took 0.97-0.98 on settling_boxes 3000 and 200 and 0.99-1.00 on the piles; with the walk
// from one in 16, 2 and 4, settling_boxes 3000 took 1.12, 0.98 and 0.98 (it opens the pairs of
// bodies that did not move too). Nor did a walk that opens no pair of nodes without a moved leaf
// below one of them (a mark per node, set in one pass first) pay from one in 16 or one in 4 (`ab`,
// sleeping off, 800 bodies): settling_boxes 1.008 and 0.999, pile 1.006 and 0.997; instructions
// 1.003 and 1.002, 1.016 and 1.001. Where most bodies move the walk opens what the full walk does.
// Nor did sorting the fat boxes along the axis their centres spread most along, then sweeping them,
// find the same pairs sooner (settling_boxes 800, its steps in which every body moved, timed in one
// process): 125-170 us a step against the walk's 105-200 us. The sort took 31-40 us of it, and the
// sweep tested 11,500 pairs to find the 1,300 that overlap, as a falling column's boxes share its
// span on either axis; the walk opens 5,400-7,900 pairs of nodes for them.
constexpr std::uint32_t at_once_moved_in_four = 3;
// The search for new pairs spreads over the workers in blocks of this many moved bodies, once
// this many have moved (measured: see fx2d/src/README.md).
constexpr std::uint32_t moved_bodies_per_block = 64;
constexpr std::uint32_t min_parallel_moved_bodies = 256;

// A proxy's fat box: the tight box enlarged by a margin and swept by `displacement`.
FxAABB fat_box_for(const FxAABB& tight, FxVec2f displacement) { return swept(inflate(tight, proxy_margin), displacement); }

std::uint64_t pair_key(std::uint32_t a, std::uint32_t b) {
  return a < b ? (std::uint64_t{a} << 32 | b) : (std::uint64_t{b} << 32 | a);
}

void rebuild_jointed_pairs(BroadPhase& broad, const Constraints& constraints) {
  broad.jointed_pairs.clear();
  for (const auto& constraint : constraints) {
    broad.jointed_pairs.push_back(pair_key(constraint->entity_a()->packed_index(), constraint->entity_b()->packed_index()));
  }
  std::sort(broad.jointed_pairs.begin(), broad.jointed_pairs.end());
  broad.jointed_pairs_dirty = false;
}

void create_contact(ContactCache& contacts, std::vector<BodyRecord>& records, std::uint32_t a, std::uint32_t b) {
  const int id = contacts.create(a, b, records[a].contact_head, records[b].contact_head);
  CachedContact& contact = contacts.slots[id];
  const FxMaterial& ma = records[a].material;
  const FxMaterial& mb = records[b].material;
  contact.static_friction = std::sqrt(ma.static_friction * mb.static_friction);
  contact.dynamic_friction = std::sqrt(ma.dynamic_friction * mb.dynamic_friction);
  contact.restitution = ma.restitution > mb.restitution ? ma.restitution : mb.restitution;
  contact.round_a = records[a].shape.type() == FxShapeType::circle;
  contact.round_b = records[b].shape.type() == FxShapeType::circle;
  contact.reuse_distance = manifold_reuse_distance(records[a].shape, records[b].shape);
}

// The bodies that already share a contact with one body: its contact list read once, into an
// array, rather than walked through the scattered contact records for every leaf its query visits.
// A list longer than the array is walked per leaf as before.
class KnownPartners {
 public:
  KnownPartners(const ContactCache& contacts, int head) : contacts_(contacts), head_(head) {
    for (int edge = head; edge >= 0; edge = contacts.next(edge)) {
      if (count_ == capacity) {
        count_ = overflowed;
        return;
      }
      partners_[count_++] = contacts.other_body(edge);
    }
  }
  bool contains(std::uint32_t body) const {
    if (count_ == overflowed) return contacts_.has_pair(head_, body);
    for (int k = 0; k < count_; ++k) {
      if (partners_[k] == body) return true;
    }
    return false;
  }

 private:
  static constexpr int capacity = 24;
  static constexpr int overflowed = -1;
  const ContactCache& contacts_;
  int head_;
  int count_ = 0;
  std::uint32_t partners_[capacity];
};

// Appends to `found` every pair of moved body i whose fat boxes overlap and that has no contact yet.
// A pair of moved bodies is found from both sides; only the lower index records it. Per leaf it
// reads only the broad phase's compact arrays and i's partners, not the other body's record.
// Late in settling_boxes 800 (sleeping off) a query opens 27 internal nodes on average for 4.3
// leaves and takes 0.5-0.7 us, some 25 ns a node: by the broad phase's turn the rest of the step has
// pushed the tree's lines out of the near caches. The 20-30 bodies that leave their boxes in such a
// step cost the broad phase 5-10% of it.
void find_pairs_of(std::uint32_t i, const BroadPhase& broad, const std::vector<BodyRecord>& records,
                   const ContactCache& contacts, std::vector<std::uint64_t>& found) {
  const BodyRecord& record = records[i];
  const bool i_dynamic = record.type == FxBodyType::dynamic;
  const KnownPartners partners(contacts, record.contact_head);
  broad.tree.query(broad.tree.fat_box(record.proxy), [&](int proxy) {
    const std::uint32_t j = broad.body_of_proxy[proxy];
    if (j == i) return true;
    if (broad.proxy_moved[proxy] && j < i) return true;
    if (!i_dynamic && records[j].type != FxBodyType::dynamic) return true;
    if (partners.contains(j) || broad.jointed(i, j)) return true;
    found.push_back(std::uint64_t{i} << 32 | j);
    return true;
  });
}

// The pairs find_pairs_of() finds from every moved body, found instead in one walk of the tree
// against itself: for steps in which most bodies moved, where a query per body walks much of the
// tree again and meets each pair of two moved bodies twice. Recorded as find_pairs_of() records
// them, by the moved body, or the lower index of two, so that sorted they are the same list.
void find_pairs_at_once(const BroadPhase& broad, const std::vector<BodyRecord>& records,
                        const ContactCache& contacts, std::vector<std::uint64_t>& found) {
  broad.tree.for_each_overlapping_pair([&](int proxy, int other) {
    const bool proxy_moved = broad.proxy_moved[proxy] != 0;
    const bool other_moved = broad.proxy_moved[other] != 0;
    if (!proxy_moved && !other_moved) return;
    std::uint32_t i = broad.body_of_proxy[proxy];
    std::uint32_t j = broad.body_of_proxy[other];
    if (!proxy_moved || (other_moved && j < i)) std::swap(i, j);
    if (records[i].type != FxBodyType::dynamic && records[j].type != FxBodyType::dynamic) return;
    if (contacts.has_pair(records[i].contact_head, j) || broad.jointed(i, j)) return;
    found.push_back(std::uint64_t{i} << 32 | j);
  });
}

// Fills broad.new_pairs with the pairs found from the moved bodies, in their order. The search only
// reads the tree, the records and the contacts, so blocks of moved bodies run on any thread, each
// into a list of its own; the lists joined in block order are one thread's list.
void find_new_pairs(const StepContext& step, BroadPhase& broad, const std::vector<BodyRecord>& records,
                    const ContactCache& contacts) {
  const std::vector<std::uint32_t>& moved = broad.moved_bodies;
  const auto moved_count = static_cast<std::uint32_t>(moved.size());
  broad.new_pairs.clear();
  const bool parallel = step.tasks.runs_in_parallel(moved_count, min_parallel_moved_bodies);
  if (!parallel && 4 * moved_count > at_once_moved_in_four * std::uint32_t(broad.tree.proxy_count())) {
    find_pairs_at_once(broad, records, contacts, broad.new_pairs);
    return;
  }
  if (!parallel) {
    for (const std::uint32_t i : moved) find_pairs_of(i, broad, records, contacts, broad.new_pairs);
    return;
  }
  const std::uint32_t blocks = (moved_count + moved_bodies_per_block - 1) / moved_bodies_per_block;
  if (broad.new_pairs_by_block.size() < blocks) broad.new_pairs_by_block.resize(blocks);
  step.tasks.for_each_range(moved_count, moved_bodies_per_block, min_parallel_moved_bodies,
                            [&](std::uint32_t first, std::uint32_t last) {
                              for (std::uint32_t start = first; start < last; start += moved_bodies_per_block) {
                                std::vector<std::uint64_t>& found = broad.new_pairs_by_block[start / moved_bodies_per_block];
                                found.clear();
                                const std::uint32_t end = std::min(start + moved_bodies_per_block, last);
                                for (std::uint32_t k = start; k < end; ++k) find_pairs_of(moved[k], broad, records, contacts, found);
                              }
                            });
  for (std::uint32_t block = 0; block < blocks; ++block) {
    const std::vector<std::uint64_t>& found = broad.new_pairs_by_block[block];
    broad.new_pairs.insert(broad.new_pairs.end(), found.begin(), found.end());
  }
}

}  // namespace

void BroadPhase::reserve(std::size_t bodies) {
  body_of_proxy.reserve(2 * bodies);
  proxy_moved.reserve(2 * bodies);
  moved_bodies.reserve(bodies);
  new_pairs.reserve(4 * bodies);
  // Every block's list reserved as new_pairs is, per body: the search never allocates.
  new_pairs_by_block.resize((bodies + moved_bodies_per_block - 1) / moved_bodies_per_block);
  for (std::vector<std::uint64_t>& found : new_pairs_by_block) found.reserve(4 * moved_bodies_per_block);
  tree.reserve(static_cast<int>(bodies));
}

void BroadPhase::add_body(BodyRecord& record, const FxAABB& aabb, std::uint32_t index) {
  const FxAABB fat = fat_box_for(aabb, {});
  record.proxy = tree.create_proxy(fat);
  if (body_of_proxy.size() <= static_cast<std::size_t>(record.proxy)) {
    body_of_proxy.resize(record.proxy + 1);
    proxy_moved.resize(record.proxy + 1);
  }
  if (record.type != FxBodyType::dynamic) {
    record.fixed_proxy = fixed_tree.create_proxy(fat);
    if (body_of_fixed_proxy.size() <= static_cast<std::size_t>(record.fixed_proxy)) {
      body_of_fixed_proxy.resize(record.fixed_proxy + 1);
    }
  }
  renumber(record, index);
}

void BroadPhase::remove_body(const BodyRecord& record) {
  tree.destroy_proxy(record.proxy);
  if (record.fixed_proxy != AabbTree::null_node) fixed_tree.destroy_proxy(record.fixed_proxy);
}

void BroadPhase::renumber(const BodyRecord& record, std::uint32_t index) {
  body_of_proxy[record.proxy] = index;
  if (record.fixed_proxy != AabbTree::null_node) body_of_fixed_proxy[record.fixed_proxy] = index;
}

bool BroadPhase::jointed(std::uint32_t a, std::uint32_t b) const {
  return std::binary_search(jointed_pairs.begin(), jointed_pairs.end(), pair_key(a, b));
}

void update_broad_phase(const StepContext& step, BroadPhase& broad, Bodies& bodies, ContactCache& contacts,
                        const Constraints& constraints) {
  if (broad.jointed_pairs_dirty) rebuild_jointed_pairs(broad, constraints);
  // Only a step with awake bodies (finalize, continuous) or a body created or placed marks one moved.
  if (!broad.may_have_moved && bodies.awake_count == 0) return;
  broad.may_have_moved = bodies.awake_count > 0;
  std::vector<BodyRecord>& records = bodies.records;
  AabbTree& tree = broad.tree;
  std::vector<std::uint32_t>& moved_bodies = broad.moved_bodies;
  moved_bodies.clear();
  for (std::uint32_t i = 0; i < records.size(); ++i) {
    if (records[i].moved) moved_bodies.push_back(i);
  }
  // When many proxies left their boxes at once (bodies falling in unison do so every few steps),
  // a refit costs less than moving each of them.
  const bool refit = moved_bodies.size() * refit_fraction_inverse > std::size_t(tree.proxy_count());
  for (const std::uint32_t i : moved_bodies) {
    broad.proxy_moved[records[i].proxy] = 1;
    const BodySim& sim = bodies.sims[i];
    const FxAABB fat = fat_box_for(sim.aabb, proxy_sweep_steps * step.settings.dt * sim.linear_velocity);
    if (refit) {
      tree.set_fat_box(records[i].proxy, fat);
    } else {
      tree.move_proxy(records[i].proxy, fat);
    }
    // A static or kinematic body's second proxy moves with its first.
    if (records[i].fixed_proxy != AabbTree::null_node) broad.fixed_tree.move_proxy(records[i].fixed_proxy, fat);
  }
  if (refit) tree.refit_or_rebuild(refit_growth_allowed);

  find_new_pairs(step, broad, records, contacts);
  std::vector<std::uint64_t>& new_pairs = broad.new_pairs;
  // Contacts are created, and so solved, in the order of the moved body's index, then the other
  // body's, not in the order the tree happens to list them: the physics does not depend on how the
  // tree is built. (moved_bodies is ascending, so this sorts only within each body's finds.)
  std::sort(new_pairs.begin(), new_pairs.end());
  for (const std::uint64_t found : new_pairs) {
    const auto i = static_cast<std::uint32_t>(found >> 32);
    const auto j = static_cast<std::uint32_t>(found);
    create_contact(contacts, records, i < j ? i : j, i < j ? j : i);
  }
  for (const std::uint32_t i : moved_bodies) {
    records[i].moved = false;
    broad.proxy_moved[records[i].proxy] = 0;
  }
}

}  // namespace fx2d::detail
