// Sleeping: resting islands sleep as a whole and wake on a hit, a push, or a removed neighbour.
#include <gtest/gtest.h>

#include <vector>

#include "test_bodies.h"

namespace fx2d {
namespace {

using test::add_box;
using test::add_circle;
using test::add_ground;
using test::run;

std::vector<std::shared_ptr<FxEntity>> build_stack(FxScene& scene, int height) {
  add_ground(scene);
  std::vector<std::shared_ptr<FxEntity>> boxes;
  for (int i = 0; i < height; ++i) boxes.push_back(add_box(scene, {0.0f, 0.5f + static_cast<float>(i)}));
  return boxes;
}

bool all_asleep(const std::vector<std::shared_ptr<FxEntity>>& bodies) {
  for (const auto& body : bodies) {
    if (body->is_awake()) return false;
  }
  return true;
}

TEST(Sleep, RestingStackFallsAsleepAfterTimeToSleep) {
  FxScene scene;
  auto boxes = build_stack(scene, 5);
  run(scene, 0.25f);
  EXPECT_FALSE(all_asleep(boxes));  // time_to_sleep is 0.5 s
  run(scene, 1.0f);
  EXPECT_TRUE(all_asleep(boxes));
}

TEST(Sleep, FallingBodyNeverSleeps) {
  FxScene scene;
  auto ball = add_circle(scene, {0.0f, 1000.0f});
  run(scene, 2.0f);
  EXPECT_TRUE(ball->is_awake());
}

TEST(Sleep, SleepingStackWakesWhenHit) {
  FxScene scene;
  auto boxes = build_stack(scene, 5);
  run(scene, 2.0f);
  ASSERT_TRUE(all_asleep(boxes));
  auto ball = add_circle(scene, {-6.0f, 4.5f}, 0.25f, FxMaterial{5.0f});
  ball->set_linear_velocity({20.0f, 0.0f});
  run(scene, 0.5f);
  EXPECT_TRUE(boxes[4]->is_awake());
  EXPECT_GT(std::fabs(boxes[4]->position().x), 0.01f);  // the hit moved the top box
}

TEST(Sleep, PushWakesTheWholeIsland) {
  FxScene scene;
  auto boxes = build_stack(scene, 3);
  run(scene, 2.0f);
  ASSERT_TRUE(all_asleep(boxes));
  boxes[2]->apply_linear_impulse({0.1f, 0.0f}, boxes[2]->world_center());
  for (const auto& box : boxes) EXPECT_TRUE(box->is_awake());
}

TEST(Sleep, RemovingASupportWakesWhatRestedOnIt) {
  FxScene scene;
  auto boxes = build_stack(scene, 3);
  run(scene, 2.0f);
  ASSERT_TRUE(all_asleep(boxes));
  scene.remove_entity(*boxes[0]);
  EXPECT_TRUE(boxes[1]->is_awake());
  run(scene, 1.0f);
  EXPECT_NEAR(boxes[1]->position().y, 0.5f, 0.01f);  // it fell onto the ground
}

// A box that slides from rest more slowly than linear_sleep_speed / time_to_sleep (0.1 m/s^2) is
// slower than the sleep speed for the whole of time_to_sleep; speed alone put it to sleep at 0.5 s,
// 9 mm down a slope it slides 14 cm down in 2 s (stability's friction_ramp, at 66.5 degrees). It
// speeds up all the while, so it is not resting.
TEST(Sleep, ABoxThatSpeedsUpSlowlyKeepsSliding) {
  const float slide_acceleration = 0.07f;  // m/s^2, between the 0.05 that may sleep and the old 0.1
  FxSceneSettings settings;
  const float friction = FxMaterial{}.dynamic_friction;  // box and ground alike
  settings.gravity = {friction * 10.0f + slide_acceleration, -10.0f};
  FxScene scene(settings);
  add_ground(scene);
  auto box = add_box(scene, {0.0f, 0.5f});
  const float seconds = 2.0f;
  run(scene, seconds);
  EXPECT_TRUE(box->is_awake());
  const float coulomb_slide = 0.5f * slide_acceleration * seconds * seconds;  // 14 cm
  EXPECT_NEAR(box->position().x, coulomb_slide, 0.1f * coulomb_slide);
}

TEST(Sleep, DisabledSleepingKeepsEveryBodyAwake) {
  FxSceneSettings settings;
  settings.sleeping = false;
  FxScene scene(settings);
  auto boxes = build_stack(scene, 3);
  run(scene, 2.0f);
  for (const auto& box : boxes) EXPECT_TRUE(box->is_awake());
}

}  // namespace
}  // namespace fx2d
