// ODE 0.16 behind the plugin C ABI (plugin/fx2d_plugin_abi.h), written with the SDK's C++ layer
// (plugin/fx2d_bench_plugin.hpp) and linked into fx2d-bench as the built-in "ode" engine, as Box2D
// is: a 3D ODE world held to the plane z = 0, stepped with dWorldQuickStep.
//
// Invariant: bodies_[i] describes scene body i, so every read is in scene order, and after each
// step every dynamic body lies in z = 0 with a rotation about z only and no out-of-plane velocity.
//
// How 2D is emulated (ODE has no 2D mode):
// - every dynamic body carries a plane-2D joint, and after each step the adapter zeroes what the
//   joint only damps (z, vz, wx, wy) and resets the rotation to the one about z it implies, as
//   ODE's FAQ recommends for 2D;
// - a box is a 1 m deep box, so density per m^3 equals the scene's per m^2 and mass and
//   z-inertia equal the 2D ones;
// - a circle is a sphere of the same radius and the 2D mass, so its z-inertia is 2/5 m r^2, not
//   the disc's 1/2 m r^2: ODE spheres roll with 20% less rotational inertia than the other engines.
// Contacts: at most max_contacts_per_pair points per geom pair, friction pyramid (dContactApprox1)
// with mu = sqrt(mu_a * mu_b) of the dynamic frictions and restitution max(e_a, e_b) above 1 m/s,
// the same mixing and threshold as Box2D; softness stays at the world's ERP and CFM.
// Capabilities: no polygons, as ODE 0.16's convex-box collider returns one contact point, so a
// convex prism cannot rest on a face (a triangle dropped on the ground sinks 2 cm and slides 4 cm);
// no bullets, as ODE has no continuous collision; sleeping is ODE's auto-disable.
// Determinism: dWorldQuickStep shuffles its constraint rows with dRandInt, which draws from one
// process-wide seed (ODE 0.16.2 quickstep.cpp:2457, misc.cpp:33), so a world's trajectory
// depended on how many rows every earlier world in the process had shuffled (the warm-up, earlier
// repeats). Each world keeps its own seed, swapped in around its step, so that a trajectory
// depends on the scene alone, the same in every repeat and every process.
// Space: dHashSpace with ODE's default levels. Every dSpaceCollide it allocates and clears a bit
// table of n x n bits (ODE 0.16 collision_space.cpp, "tested"), so memory and time grow as n^2:
// peak RSS 428 MB and 3.4 s a step with no contact at 50,000 bodies; at 200,000 the process grew
// to 5.3 GB and ODE aborted ("i >= 0 && i < tested_rowsize*n", collision_space.cpp:566: the
// table's int byte index overflows above about 131,000 bodies). dSweepAndPruneSpace has no such
// table, but the order in which it reports pairs sets the order of the contact rows, and so changes
// every canonical scene's trajectory and state hash (max penetration moves by 3% on pile 300, by
// 23% on stacks 50; measured on ODE 0.16.2). To keep ODE's results comparable with every earlier
// run, the hash space stays and larger scenes are refused (max_bodies), before anything is created.
#include <ode/ode.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "engines/engines.h"
#include "engines/plugin_engine.h"
#include "plugin/fx2d_bench_plugin.hpp"

namespace fxbench {
namespace {

enum Knob { iterations, erp, cfm, auto_disable, threads, knob_count };

// CFM's bound: contacts are springs of stiffness ERP / (dt CFM), and at CFM 1 (ERP 0.2, 60 Hz)
// that is 12 N/m, under which a 1 kg box sinks 0.8 m into the ground; anything softer is no solid.
constexpr Fx2dBenchKnob knobs[knob_count] = {
    {"iterations", FX2D_BENCH_KNOB_INTEGER, 1, 1000, 20, "QuickStep iterations per step"},
    {"erp", FX2D_BENCH_KNOB_NUMBER, 0, 1, 0.2,
     "error reduction parameter: share of joint error fixed per step"},
    {"cfm", FX2D_BENCH_KNOB_NUMBER, 0, 1, 1e-5, "constraint force mixing: softness of every constraint"},
    {"auto_disable", FX2D_BENCH_KNOB_BOOLEAN, 0, 1, 1, "let resting bodies sleep (ODE's auto-disable)"},
    {"threads", FX2D_BENCH_KNOB_INTEGER, 1, 8, 1,
     "threads stepping the world (ODE's thread pool); above 1 not deterministic"},
};

// At most 65,536 bodies: the hash space's n x n bit table is 512 MiB at this size, cleared every
// step, the largest scene worth waiting for, and half the size at which ODE itself aborts.
constexpr int64_t max_bodies = 65'536;

constexpr dReal box_depth = 1.0;  // metres; the 2D density becomes kg/m^3 over this depth
constexpr int max_contacts_per_pair = 4;
// Box2D's b2_velocityThreshold: slower impacts are inelastic, so restitution acts alike in both.
constexpr dReal bounce_threshold = 1.0;  // m/s

void ensure_ode_ready_on_this_thread() {
  static const int initialised = dInitODE2(0);
  if (initialised == 0) throw std::runtime_error("dInitODE2 failed");
  // Collision needs per-thread data; allocating it again on the same thread is a no-op.
  if (dAllocateODEDataForThread(dAllocateMaskAll) == 0)
    throw std::runtime_error("dAllocateODEDataForThread failed");
}

// The scene's body count, once it is one ODE can take and ODE is ready on this thread: the
// constructor's first member reads it, before any other member creates an ODE object. The harness
// refuses larger scenes before building them; this keeps ODE's abort (above) from a plugin table
// driven by hand too.
std::size_t body_count_for_ode(const Fx2dBenchScene& scene) {
  if (scene.body_count > max_bodies) {
    throw std::invalid_argument("the scene has " + std::to_string(scene.body_count) +
                                " bodies; the ODE adapter takes at most " + std::to_string(max_bodies) +
                                " (ODE's hash space clears an n x n bit table every step)");
  }
  ensure_ode_ready_on_this_thread();
  return static_cast<std::size_t>(std::max(scene.body_count, 0));
}

double angle_about_z(const dReal* rotation) { return std::atan2(rotation[4], rotation[0]); }

Fx2dBenchVec2 world_point(const Fx2dBenchBody& body, Fx2dBenchVec2 local) {
  const double c = std::cos(body.angle);
  const double s = std::sin(body.angle);
  return {body.position.x + (c * local.x - s * local.y), body.position.y + (s * local.x + c * local.y)};
}

// More than one thread: ODE's built-in multi-threaded implementation, served by a pool of that
// many threads started with the world and stopped after it, so no step starts a thread. The world
// steps its islands on the pool, and each island's QuickStep stages over its threads, while the
// calling thread waits. One thread makes nothing: the world keeps ODE's default self-threaded
// implementation, the same code and bits as before the knob.
class StepThreads {
 public:
  explicit StepThreads(int threads) {
    if (threads == 1) return;
    implementation_.reset(dThreadingAllocateMultiThreadedImplementation());
    pool_.reset(
        dThreadingAllocateThreadPool(static_cast<unsigned>(threads), 0, dAllocateFlagBasicData, nullptr));
    if (!implementation_ || !pool_) throw std::runtime_error("ODE could not start a pool of threads");
    dThreadingThreadPoolServeMultiThreadedImplementation(pool_.get(), implementation_.get());
  }
  // Releases the pool's threads; freeing the pool then waits for them, and the implementation goes last.
  ~StepThreads() {
    if (pool_) dThreadingImplementationShutdownProcessing(implementation_.get());
  }
  StepThreads(const StepThreads&) = delete;
  StepThreads& operator=(const StepThreads&) = delete;

  void step_with(dWorldID world) const {
    if (implementation_)
      dWorldSetStepThreadingImplementation(world, dThreadingImplementationGetFunctions(implementation_.get()),
                                           implementation_.get());
  }

 private:
  fx2d_bench::Owned<dxThreadingImplementation, dThreadingFreeImplementation> implementation_;
  fx2d_bench::Owned<dxThreadingThreadPool, dThreadingFreeThreadPool> pool_;
};

struct BodyRecord {
  dBodyID body = nullptr;  // null for a static body, which is a geom alone
  dGeomID geom = nullptr;
  double friction = 0.0;
  double restitution = 0.0;
};

bool is_dynamic(dBodyID body) { return body != nullptr && dBodyIsKinematic(body) == 0; }

class OdeWorld {
 public:
  explicit OdeWorld(const Fx2dBenchScene& scene)
      : bodies_(body_count_for_ode(scene)),
        threads_(static_cast<int>(scene.settings[threads])),
        dt_(scene.dt) {
    const double* knob = scene.settings;
    threads_.step_with(world_.get());
    dWorldSetGravity(world_.get(), scene.gravity.x, scene.gravity.y, 0.0);
    dWorldSetQuickStepNumIterations(world_.get(), static_cast<int>(knob[iterations]));
    dWorldSetERP(world_.get(), knob[erp]);
    dWorldSetCFM(world_.get(), knob[cfm]);
    // Bodies copy the world's flag when created, so it is set first; thresholds stay ODE's defaults.
    dWorldSetAutoDisableFlag(world_.get(), knob[auto_disable] != 0.0 ? 1 : 0);
    // bodies_ is sized once: geoms point at their record (dGeomSetData), so it must never move.
    for (std::size_t i = 0; i < bodies_.size(); ++i) create_body(scene.bodies[i], bodies_[i]);
    for (int32_t i = 0; i < scene.joint_count; ++i) create_joint(scene, scene.joints[i]);
    std::ranges::sort(jointed_pairs_);
  }

  void step() {
    touching_pairs_ = 0;
    dSpaceCollide(space_.get(), this, &OdeWorld::near_callback);
    dRandSetSeed(random_seed_);
    dWorldQuickStep(world_.get(), dt_);
    random_seed_ = dRandGetSeed();
    dJointGroupEmpty(contact_group_.get());
    flatten_dynamic_bodies();
  }

  int32_t contact_count() const { return touching_pairs_; }

  Fx2dBenchBodyState body_state(std::size_t index) const {
    const BodyRecord& record = bodies_[index];
    if (record.body == nullptr) {
      const dReal* p = dGeomGetPosition(record.geom);
      return {{p[0], p[1]}, angle_about_z(dGeomGetRotation(record.geom)), {0.0, 0.0}, 0.0};
    }
    const dReal* p = dBodyGetPosition(record.body);
    const dReal* v = dBodyGetLinearVel(record.body);
    return {{p[0], p[1]},
            angle_about_z(dBodyGetRotation(record.body)),
            {v[0], v[1]},
            dBodyGetAngularVel(record.body)[2]};
  }

  OutOfPlaneDrift drift() const {
    OutOfPlaneDrift worst;
    for (const BodyRecord& record : bodies_) {
      if (!is_dynamic(record.body)) continue;
      const dReal* p = dBodyGetPosition(record.body);
      const dReal* v = dBodyGetLinearVel(record.body);
      const dReal* w = dBodyGetAngularVel(record.body);
      const dReal* r = dBodyGetRotation(record.body);
      worst.position_z = std::max(worst.position_z, std::abs(p[2]));
      worst.linear_velocity_z = std::max(worst.linear_velocity_z, std::abs(v[2]));
      worst.angular_velocity_xy = std::max({worst.angular_velocity_xy, std::abs(w[0]), std::abs(w[1])});
      worst.rotation_off_z =
          std::max({worst.rotation_off_z, std::abs(r[2]), std::abs(r[6]), std::abs(r[8]), std::abs(r[9])});
    }
    return worst;
  }

 private:
  // The SDK's create() lets through only circles and boxes (the capabilities below).
  dGeomID create_geom(const Fx2dBenchBody& spec) {
    if (spec.shape == FX2D_BENCH_CIRCLE) return dCreateSphere(space_.get(), spec.radius);
    return dCreateBox(space_.get(), 2.0 * spec.half_extents.x, 2.0 * spec.half_extents.y, box_depth);
  }

  static dMass mass_of(const Fx2dBenchBody& spec) {
    dMass mass;
    if (spec.shape == FX2D_BENCH_CIRCLE) {
      dMassSetSphereTotal(&mass, spec.density * std::numbers::pi * spec.radius * spec.radius, spec.radius);
    } else {
      dMassSetBox(&mass, spec.density / box_depth, 2.0 * spec.half_extents.x, 2.0 * spec.half_extents.y,
                  box_depth);
    }
    return mass;
  }

  void create_body(const Fx2dBenchBody& spec, BodyRecord& record) {
    record.friction = spec.dynamic_friction;
    record.restitution = spec.restitution;
    record.geom = create_geom(spec);
    dGeomSetData(record.geom, &record);

    // Box and sphere have their centre of mass at the geometric centre, which ODE requires of the
    // body frame, so the body frame is the scene's body origin.
    dMatrix3 rotation;
    dRFromAxisAndAngle(rotation, 0, 0, 1, spec.angle);
    if (spec.type == FX2D_BENCH_STATIC_BODY) {
      dGeomSetPosition(record.geom, spec.position.x, spec.position.y, 0);
      dGeomSetRotation(record.geom, rotation);
      return;
    }
    record.body = dBodyCreate(world_.get());
    dBodySetPosition(record.body, spec.position.x, spec.position.y, 0);
    dBodySetRotation(record.body, rotation);
    dBodySetLinearVel(record.body, spec.linear_velocity.x, spec.linear_velocity.y, 0);
    dBodySetAngularVel(record.body, 0, 0, spec.angular_velocity);
    dGeomSetBody(record.geom, record.body);
    if (spec.type == FX2D_BENCH_KINEMATIC_BODY) {
      dBodySetKinematic(record.body);
      return;
    }
    const dMass mass = mass_of(spec);
    dBodySetMass(record.body, &mass);
    dJointAttach(dJointCreatePlane2D(world_.get(), nullptr), record.body, nullptr);
  }

  void create_joint(const Fx2dBenchScene& scene, const Fx2dBenchJoint& spec) {
    dBodyID body_a = fx2d_bench::joint_body(bodies_, spec.body_a).body;
    dBodyID body_b = fx2d_bench::joint_body(bodies_, spec.body_b).body;
    if (body_a == nullptr && body_b == nullptr)
      throw std::invalid_argument("a joint between two static bodies");
    const auto a = static_cast<std::size_t>(spec.body_a);
    const auto b = static_cast<std::size_t>(spec.body_b);
    jointed_pairs_.push_back(ordered_pair(a, b));
    const Fx2dBenchVec2 anchor_a = world_point(scene.bodies[a], spec.local_anchor_a);
    const Fx2dBenchVec2 anchor_b = world_point(scene.bodies[b], spec.local_anchor_b);

    // A missing second body is the static world to every ODE joint; giving the first one a body
    // keeps the adapter clear of ODE's reversed-joint handling.
    const bool swap = body_a == nullptr;
    dBodyID first = swap ? body_b : body_a;
    dBodyID second = swap ? body_a : body_b;
    const Fx2dBenchVec2 first_anchor = swap ? anchor_b : anchor_a;
    const Fx2dBenchVec2 second_anchor = swap ? anchor_a : anchor_b;
    if (spec.kind == FX2D_BENCH_DISTANCE_JOINT) {
      dJointID joint = dJointCreateDBall(world_.get(), nullptr);
      dJointAttach(joint, first, second);
      dJointSetDBallAnchor1(joint, first_anchor.x, first_anchor.y, 0);
      dJointSetDBallAnchor2(joint, second_anchor.x, second_anchor.y, 0);
      const double as_built = std::hypot(anchor_b.x - anchor_a.x, anchor_b.y - anchor_a.y);
      dJointSetDBallDistance(joint, spec.length >= 0.0 ? spec.length : as_built);
      return;
    }
    dJointID joint = dJointCreateHinge(world_.get(), nullptr);
    dJointAttach(joint, first, second);
    dJointSetHingeAnchor(joint, first_anchor.x, first_anchor.y, 0);
    dJointSetHingeAxis(joint, 0, 0, 1);
  }

  // Jointed bodies do not collide, as in Box2D (collideConnected = false). ODE's own
  // dAreConnected cannot tell one static body from another, so the adapter keeps the pairs.
  bool are_jointed(const BodyRecord& a, const BodyRecord& b) const {
    if (jointed_pairs_.empty()) return false;
    return std::ranges::binary_search(jointed_pairs_, ordered_pair(index_of(a), index_of(b)));
  }

  std::size_t index_of(const BodyRecord& record) const {
    return static_cast<std::size_t>(&record - bodies_.data());
  }

  static std::pair<std::size_t, std::size_t> ordered_pair(std::size_t a, std::size_t b) {
    return std::minmax(a, b);
  }

  static void near_callback(void* world, dGeomID a, dGeomID b) {
    static_cast<OdeWorld*>(world)->collide_pair(a, b);
  }

  void collide_pair(dGeomID a, dGeomID b) {
    dBodyID body_a = dGeomGetBody(a);
    dBodyID body_b = dGeomGetBody(b);
    // Static and kinematic bodies never push each other.
    if (!is_dynamic(body_a) && !is_dynamic(body_b)) return;
    const auto& record_a = *static_cast<const BodyRecord*>(dGeomGetData(a));
    const auto& record_b = *static_cast<const BodyRecord*>(dGeomGetData(b));
    if (are_jointed(record_a, record_b)) return;
    std::array<dContact, max_contacts_per_pair> contacts{};
    const int count = dCollide(a, b, max_contacts_per_pair, &contacts[0].geom, sizeof(dContact));
    if (count == 0) return;
    ++touching_pairs_;

    dSurfaceParameters surface{};
    surface.mode = dContactApprox1;
    surface.mu = std::sqrt(record_a.friction * record_b.friction);
    const double restitution = std::max(record_a.restitution, record_b.restitution);
    if (restitution > 0.0) {
      surface.mode |= dContactBounce;
      surface.bounce = restitution;
      surface.bounce_vel = bounce_threshold;
    }
    for (int i = 0; i < count; ++i) {
      dContact& contact = contacts[static_cast<std::size_t>(i)];
      contact.surface = surface;
      dJointAttach(dJointCreateContact(world_.get(), contact_group_.get(), &contact), body_a, body_b);
    }
  }

  // The plane-2D joint only drives out-of-plane motion back towards the plane over several
  // steps; this removes what is left so the 2D pose is exact. A disabled body does not move.
  void flatten_dynamic_bodies() {
    for (const BodyRecord& record : bodies_) {
      if (!is_dynamic(record.body) || dBodyIsEnabled(record.body) == 0) continue;
      dQuaternion about_z;
      dQFromAxisAndAngle(about_z, 0, 0, 1, angle_about_z(dBodyGetRotation(record.body)));
      dBodySetQuaternion(record.body, about_z);
      const dReal* p = dBodyGetPosition(record.body);
      dBodySetPosition(record.body, p[0], p[1], 0);
      const dReal* v = dBodyGetLinearVel(record.body);
      dBodySetLinearVel(record.body, v[0], v[1], 0);
      const dReal* w = dBodyGetAngularVel(record.body);
      dBodySetAngularVel(record.body, 0, 0, w[2]);
    }
  }

  std::vector<BodyRecord> bodies_;  // first: its size is checked before ODE is touched
  // Freed in reverse order, also when building failed part way: the contact group, then the space
  // with its geoms, then the world with its bodies and joints, then the threads, which the world
  // still calls as it is destroyed (it frees a wait of theirs: ODE 0.16 threading_base.cpp).
  StepThreads threads_;
  fx2d_bench::Owned<dxWorld, dWorldDestroy> world_{dWorldCreate()};
  fx2d_bench::Owned<dxSpace, dSpaceDestroy> space_{dHashSpaceCreate(nullptr)};
  fx2d_bench::Owned<dxJointGroup, dJointGroupDestroy> contact_group_{dJointGroupCreate(0)};
  double dt_;
  std::vector<std::pair<std::size_t, std::size_t>> jointed_pairs_;  // sorted (lower, higher) body indices
  int32_t touching_pairs_ = 0;     // geom pairs with at least one contact point in the last step
  unsigned long random_seed_ = 0;  // this world's state of ODE's shared generator, between steps
};

const fx2d_bench::EngineDescription ode_engine{
    .name = "ode",
    .library_version = [] { return FX2D_BENCH_ODE_VERSION; },
    .knobs = knobs,
    .capabilities = {FX2D_BENCH_BIT(FX2D_BENCH_CIRCLE) | FX2D_BENCH_BIT(FX2D_BENCH_BOX),
                     fx2d_bench::all_joints, 1, 0, max_bodies, 0.0},
};

std::shared_ptr<const Plugin> linked_ode_plugin() {
  static const Fx2dBenchPlugin table = fx2d_bench::plugin_table<OdeWorld, ode_engine>();
  static const std::shared_ptr<const Plugin> linked = Plugin::linked(table);
  return linked;
}

}  // namespace

std::unique_ptr<Engine> make_ode_engine() { return make_plugin_engine(linked_ode_plugin()); }

// The table is linked in, so no library needs holding: the entry makes engines with the plain factory.
EngineInfo ode_engine_info() {
  EngineInfo info = plugin_engine_info(linked_ode_plugin(), "ode");
  info.make = &make_ode_engine;
  return info;
}

OutOfPlaneDrift ode_out_of_plane_drift(const Engine& engine) {
  const Fx2dBenchInstance* instance = built_instance(engine, *linked_ode_plugin());
  if (instance == nullptr) throw std::invalid_argument("ode_out_of_plane_drift: not a built ODE engine");
  return fx2d_bench::built_world<OdeWorld>(instance).drift();
}

}  // namespace fxbench
