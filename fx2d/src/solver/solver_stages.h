// The solver's stages of a step, in order (solver_stages.cpp): gather the bodies' hot state and
// build the contact constraints; colour and pack them into batches; per substep integrate
// velocities, warm start, solve, integrate positions, relax; then restitution, the position
// projection, the write-back of poses and the storage of impulses for the next step.
//
// SolverData is what these stages own. `states` is the hot 32-byte record of each body the velocity
// passes touch, gathered once per step, with one extra, always-zero slot that padding lanes of
// contact batches and body groups point at.
#pragma once

#include <cstdint>
#include <vector>

#include "collision/broad_phase.h"
#include "collision/contact_cache.h"
#include "solver/body_integration.h"
#include "solver/contact_batch.h"
#include "solver/contact_graph.h"
#include "solver/contact_solver.h"
#include "solver/joint_rows.h"
#include "solver/step_schedule.h"
#include "world/bodies.h"

namespace fx2d::detail {

struct StepContext;

struct SolverData {
  std::vector<FxBodyState> states;
  BodyIntegration integration;        // the awake moving bodies, for the substep loops
  ContactSolver contact_solver;
  ContactGraph contact_graph;
  ContactBatches contact_batches;
  JointRows joint_rows;               // the user constraints (joints), for the substeps' passes
  SupportChains support_chains;       // prepare_solver's scratch for the shallow schedule
  // What the last step found of its support chains, for a step whose contacts are the same: the
  // depth it asked about (-1 when it did not look) and whether every chain was within it.
  struct ChainsFound {
    int depth = -1;
    bool within = false;
  } chains_found;
  PassCounts passes;                  // chosen by prepare_solver
  // Whether every awake body has rested (FxSceneSettings::rest_schedule): set by prepare_solver.
  bool at_rest = false;
  // Set by colour_and_pack: the substeps measure the separations once, at the step's start
  // (step_schedule.h's resting_rebound says when).
  bool separations_once = false;

  void reserve(std::size_t bodies);
};

// Stage prepare: gathers the bodies' hot state, lists one constraint per touching contact with an
// awake body and chooses the step's passes (step_schedule.h).
void prepare_solver(const StepContext& step, SolverData& solver, const Bodies& bodies,
                    const ContactCache& contacts, const Constraints& constraints);
// Stage colour_and_pack: colours the contact constraints, builds each from its contact and bodies
// into its lane of the batches and works out their separations at the step's start.
void colour_and_pack(const StepContext& step, SolverData& solver, const Bodies& bodies, const ContactCache& contacts);
// The substeps, each stage timed as its own FxStage: integrate, warm start, solve, integrate,
// relax; user constraints (joints) are solved in the same passes, contacts last.
void solve_substeps(const StepContext& step, SolverData& solver, const Bodies& bodies, const Constraints& constraints);
// Stage restitution: bounce where an approaching point pushed and restitution is > 0.
void apply_restitution(const StepContext& step, SolverData& solver);
// Stage position_solve: projects what overlap remains deeper than the slop.
void solve_positions(const StepContext& step, SolverData& solver);
// Stage integrate (its end): writes poses and velocities back to the bodies, with carries, counts
// their rest times, clears their forces and refreshes their boxes.
void finalize_bodies(const StepContext& step, const SolverData& solver, Bodies& bodies, const BroadPhase& broad);
// Stage store: keeps each point's impulses in the contact cache for the next step's warm start.
void store_impulses(const SolverData& solver, ContactCache& contacts);

}  // namespace fx2d::detail
