// The scene behind FxScene: the bodies, the user constraints and what each stage of the step owns,
// private to World. The step (scene.cpp) builds a StepContext and hands each stage function
// only the parts it reads or writes (README.md here says which stage reads what).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>

#include "world/bodies.h"
#include "collision/broad_phase.h"
#include "collision/contact_cache.h"
#include "collision/continuous.h"
#include "collision/narrow_phase.h"
#include "fx2d/Constraint.h"
#include "fx2d/Entity.h"
#include "fx2d/Profile.h"
#include "fx2d/Scene.h"
#include "world/sleep.h"
#include "solver/solver_stages.h"
#include "world/tasks.h"

namespace fx2d::detail {

class World final {
 public:
  World(const FxSceneSettings& settings, FxScene& owner);
  ~World();

  // Entities (entity.cpp).
  std::shared_ptr<FxEntity> create_entity(const FxEntityDef& def);
  void remove_entity(std::uint32_t index);
  std::uint32_t index_of(const FxEntity& entity) const;
  void wake_body(std::uint32_t index) { detail::wake_body(bodies_, index); }
  // Recomputes a body's tight box after its pose was set from outside the step.
  void refresh_aabb(std::uint32_t index);
  const Bodies& bodies() const { return bodies_; }
  BodySim& sim(std::uint32_t index) { return bodies_.sims[index]; }

  // Constraints (entity.cpp).
  void add_constraint(std::shared_ptr<FxConstraint> constraint);
  void remove_constraint(const FxConstraint& constraint);
  std::size_t constraint_count() const { return constraints_.size(); }

  void step();
  void set_step_callback(std::function<void(FxScene&)> callback) { step_callback_ = std::move(callback); }

  const FxSceneSettings& settings() const { return settings_; }
  void set_settings(const FxSceneSettings& settings);
  const ContactCache& contacts() const { return contacts_; }
  const FxProfile& profile() const { return profile_; }
  std::uint64_t step_index() const { return step_index_; }

 private:
  // Grows per-step scratch with the body count, at creation, so a step allocates nothing.
  void reserve_scratch();

  FxSceneSettings settings_;
  FxScene& owner_;
  Bodies bodies_;
  Constraints constraints_;
  BroadPhase broad_phase_;
  ContactCache contacts_;
  NarrowPhaseScratch narrow_phase_;
  SolverData solver_;
  SleepScratch sleep_;
  ContinuousScratch continuous_;
  Tasks tasks_;

  std::function<void(FxScene&)> step_callback_;
  FxProfile profile_;
  std::uint64_t step_index_ = 0;
  float last_substep_dt_ = 0.0f;  // the h of the last step (StepContext::impulse_ratio), 0 before it
  bool stepping_ = false;
  std::size_t reserved_bodies_ = 0;
};

}  // namespace fx2d::detail
