// The scene as a registry and an API: packed indices, removal at any time (also from the step
// callback), handles that outlive removal and the scene, validation that names the field, the
// profile's timer per stage, and determinism within a process.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "test_bodies.h"

namespace fx2d {
namespace {

using test::add_box;
using test::add_circle;
using test::add_ground;
using test::run;

template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const FxInvalidArgument& e) {
    return e.what();
  }
  return "";
}

TEST(Registry, PackedIndicesFollowCreationOrderAndCloseGapsOnRemoval) {
  FxScene scene;
  auto a = add_circle(scene, {0.0f, 0.0f});
  auto b = add_circle(scene, {2.0f, 0.0f});
  auto c = add_circle(scene, {4.0f, 0.0f});
  EXPECT_EQ(a->packed_index(), 0u);
  EXPECT_EQ(c->packed_index(), 2u);
  scene.remove_entity(*b);
  EXPECT_EQ(scene.entity_count(), 2u);
  EXPECT_EQ(c->packed_index(), 1u);
  EXPECT_EQ(scene.entity(1).get(), c.get());
  EXPECT_FALSE(b->in_scene());
  EXPECT_NEAR(b->position().x, 2.0f, 1e-6f);  // a detached handle reports its last pose
}

TEST(Registry, EntitiesCanBeAddedAndRemovedFromTheStepCallback) {
  FxScene scene;
  add_ground(scene);
  std::vector<std::shared_ptr<FxEntity>> spawned;
  scene.set_step_callback([&](FxScene& s) {
    if (s.step_index() % 10 == 0) spawned.push_back(add_box(s, {0.0f, 5.0f}));
    if (spawned.size() > 3) {
      s.remove_entity(*spawned.front());
      spawned.erase(spawned.begin());
    }
  });
  run(scene, 2.0f);
  EXPECT_EQ(spawned.size(), 3u);
  EXPECT_EQ(scene.entity_count(), 4u);
  for (const auto& box : spawned) {
    EXPECT_TRUE(box->in_scene());
    EXPECT_TRUE(std::isfinite(box->position().y));
  }
}

TEST(Registry, RemovedEntityTakesItsContactsAndConstraintsWithIt) {
  FxScene scene;
  add_ground(scene);
  auto a = add_box(scene, {0.0f, 0.5f});
  auto b = add_box(scene, {0.0f, 1.5f});
  scene.add_constraint(std::make_shared<FxDistanceJoint>(a, b, FxVec2f{}, FxVec2f{}));
  run(scene, 0.1f);
  EXPECT_EQ(scene.contact_count(), 1);  // a on the ground; jointed a and b never collide
  scene.remove_entity(*a);
  EXPECT_EQ(scene.constraint_count(), 0u);
  EXPECT_EQ(scene.contact_count(), 0);
  run(scene, 1.0f);
  EXPECT_NEAR(b->position().y, 0.5f, 0.01f);
  EXPECT_EQ(scene.contact_count(), 1);
}

TEST(Registry, HandlesOutliveTheScene) {
  std::shared_ptr<FxEntity> survivor;
  {
    FxScene scene;
    survivor = add_circle(scene, {1.0f, 2.0f});
    run(scene, 0.1f);
  }
  EXPECT_FALSE(survivor->in_scene());
  EXPECT_LT(survivor->position().y, 2.0f);
  EXPECT_THROW(survivor->set_linear_velocity({1.0f, 0.0f}), FxInvalidArgument);
}

TEST(Profile, EveryStageFunctionOfAStepWithContactsAndAJointIsTimed) {
  if (!fx_profiling_enabled()) GTEST_SKIP() << "built without FX2D_PROFILE: the profile stays zero";
  FxSceneSettings settings;
  settings.sleeping = false;  // every stage has work in every step
  FxScene scene(settings);
  add_ground(scene);
  const auto lower = add_box(scene, {0.0f, 0.5f});
  const auto upper = add_box(scene, {0.0f, 1.5f});
  scene.add_constraint(std::make_shared<FxRevoluteJoint>(lower, upper, FxVec2f{0.0f, 1.0f}));
  // The counter is read where the step changes stage, so a stage the step never switches to
  // keeps zero cycles; and the stages together never exceed the step that holds them. Summed
  // over steps, because a coarse counter (aarch64's virtual counter ticks every 16 ns at
  // 62.5 MHz) can read no tick across one short stage of one step.
  std::vector<std::uint64_t> cycles(fx_stage_count, 0);
  std::uint64_t stages = 0;
  std::uint64_t steps = 0;
  for (int step = 0; step < 60; ++step) {
    scene.step();
    const FxProfile& profile = scene.profile();
    for (int i = 0; i < fx_stage_count; ++i) {
      cycles[static_cast<std::size_t>(i)] += profile.cycles(static_cast<FxStage>(i));
      stages += profile.cycles(static_cast<FxStage>(i));
    }
    steps += profile.step_cycles;
  }
  for (int i = 0; i < fx_stage_count; ++i)
    EXPECT_GT(cycles[static_cast<std::size_t>(i)], 0u) << stage_name(static_cast<FxStage>(i));
  EXPECT_LE(stages, steps);
}

TEST(Validation, SceneSettingsNameTheBadField) {
  FxSceneSettings s;
  s.dt = 0.0f;
  EXPECT_NE(error_of([&] { FxScene scene(s); }).find("dt"), std::string::npos);
  s = {};
  s.substeps = 0;
  EXPECT_NE(error_of([&] { FxScene scene(s); }).find("substeps"), std::string::npos);
  s = {};
  s.gravity.y = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NE(error_of([&] { FxScene scene(s); }).find("gravity"), std::string::npos);
  // Found by the engine fuzzer: finite but huge values overflowed the soft-constraint
  // coefficients into inf * 0 = NaN on the first step.
  s = {};
  s.contact_damping_ratio = 3.0e38f;
  EXPECT_NE(error_of([&] { FxScene scene(s); }).find("contact_damping_ratio"), std::string::npos);
  s = {};
  s.joint_damping_ratio = 1.0e30f;
  EXPECT_NE(error_of([&] { FxScene scene(s); }).find("joint_damping_ratio"), std::string::npos);
  s = {};
  s.dt = 1.0e30f;
  EXPECT_NE(error_of([&] { FxScene scene(s); }).find("dt"), std::string::npos);
  s = {};
  s.dt = 1.0e-40f;  // positive, but the substep dt / substeps would underflow to 0
  EXPECT_NE(error_of([&] { FxScene scene(s); }).find("dt"), std::string::npos);
  s = {};
  s.rest_schedule_time = -1.0f;
  EXPECT_NE(error_of([&] { FxScene scene(s); }).find("rest_schedule_time"), std::string::npos);
  s = {};
  s.shallow_schedule_depth = -1;
  EXPECT_NE(error_of([&] { FxScene scene(s); }).find("shallow_schedule_depth"), std::string::npos);
  s = {};
  s.shallow_schedule_speed = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NE(error_of([&] { FxScene scene(s); }).find("shallow_schedule_speed"), std::string::npos);
  s = {};
  s.impact_schedule_travel = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NE(error_of([&] { FxScene scene(s); }).find("impact_schedule_travel"), std::string::npos);
  s = {};
  s.impact_velocity_passes = 0;
  EXPECT_NE(error_of([&] { FxScene scene(s); }).find("impact_velocity_passes"), std::string::npos);
  s = {};
  s.joint_relax_passes = 0;
  EXPECT_NE(error_of([&] { FxScene scene(s); }).find("joint_relax_passes"), std::string::npos);
}

TEST(Validation, EntityDefinitionsNameTheBadField) {
  FxScene scene;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  auto expect_field = [&](FxEntityDef def, const char* field) {
    const std::string message = error_of([&] { scene.create_entity(def); });
    EXPECT_NE(message.find(field), std::string::npos) << "message: '" << message << "'";
  };
  FxEntityDef def;
  def.position.x = nan;
  expect_field(def, "position");
  def = {};
  def.linear_velocity.y = inf;
  expect_field(def, "linear_velocity");
  def = {};
  def.angle = nan;
  expect_field(def, "angle");
  def = {};
  def.material.density = 0.0f;
  expect_field(def, "density");
  def = {};
  def.material.static_friction = -0.1f;
  expect_field(def, "static_friction");
  def = {};
  def.material.dynamic_friction = -0.1f;
  expect_field(def, "dynamic_friction");
  def = {};
  def.material.restitution = 1.5f;
  expect_field(def, "restitution");
  def = {};
  def.linear_damping = -1.0f;
  expect_field(def, "linear_damping");
  def = {};
  def.material.density = 1.0e-40f;  // positive, but its mass has no finite inverse
  expect_field(def, "density");
  def = {};
  def.material.density = 1.0e-36f;  // a normal float, but a mass of 1e-36 kg overflows the solver
  expect_field(def, "density");
  def = {};
  def.material.density = 1.0e36f;
  expect_field(def, "density");
  def = {};
  def.position = {2.0e7f, 0.0f};
  expect_field(def, "position");
  def = {};
  def.linear_velocity = {1.5f * scene.settings().max_linear_speed, 0.0f};
  expect_field(def, "linear_velocity");
  def = {};
  def.angular_velocity = 1.0e20f;
  expect_field(def, "angular_velocity");
  EXPECT_EQ(scene.entity_count(), 0u);  // nothing half-created
  def = {};
  def.type = FxBodyType::static_body;
  def.material.density = 0.0f;  // a static body needs no density
  EXPECT_NO_THROW(scene.create_entity(def));
}

TEST(Robustness, HugePushesAreClampedNotOverflowed) {
  // Found by the engine fuzzer: a finite impulse of 3e38 made the velocity infinite.
  FxScene scene;
  auto box = add_box(scene, {0.0f, 0.0f});
  box->apply_linear_impulse({3.0e38f, 3.0e38f}, {1.0e6f, 0.0f});
  EXPECT_TRUE(is_finite(box->linear_velocity()));
  EXPECT_NEAR(length(box->linear_velocity()), scene.settings().max_linear_speed, 1e-3f);
  EXPECT_TRUE(std::isfinite(box->angular_velocity()));
  run(scene, 0.5f);
  EXPECT_TRUE(is_finite(box->position()));
  EXPECT_TRUE(std::isfinite(box->angle()));
}

TEST(Robustness, StepNeverProducesNaNFromExtremeButValidInput) {
  FxScene scene;
  add_ground(scene);
  FxEntityDef thin;
  thin.shape = FxShape::box(2.0f, 0.001f);
  thin.position = {0.0f, 1.0f};
  auto sliver = scene.create_entity(thin);
  sliver->set_linear_velocity({0.0f, -2.0f * scene.settings().max_linear_speed});  // clamped to max_linear_speed
  EXPECT_FLOAT_EQ(length(sliver->linear_velocity()), scene.settings().max_linear_speed);
  auto tiny = add_circle(scene, {0.0f, 0.5f}, 0.001f);
  auto dense = add_box(scene, {0.2f, 3.0f}, 0.5f, FxMaterial{1.0e6f});
  std::vector<std::shared_ptr<FxEntity>> heap;
  for (int i = 0; i < 50; ++i) heap.push_back(add_box(scene, {5.0f, 2.0f}, 0.5f));  // all in one spot
  run(scene, 2.0f);
  for (const auto& e : {sliver, tiny, dense}) {
    EXPECT_TRUE(is_finite(e->position()));
    EXPECT_TRUE(is_finite(e->linear_velocity()));
  }
  for (const auto& e : heap) EXPECT_TRUE(is_finite(e->position()));
}

TEST(Robustness, ForceThatOverflowsTheAccelerationIsClamped) {
  // Found by the engine fuzzer: 3e38 N on a light body made inv_mass * force infinite, then NaN.
  FxScene scene;
  auto box = add_box(scene, {0.0f, 0.0f}, 0.05f);
  box->apply_force({3.0e38f, -3.0e38f});
  scene.step();
  EXPECT_TRUE(is_finite(box->position()));
  EXPECT_NEAR(length(box->linear_velocity()), scene.settings().max_linear_speed, 1e-2f);
  EXPECT_GT(box->linear_velocity().x, 0.0f);  // the direction of the force survives
  EXPECT_LT(box->linear_velocity().y, 0.0f);
}

TEST(Robustness, ABodyOverTheSpeedLimitSlowsNoOtherBody) {
  // Bodies are integrated eight at a time and the rare one over the limit is slowed on its own:
  // its neighbours in the group must move exactly as they do without it.
  auto falling_boxes = [](FxScene& scene) {
    std::vector<std::shared_ptr<FxEntity>> boxes;
    for (int i = 0; i < 11; ++i) boxes.push_back(add_box(scene, {3.0f * static_cast<float>(i), 0.0f}));
    return boxes;
  };
  FxScene alone;
  const auto reference = falling_boxes(alone);
  FxScene with_fast_one;
  const auto boxes = falling_boxes(with_fast_one);
  auto fast = add_box(with_fast_one, {0.0f, 50.0f}, 0.05f);
  fast->apply_force({3.0e38f, -3.0e38f});
  alone.step();
  with_fast_one.step();
  EXPECT_NEAR(length(fast->linear_velocity()), with_fast_one.settings().max_linear_speed, 1e-2f);
  const float free_fall_speed = -10.0f * alone.settings().dt;  // gravity (0, -10) for one step
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    EXPECT_NEAR(reference[i]->linear_velocity().y, free_fall_speed, 1e-5f) << "box " << i;
    EXPECT_EQ(boxes[i]->linear_velocity().y, reference[i]->linear_velocity().y) << "box " << i;
    EXPECT_EQ(boxes[i]->position().y, reference[i]->position().y) << "box " << i;
  }
}

TEST(Robustness, PinFarFromALightBodyStaysFinite) {
  // Found by the engine fuzzer: a pin 1e7 m from a light body makes the 2x2 effective-mass
  // matrix overflow float (det ~ 1e43), and its inverse filled the velocities with NaN. Such a
  // joint cannot be solved in float; it must do nothing rather than poison the scene.
  FxScene scene;
  add_ground(scene);
  auto speck = add_box(scene, {0.0f, 0.01f}, 0.01f);
  auto crate = add_box(scene, {3.0f, 0.5f});
  scene.add_constraint(std::make_shared<FxRevoluteJoint>(crate, speck, FxVec2f{1.0e7f, 0.0f}));
  run(scene, 1.0f);
  for (const auto& body : {speck, crate}) {
    EXPECT_TRUE(is_finite(body->position()));
    EXPECT_TRUE(is_finite(body->linear_velocity()));
    EXPECT_TRUE(std::isfinite(body->angular_velocity()));
  }
}

TEST(Validation, JointAnchorsBeyondTheWorldAreRefused) {
  FxScene scene;
  auto a = add_box(scene, {0.0f, 0.0f});
  auto b = add_box(scene, {2.0f, 0.0f});
  EXPECT_THROW(FxRevoluteJoint(a, b, {3.0e38f, 0.0f}), FxInvalidArgument);
  EXPECT_THROW(FxDistanceJoint(a, b, {0.0f, 2.0e7f}, {}, 1.0f), FxInvalidArgument);
  EXPECT_THROW(FxDistanceJoint(a, b, {}, {}, 1.0e30f), FxInvalidArgument);
  EXPECT_NO_THROW(FxDistanceJoint(a, b, {0.0f, 1.0e6f}, {}, 1.0e6f));
}

// Exact bit patterns of every pose, so "equal" means bit-identical.
std::vector<std::uint32_t> pose_bits(const FxScene& scene) {
  std::vector<std::uint32_t> bits;
  for (std::uint32_t i = 0; i < scene.entity_count(); ++i) {
    const auto& e = scene.entity(i);
    for (float v : {e->position().x, e->position().y, e->rotation().c, e->rotation().s, e->linear_velocity().x,
                    e->linear_velocity().y, e->angular_velocity()}) {
      std::uint32_t b;
      std::memcpy(&b, &v, sizeof b);
      bits.push_back(b);
    }
  }
  return bits;
}

std::vector<std::uint32_t> run_tumbling_scene() {
  FxScene scene;
  add_ground(scene);
  for (int i = 0; i < 60; ++i) {
    const float x = static_cast<float>(i % 6) * 1.1f - 3.0f;
    const float y = 1.0f + 1.2f * static_cast<float>(i / 6);
    if (i % 2 == 0) {
      add_box(scene, {x, y}, 0.5f, {}, 0.1f * static_cast<float>(i % 5));
    } else {
      add_circle(scene, {x, y}, 0.45f);
    }
  }
  run(scene, 3.0f);
  return pose_bits(scene);
}

TEST(Determinism, TwoRunsInOneProcessAgreeToTheBit) {
  EXPECT_EQ(run_tumbling_scene(), run_tumbling_scene());
}

}  // namespace
}  // namespace fx2d

namespace fx2d {
namespace {

// Rows 0.9 m apart, so each row starts sunk 0.1 m into the one below (the lowest 0.05 m into the
// ground): the push of deep overlaps runs from the first step, as the velocity passes do.
std::vector<std::uint32_t> run_tumbling_scene_with(bool force_scalar) {
  FxSceneSettings settings;
  settings.force_scalar_solver = force_scalar;
  FxScene scene(settings);
  add_ground(scene);
  for (int i = 0; i < 120; ++i) {
    const float x = static_cast<float>(i % 10) * 1.05f - 5.0f;
    const float y = 0.45f + 0.9f * static_cast<float>(i / 10);
    if (i % 3 == 0) {
      add_circle(scene, {x, y}, 0.5f);
    } else {
      add_box(scene, {x, y}, 0.5f, {}, 0.05f * static_cast<float>(i % 7));
    }
  }
  run(scene, 3.0f);
  return pose_bits(scene);
}

TEST(Determinism, BatchedSolverAgreesWithItsScalarTwinToTheBit) {
  // Lanes of a batch share no movable body and run the same arithmetic as the scalar path, so
  // vectorising changes nothing but speed.
  EXPECT_EQ(run_tumbling_scene_with(false), run_tumbling_scene_with(true));
}

}  // namespace
}  // namespace fx2d
