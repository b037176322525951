// The step's threads: the default pool runs every item of every task once, a step gives the same
// bits on any worker count and under a user's scheduler that runs ranges in any order, and the
// settings that choose them are validated like the others.
#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "test_bodies.h"
#include "world/tasks.h"

namespace fx2d {
namespace {

using test::add_box;
using test::add_ground;

TEST(TaskPool, RunsEveryItemOfEveryTaskExactlyOnce) {
  for (const int workers : {2, 3, 8}) {
    detail::TaskPool pool(workers);
    const FxTaskScheduler scheduler = pool.scheduler();
    std::vector<std::atomic<int>> runs(1000);
    FxTaskFunction count_runs = [](std::uint32_t begin, std::uint32_t end, void* context) {
      auto& counts = *static_cast<std::vector<std::atomic<int>>*>(context);
      for (std::uint32_t i = begin; i < end; ++i) counts[i].fetch_add(1, std::memory_order_relaxed);
    };
    constexpr int tasks = 200;  // back to back, as a step's substeps post them
    for (int task = 0; task < tasks; ++task) {
      scheduler.wait(scheduler.enqueue(count_runs, static_cast<std::uint32_t>(runs.size()), &runs, scheduler.user_context),
                     scheduler.user_context);
    }
    for (std::size_t i = 0; i < runs.size(); ++i) ASSERT_EQ(runs[i].load(), tasks) << "item " << i << ", " << workers << " workers";
  }
}

// A scheduler of the user's: runs the ranges on the calling thread, last range first and in
// uneven sizes, to show that neither the order nor the split of the ranges changes a result.
struct BackwardsScheduler {
  int tasks_run = 0;

  static void* enqueue(FxTaskFunction task, std::uint32_t item_count, void* task_context, void* self) {
    std::uint32_t end = item_count;
    for (std::uint32_t size = 1; end > 0; size = size % 3 + 1) {
      const std::uint32_t begin = end > size ? end - size : 0;
      task(begin, end, task_context);
      end = begin;
    }
    ++static_cast<BackwardsScheduler*>(self)->tasks_run;
    return nullptr;
  }
  static void wait(void*, void*) {}
};

// Every entity's pose and velocity, in entity order.
std::vector<float> state_of(const FxScene& scene) {
  std::vector<float> state;
  for (std::uint32_t i = 0; i < scene.entity_count(); ++i) {
    const FxEntity& e = *scene.entity(i);
    for (const float value : {e.position().x, e.position().y, e.rotation().c, e.rotation().s, e.linear_velocity().x,
                              e.linear_velocity().y, e.angular_velocity()}) {
      state.push_back(value);
    }
  }
  return state;
}

// Columns of boxes fall asleep; a box of one column is removed early so that a later contact
// reuses its low slot; then boxes dropped onto columns wake them. A pair that wakes a body in the
// narrow phase makes the sleeping pairs after it active in the same step, which the parallel
// narrow phase must reproduce. 1200 boxes: past the thresholds of the narrow phase, the contact
// constraints and the body loops (the contact passes spread only from a colour of 256 batches:
// wide_colours_state() below).
std::vector<float> final_state(FxSceneSettings settings) {
  constexpr int columns = 100;
  constexpr int boxes_per_column = 12;
  constexpr float column_spacing = 1.5f;
  FxScene scene(settings);
  add_ground(scene, column_spacing * columns);
  std::vector<std::shared_ptr<FxEntity>> boxes;
  for (int column = 0; column < columns; ++column) {
    for (int level = 0; level < boxes_per_column; ++level) {
      boxes.push_back(add_box(scene, {column_spacing * static_cast<float>(column), 0.5f + static_cast<float>(level)}));
    }
  }
  scene.step();
  scene.remove_entity(*boxes[boxes_per_column - 1]);  // the top of column 0: frees its contact's slot
  for (int step = 0; step < 150; ++step) scene.step();  // 2.5 s: every column asleep
  for (int column = 10; column < columns; column += 10) {
    FxEntityDef def;
    def.shape = FxShape::box(0.5f, 0.5f);
    def.position = {column_spacing * static_cast<float>(column), boxes_per_column + 1.0f};
    def.linear_velocity = {0.0f, -10.0f};
    scene.create_entity(def);
  }
  for (int step = 0; step < 60; ++step) scene.step();
  return state_of(scene);
}

// 2100 columns of two boxes on the ground: two colours of 2100 contacts (263 batches each, past
// min_parallel_batches), every lane of the first sharing the static ground, so the contact passes
// spread colour by colour and their ranges all read the same static body.
std::vector<float> wide_colours_state(FxSceneSettings settings) {
  constexpr int columns = 2100;
  constexpr float column_spacing = 1.5f;
  FxScene scene(settings);
  add_ground(scene, column_spacing * columns);
  for (int column = 0; column < columns; ++column) {
    for (int level = 0; level < 2; ++level) {
      add_box(scene, {column_spacing * static_cast<float>(column), 0.5f + static_cast<float>(level)});
    }
  }
  for (int step = 0; step < 15; ++step) scene.step();
  return state_of(scene);
}

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

// A scene's final state at 2, 3 and 8 workers, each against one worker's.
void expect_same_bits_on_every_worker_count(std::vector<float> (*scene_state)(FxSceneSettings)) {
  const std::vector<float> serial = scene_state({});
  for (const int workers : {2, 3, 8}) {
    FxSceneSettings settings;
    settings.workers = workers;
    EXPECT_TRUE(same_bits(scene_state(settings), serial)) << workers << " workers";
  }
}

TEST(Threads, WakingColumnsEndInTheSameBitsOnEveryWorkerCount) { expect_same_bits_on_every_worker_count(&final_state); }

TEST(Threads, WideColoursSpreadOverWorkersEndInTheSameBitsOnEveryWorkerCount) {
  expect_same_bits_on_every_worker_count(&wide_colours_state);
}

// Boxes dropped in columns of two onto the ground, bouncing: contacts begin as they land and stop as
// they rebound, among 400 pairs, more than the narrow phase collides on one thread. Each pair says
// whether it began or stopped touching, and the serial pass keeps the count from that alone: the
// count must be the touching contacts after every step, on one worker and on two.
TEST(Threads, TheTouchingCountFollowsContactsThatBeginAndStopOnEveryWorkerCount) {
  constexpr int columns = 200;
  constexpr float column_spacing = 1.5f;
  FxMaterial bouncy;
  bouncy.restitution = 0.8f;
  for (const int workers : {1, 2}) {
    FxSceneSettings settings;
    settings.workers = workers;
    FxScene scene(settings);
    add_ground(scene, column_spacing * columns, 0.0f, bouncy);
    for (int column = 0; column < columns; ++column) {
      for (const float height : {1.5f, 3.5f}) {
        add_box(scene, {column_spacing * static_cast<float>(column), height}, 0.5f, bouncy);
      }
    }
    std::vector<FxContact> touching;
    int rises = 0;
    int falls = 0;
    int previous = 0;
    for (int step = 0; step < 120; ++step) {
      scene.step();
      scene.contacts(touching);
      ASSERT_EQ(scene.contact_count(), static_cast<int>(touching.size())) << "step " << step << ", " << workers << " workers";
      rises += scene.contact_count() > previous;
      falls += scene.contact_count() < previous;
      previous = scene.contact_count();
    }
    EXPECT_GT(rises, 0) << "no contact began";
    EXPECT_GT(falls, 0) << "no contact stopped";
  }
}

TEST(Threads, AUsersSchedulerRunningRangesBackwardsGivesTheSameBits) {
  BackwardsScheduler backwards;
  FxSceneSettings settings;
  settings.workers = 2;
  settings.scheduler = {&BackwardsScheduler::enqueue, &BackwardsScheduler::wait, &backwards};
  EXPECT_TRUE(same_bits(final_state(settings), final_state({})));
  EXPECT_TRUE(same_bits(wide_colours_state(settings), wide_colours_state({})));
  EXPECT_GT(backwards.tasks_run, 0) << "the scene never used the user's scheduler";
}

TEST(Threads, OneWorkerNeverCallsTheScheduler) {
  BackwardsScheduler backwards;
  FxSceneSettings settings;
  settings.scheduler = {&BackwardsScheduler::enqueue, &BackwardsScheduler::wait, &backwards};
  final_state(settings);
  EXPECT_EQ(backwards.tasks_run, 0);
}

std::string settings_error(const FxSceneSettings& settings) {
  try {
    FxScene scene(settings);
  } catch (const FxInvalidArgument& e) {
    return e.what();
  }
  return "";
}

TEST(Threads, SettingsNameTheFieldOutOfRange) {
  FxSceneSettings none;
  none.workers = 0;
  EXPECT_EQ(settings_error(none), "FxSceneSettings: workers: expected an integer in [1, 64]");
  FxSceneSettings half;
  half.scheduler.enqueue = &BackwardsScheduler::enqueue;
  EXPECT_EQ(settings_error(half), "FxSceneSettings: scheduler: expected both enqueue and wait, or neither");
}

}  // namespace
}  // namespace fx2d
