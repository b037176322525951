// The simulation: entities, their contacts and constraints, advanced one fixed step at a time.
//
// A step runs a fixed sequence of stages (see Profile.h): broad phase and narrow phase once per
// step, then `substeps` substeps of velocity integration, `velocity_passes` soft sequential-impulse
// passes over contacts and constraints, position integration and `relax_passes` relaxation passes; then
// restitution, a final position projection, pose finalisation and sleeping. Same scene, same
// settings, same calls: bit-identical state, run to run and process to process.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "fx2d/Constraint.h"
#include "fx2d/Contact.h"
#include "fx2d/Entity.h"
#include "fx2d/Math.h"
#include "fx2d/Profile.h"
#include "fx2d/Tasks.h"

namespace fx2d {

struct FxSceneSettings {
  FxVec2f gravity{0.0f, -10.0f};       // m/s^2
  float dt = 1.0f / 60.0f;             // seconds per step, in [1e-6, 1]
  // The schedule: 8 substeps x (1 soft pass + 3 rigid passes), 32 sweeps over the contacts, where
  // the seeds' 14 x (4 + 4) made 112 and 12 x (2 + 2) 48 (issue 19); a step of hard impacts takes a
  // second soft pass (the impact schedule below). The stability suite and the piles set the floor.
  // A third rigid pass keeps a box landing flat at 1000 m/s out of a thin floor (8 x 2 x 2 lets a
  // 10 cm box through it, continuous_test, and holds a stack of 105 boxes; 8 x 1 x 3 the floor and
  // 125, 8 x 2 x 3 115, the points' order alternating by substep as contact_batch.h says); fewer
  // substeps lose the piles (7 x 2 x 3: 20 of 41 pile 1200 runs over its 15 mm ceiling against 2,
  // pile 600's median peak penetration 4.95 -> 5.54 mm; with the stiffness cap raised to keep
  // 120 Hz at 7, still 4 of 21, and a heavy box then slides off a light one) and then the stacks
  // (6 x 2 x 3: 90 boxes, target 100; 7 x 1 x 3 holds vertical_stack 111, mass_ratio 1.02e3 and
  // chain_load 724, against 125, 1.22e3 and 939). A second soft pass in every step holds no stability
  // boundary further (mass ratio 1.22e3 either way, since the shallow schedule took the calm
  // steps) and costs a sweep: 8 x 2 x 3 took 1.05-1.09 times 8 x 1 x 3's step on pile 600 and
  // 1200 and settling_boxes 3000 (1.03 on settling_boxes 800, 1.00 on the stacks, pile 300 and
  // settling_boxes 200, sleeping off), with deeper median peak penetrations on pile 1200 (12.1
  // against 9.8 mm) and settling_boxes 3000 (55.4 against 46.4 mm), shallower on pile 300 (2.1
  // against 2.8), settling_boxes 200 (1.4 against 1.7) and 800 (4.1 against 5.4), all within
  // issue 19's ceilings (reports/default_front.py). Solving a two-point contact's normal rows as
  // one 2x2 block holds that floor at 8 x 2 x 2, but on box scenes costs the time the pass saved
  // (stacks 200: step 0.98 of 8 x 2 x 3's) and lets settling_boxes 3000 penetrate 67 mm (median
  // of 21 runs, against 53 mm). Peak penetration is one draw from a wide spread; medians are of
  // runs with gravity scaled by 1 + 1e-6 i: pile 1200's of 41 runs at 8 x 2 x 3 is 12.1 mm (8 x 2
  // x 2: 12.7, with 15 runs over 15 mm), the unperturbed run's 9.5 mm.
  int substeps = 8;                    // >= 1
  int velocity_passes = 1;             // >= 1, soft passes per substep that also push overlaps apart
  // >= 1, rigid passes per substep once positions have moved, which take out what the soft
  // passes' spring added to the velocities. The spring pushes at most max_push_speed / 8 and
  // overlaps deeper than linear_slop are pushed apart through the positions, so even one pass
  // launches no column of up to eight overlapping bodies (fx2d_canonical_test).
  // Sweeping the colours in reverse on every other rigid pass (a symmetric Gauss-Seidel) did not
  // converge them better: single runs' peak penetration at 3 passes rose from 8.35 to 12.80 mm on
  // pile 1200 and 2.43 to 4.12 on pile 300, and at 2 passes from 5.73 to 8.66 on settling_boxes 800.
  // Nor would the later passes spare much by skipping the batches the pass before left converged:
  // in the steps that take them, only 3-4% of settling_boxes 800's batches (8-10% of 200's) change
  // an impulse by less than 1e-4 N s in the second or the third pass (a probe over 200 steps).
  int relax_passes = 3;
  // >= 1: how many of a substep's rigid passes include the joints (every FxConstraint); the others
  // sweep the contacts alone. The further passes carry a load down a column of contacts; a chain of
  // joints holds its pins about as well without them. A chain deeper than shallow_schedule_depth
  // takes the full schedule in every step: 100 links released level opened 2.11 cm at worst with
  // the joints in one rigid pass, 2.18 in two, 2.26 in three (2.98 in none); 200 links 4.8, 5.0 and
  // 5.1 cm (joint_test). The 200-link chain's step took 0.62 of the time with one (`ab`, sleeping
  // off), and joint_grid's mean step 0.88, where the lattice, whose loops the passes do converge,
  // sags 0.037 m instead of 0.032 (Box2D 2.4.1: 0.37); sweep put 1, 2 and 3 all on its front.
  int joint_relax_passes = 1;
  int position_passes = 1;             // >= 0, final projection passes per step
  // The rest schedule: a step in which every awake dynamic body has rested (slower than the sleep
  // speeds, as sleeping counts it: a body that may not sleep never rests) for rest_schedule_time, and
  // no awake kinematic body moves, takes one soft and one rigid pass per substep instead. What holds a
  // resting world is the substeps' stiffness; the passes converge what motion brings. At rest 8 x 1 x
  // 1 keeps a stack of 116 boxes and a mass ratio of 1024 (8 x 2 x 3 throughout: 120 and 1117; 8 x 1 x
  // 2 at rest: 119 and 1117, but 0.80 of the step's time on stacks where 8 x 1 x 1 takes 0.69), where
  // 4 x 2 x 3 at rest keeps 76 and 861, and with no rigid pass a resting stack gains kinetic energy
  // (measured at a max_push_speed of 3; at 5 the mass ratio is 1328). Its substeps measure the
  // separations once, at the step's start, unless a contact could close a gap within the step or
  // press a touching point in by more than its spring would push back unseen (at 1 mm/s).
  // One moving body anywhere gives the whole step the full schedule, unless the shallow schedule
  // below takes it.
  bool rest_schedule = true;
  float rest_schedule_time = 0.1f;     // seconds, >= 0; longer than a bounce's or a swing's pause
  // The shallow schedule: a step in which no touching contact closes faster than
  // shallow_schedule_speed (its bodies' approach along the normal, plus what their spins add) and
  // no awake body stands on a chain of more than shallow_schedule_depth bodies (touching contacts
  // and joints, down to a static, kinematic or sleeping body; a body on no chain, in free fall,
  // counts as none) also takes one soft and one rigid pass per substep. The passes carry an
  // impact's momentum across a row of bodies and a load down a column, about one body further
  // each; a step with neither needs one. 8 x 1 x 1 throughout holds a stack of 83 boxes and a
  // pyramid of base 75 (a depth of 75), so 32 leaves the deep ones the full schedule with room;
  // it keeps every other stability boundary (mass ratio, card house, chain load, thin floor) and
  // every behavioural test of the full schedule. At 5 m/s pile 1200's median peak penetration over
  // 7 runs (gravity scaled by 1 + 1e-6 i) rose from 11.7 to 15.2 mm, its landings solved lightly;
  // at 3 m/s it is 11.3 mm. With one soft pass in the other steps (median of 5 runs): 9.8 mm at
  // 3 m/s, 14.2 at 5 and 13.0 at 8, pile 300's 2.8, 4.2 and 4.3 mm, and no step time gained beyond
  // noise. Costs a pass over the contacts, and over their bodies' links when calm.
  // The whole step takes the settings' passes, not just the contacts near an impact: given only to
  // those within 2 or 4 links of a contact that closes fast, the rest on one and one, they saved
  // pile 1200 a tenth of its solve and relax but raised pile 300's median peak penetration over 7
  // runs from 2.07 to 4.16 mm and pile 1200's from 11.3 to 14.2 mm (4 links; 19.5 mm unperturbed
  // at 2; settling_boxes 3000's fell from 57.9 to 45.9): an impact's load travels down the heap to
  // the ground, past any few links. Given per island instead, they would keep each heap whole but
  // spare little: in the steps that take the settings' passes, the islands with a fast contact
  // hold 0.81 of settling_boxes 800's contacts, 0.93 of settling_boxes 3000's and 0.97 of a pile's
  // (0.47 of settling_boxes 200's, whose median step is a shallow one). Nor in the substeps where a
  // point closes faster than shallow_schedule_speed within the substep (its approach measured after
  // the warm start) and one rigid pass in the others: only 33 of settling_boxes 200's 376 substeps
  // of such steps and 261 of 800's 960 have one, but the peak penetrations of single runs rose from
  // 1.73 to 2.38 mm (settling_boxes 200), 2.43 to 3.59 (pile 300) and 8.35 to 12.69 (pile 1200).
  // Kept from the first such substep to the step's end (91 of 384 and 440 of 992), still 2.16, 4.30
  // and 10.22 mm: the rigid passes before an impact carry the heap's own settling, not the impact's.
  // Nor do shallow steps pay at fewer substeps, their springs then capped lower (a throwaway build
  // that gave a step 6 substeps after a shallow one; `ab`, sleeping off, 10 rounds): settling_boxes
  // 200's step 0.871 (instructions 0.903), 800's 0.968 (0.971), pile 200's instructions 0.900, but
  // stacks' displacement 2.3 -> 3.3 mm, pile 200's and 800's penetration 2.2 -> 2.8 and 5.1 -> 5.5 mm,
  // and stability's mass_ratio 1220 -> 861 (under its 1000) and chain_load 939 -> 512; with 4
  // substeps stacks 50 moved 9.7 mm (ceiling 5) and pile 1200 penetrated 15.1 mm (ceiling 15).
  // Nor at 4 substeps after a shallow step whose chains were at most 8 bodies deep, with no joint
  // and no touching pair of mass ratio over 4, which leaves the stacks (10 deep) and mass_ratio at 8
  // (a throwaway build; `run --counter instructions`, sleeping off): settling_boxes 200 took 151 of
  // its 200 steps so and 0.90 of the instructions, peak penetration 1.73 -> 2.25 mm, but 800 only
  // its 19 steps of free fall (its heaps stand deeper), 0.98; at a depth of 4, both only their free
  // fall. Every step at 4 substeps (`sweep`) takes 0.74-0.76 of the time, but settling_boxes 800 then
  // penetrates 12.2 mm (ceiling 10).
  bool shallow_schedule = true;
  int shallow_schedule_depth = 32;      // bodies, >= 0
  float shallow_schedule_speed = 3.0f;  // m/s, >= 0
  // The impact schedule: a step in which some contact closes, within one substep, by more than
  // impact_schedule_travel times the motion past which continuous collision sweeps the thinner of
  // its bodies (half its least distance from centroid to surface; its closing speed measured as
  // the shallow schedule measures it) takes impact_velocity_passes soft passes per substep where
  // velocity_passes asks for fewer. In the substep that takes such an impact, one soft pass
  // leaves the points of a face landing flat far apart, and the body turns before the rigid
  // passes agree. A box landing flat tilts by (one soft pass / two; that closing share): 10 cm box
  // at 5 m/s 0.004 / 0.002 rad (0.42), 10 m/s 0.026 / 0.013 (0.83), 20 m/s 0.108 / 0.036 (1.67),
  // 40 m/s 0.325 / 0.075 (3.3); 1 m box at 20 m/s 0.006 / 0.001 (0.17), 40 m/s 0.030 / 0.018
  // (0.33). At 1000 m/s one pass throws a 10 cm box back up at 6.8 m/s spinning at 122 rad/s, and
  // it falls through a 2 cm floor when it comes down (continuous_test); with two it stops. The
  // canonical scenes close by 0.34 at most (settling_boxes 3000; pile 1200 0.09), so they never
  // take it.
  float impact_schedule_travel = 0.5f;   // >= 0
  int impact_velocity_passes = 2;        // >= 1
  bool sleeping = true;                // let resting bodies sleep
  float time_to_sleep = 0.5f;          // seconds a whole island must rest before it sleeps
  float linear_sleep_speed = 0.05f;    // m/s below which a body counts as resting
  float angular_sleep_speed = 0.05f;   // rad/s below which a body counts as resting
  float restitution_threshold = 1.0f;  // m/s: slower impacts do not bounce
  // Contact stiffness, capped at a quarter of the substep rate. A resting soft contact sinks by
  // load / (m_eff (2 pi hertz)^2), whatever the damping ratio: 2.2 mm down a column of ten boxes at
  // 120 Hz, 8.8 mm at 4 substeps' cap of 60 Hz. Scaling the spring's impulse term down to shrink
  // that depth turns the warm-started impulse into an integrator: at half its value stacks' columns
  // at 4 substeps swung between 2 and 9.6 mm for over half a second, at a quarter or none they
  // never settled (10 s). Nor do more passes make up for the softer cap: at 4 substeps, with 1 or 2
  // soft and 2 to 4 rigid passes, settling_boxes 800's median peak penetration over 5 runs (gravity
  // scaled by 1 + 1e-6 i) is 10.1 to 12.9 mm (ceiling 10), against 5.1 at 8 x 1 x 3.
  float contact_hertz = 120.0f;
  // Dimensionless, in (0, 1000]. A higher ratio makes the soft passes nearly rigid: at 8 x 2 x 1 and
  // 17 a stack of 113 boxes and a mass ratio of 1720 hold, but a pyramid of base 56 never comes to
  // rest (its top slides 0.38 m in 5 s), where at 10 it rests within 70 steps.
  float contact_damping_ratio = 10.0f;
  // Joint stiffness (hertz), capped likewise. A soft pin yields like a spring of stiffness
  // m_eff (2 pi hertz)^2, m_eff its effective mass (half a link's mass for two links pulled end to
  // end): a chain carrying a load N times a link's mass opens each pin by 2 N g / (2 pi hertz)^2
  // under the load's weight, three times that at the bottom of a swing from level. 120 Hz keeps
  // N = 500 within 5.3 cm there; 60 Hz would open 21 cm.
  float joint_hertz = 120.0f;
  float joint_damping_ratio = 2.0f;    // dimensionless, in (0, 1000]
  // m/s: the fastest a contact pushes an overlap apart; the contact's soft spring, which acts
  // through the velocities, pushes at most an eighth of it. The spring's cap is the load a contact
  // holds before it sinks (3 -> 5: mass_ratio 1024 -> 1328, settling_boxes 3000's median peak
  // penetration 57.2 -> 47.8 mm), and the launch one rigid pass leaves where its pushes add up
  // down a column: overlap_recovery's pyramid throws a box at 3.06 m/s at 4, over that test's
  // 3 m/s. 3.5 is the most the one-pass launch allows (mass_ratio 1220, settling_boxes 3000 51.5
  // mm; stability_test's Fx2dRecoversFromOverlapOfFourTenthsOfABoxWithOneRelaxationPass).
  float max_push_speed = 3.5f;
  // metres of overlap the position projection tolerates; deeper overlap is also pushed apart
  // through the positions in every substep
  float linear_slop = 0.005f;
  // m/s: velocities are clamped, so no input can overflow. 1000 m/s is a rifle bullet's muzzle
  // speed, the fastest anything a scene throws moves: 16.7 m per 60 Hz step. Continuous collision
  // sweeps a fast body's whole step (continuous.h), so tunnelling does not set this bound; it
  // bounds what the solver takes as finite: accelerations (max_acceleration), joint impulses.
  float max_linear_speed = 1000.0f;
  // Solve every contact batch lane by lane instead of as vectorised lanes. The results are
  // bit-identical; this exists to prove it and to measure what the batching is worth.
  bool force_scalar_solver = false;
  // Threads a step may use, in [1, 64], the stepping thread included. Results are bit-identical
  // for every count (Tasks.h). Without a scheduler the scene starts a pool of workers - 1 threads
  // once, when this is set, and keeps it; they sleep while the scene is not stepping.
  int workers = 1;
  // The user's own scheduler; both callbacks or neither. Empty: the scene's own pool.
  FxTaskScheduler scheduler;
};

// The most entities a scene holds: the solver addresses each body's 32-byte state by a 32-bit byte
// offset, one past the last body included.
inline constexpr std::uint32_t fx_max_entities = (std::uint32_t{1} << 27) - 1;

class FxScene {
 public:
  // Throws FxInvalidArgument naming the field: non-finite gravity, dt <= 0, substeps < 1, ...
  explicit FxScene(const FxSceneSettings& settings = {});
  ~FxScene();
  FxScene(const FxScene&) = delete;
  FxScene& operator=(const FxScene&) = delete;

  // Adds an entity. Throws FxInvalidArgument naming the field for non-finite pose or velocity,
  // density <= 0 on a dynamic body, negative friction, restitution outside 0..1, negative damping,
  // and when the scene already holds fx_max_entities.
  std::shared_ptr<FxEntity> create_entity(const FxEntityDef& def);
  // Removes an entity and its contacts and constraints; wakes what touched it. Allowed at any
  // time outside step(), including from the step callback. Other handles stay valid.
  void remove_entity(const FxEntity& entity);

  // Adds a constraint whose entities are in this scene (throws FxInvalidArgument otherwise).
  void add_constraint(std::shared_ptr<FxConstraint> constraint);
  void remove_constraint(const FxConstraint& constraint);

  // Advances the scene by settings().dt. Never throws for a scene built from valid input.
  void step();

  // Called at the end of every step, after the solve; it may create and remove entities.
  void set_step_callback(std::function<void(FxScene&)> callback);

  const FxSceneSettings& settings() const;
  // Changes solver settings between steps (validated like the constructor's). A new dt or substep
  // count scales the impulses that contacts and joints carry into the next step by the substep's new
  // length over its old, as they were a substep's: a resting stack keeps resting.
  void set_settings(const FxSceneSettings& settings);

  std::size_t entity_count() const;
  // The entity at a packed index (0 .. entity_count()-1).
  const std::shared_ptr<FxEntity>& entity(std::uint32_t packed_index) const;
  std::size_t constraint_count() const;

  // Touching contact manifolds (entity pairs with at least one contact point) after the last step.
  int contact_count() const;
  // Copies the touching manifolds into `out` (cleared first), in the solver's order.
  void contacts(std::vector<FxContact>& out) const;

  // The stage timings of the last step (zero unless built with FX2D_PROFILE).
  const FxProfile& profile() const;
  std::uint64_t step_index() const;

 private:
  std::unique_ptr<detail::World> world_;
};

}  // namespace fx2d
