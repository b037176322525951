// Sleeping: an island (dynamic bodies connected by touching contacts or constraints) sleeps as a
// whole once every body in it has rested for time_to_sleep; a body alone in the air never rests.
// Such an island is a group of rested bodies joined by links among themselves with no link to an
// awake body that has not rested: with one, the island holds that body; without, the group is
// the whole island. So islands are found afresh, in each step in which some body has rested that
// long, with a union-find over the links between rested bodies alone, whose roots are the lowest
// packed index of each group, and the groups an unrested body touches stay awake. The result
// depends only on the state, not on history.
// A sleeping body remembers its island's root in sleep_island; waking one wakes them all.
#include "world/sleep.h"

#include <algorithm>

#include "world/step_context.h"

namespace fx2d::detail {
namespace {

int find_root(std::vector<int>& parent, int i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

void unite(std::vector<int>& parent, int a, int b) {
  const int ra = find_root(parent, a);
  const int rb = find_root(parent, b);
  if (ra < rb) parent[rb] = ra; else parent[ra] = rb;
}

// What a body is to the islands: not in one (static, kinematic or asleep), awake and dynamic but
// not rested for time_to_sleep, or rested.
enum RestClass : std::uint8_t { outside, unrested, rested };

// The class of an awake body that moves (one of the stage's `moving`).
RestClass rest_class_of(const BodyRecord& record, float time_to_sleep) {
  if (record.type != FxBodyType::dynamic) return outside;
  return record.sleep_time >= time_to_sleep ? rested : unrested;
}

}  // namespace

void SleepScratch::reserve(std::size_t bodies) {
  island_parent.reserve(bodies);
  rest_class.reserve(bodies);
  held_awake.reserve(bodies);
}

void update_sleep(const StepContext& step, SleepScratch& scratch, Bodies& bodies,
                  std::span<const ConstraintSource> touching, const Constraints& constraints,
                  std::span<const std::uint32_t> moving) {
  const FxSceneSettings& settings = step.settings;
  if (!settings.sleeping) return;
  std::vector<BodyRecord>& records = bodies.records;
  // An island sleeps once every body in it has rested time_to_sleep: while no body has, none can,
  // and the islands are not worth finding. So it is in most steps of a scene still settling.
  const bool any_rested = std::any_of(moving.begin(), moving.end(), [&](std::uint32_t i) {
    return rest_class_of(records[i], settings.time_to_sleep) == rested;
  });
  if (!any_rested) return;
  std::vector<int>& island_parent = scratch.island_parent;
  std::vector<std::uint8_t>& rest_class = scratch.rest_class;
  std::vector<std::uint8_t>& held_awake = scratch.held_awake;
  // Only awake dynamic bodies, all of them in `moving`, join islands, so only their entries are
  // set beyond the class: a sleeping island costs nothing here.
  island_parent.resize(records.size());
  held_awake.resize(records.size());
  rest_class.assign(records.size(), outside);
  for (const std::uint32_t i : moving) {
    rest_class[i] = rest_class_of(records[i], settings.time_to_sleep);
    if (rest_class[i] == outside) continue;
    island_parent[i] = static_cast<int>(i);
    held_awake[i] = 0;
  }

  // The step's contact constraints are the touching contacts with an awake body (prepare_solver),
  // in a compact list: walking it, rather than every cached contact or the awake bodies' contact
  // lists, finds the same groups (each root is its group's lowest index, whatever the order). A
  // link between two unrested bodies decides nothing: a union-find over every link, theirs too,
  // made the stage take 2.7 times as long on settling_boxes 800 and 3 times on pile 800 (`ab`,
  // sleeping on), bound by its own instructions rather than by the records it read.
  for_each_link(touching, constraints, [&](std::uint32_t a, std::uint32_t b) {
    const std::uint8_t class_a = rest_class[a], class_b = rest_class[b];
    if (class_a == rested && class_b == rested) {
      unite(island_parent, static_cast<int>(a), static_cast<int>(b));
    } else if (class_a == rested && class_b == unrested) {
      held_awake[a] = 1;
    } else if (class_b == rested && class_a == unrested) {
      held_awake[b] = 1;
    }
  });

  // A rested body an unrested one touches holds its whole group awake: marked on the group's root.
  for (const std::uint32_t i : moving) {
    if (rest_class[i] == rested && held_awake[i] != 0)
      held_awake[find_root(island_parent, static_cast<int>(i))] = 1;
  }
  for (const std::uint32_t i : moving) {
    if (rest_class[i] != rested) continue;
    const int root = find_root(island_parent, static_cast<int>(i));
    if (held_awake[root] != 0) continue;
    BodyRecord& record = records[i];
    record.awake = false;
    --bodies.awake_count;
    record.sleep_island = root;
    bodies.sims[i].linear_velocity = {};
    bodies.sims[i].angular_velocity = 0.0f;
  }
}

void wake_body(Bodies& bodies, std::uint32_t index) {
  const BodyRecord& target = bodies.records[index];
  if (target.awake || target.type == FxBodyType::static_body) return;
  const int island = target.sleep_island;
  for (BodyRecord& record : bodies.records) {
    if (record.awake || record.sleep_island != island) continue;
    record.awake = true;
    ++bodies.awake_count;
    record.sleep_time = 0.0f;
    record.sleep_island = -1;
  }
}

}  // namespace fx2d::detail
