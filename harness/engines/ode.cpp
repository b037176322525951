// The ODE 0.16 adapter: builds a SceneSpec as a 3D ODE world held to the plane z = 0 and steps
// it with dWorldQuickStep.
//
// Invariant: bodies_[i] describes scene.bodies[i], so every read is in spec order, and after each
// step every dynamic body lies in z = 0 with a rotation about z only and no out-of-plane velocity.
//
// How 2D is emulated (ODE has no 2D mode):
// - every dynamic body carries a plane-2D joint, and after each step the adapter zeroes what the
//   joint only damps (z, vz, wx, wy) and resets the rotation to the one about z it implies, as
//   ODE's FAQ recommends for 2D;
// - a box is a 1 m deep box, so density per m^3 equals the spec's per m^2 and mass and
//   z-inertia equal the 2D ones;
// - a circle is a sphere of the same radius and the 2D mass, so its z-inertia is 2/5 m r^2, not
//   the disc's 1/2 m r^2: ODE spheres roll with 20% less rotational inertia than the other engines.
// Contacts: at most max_contacts_per_pair points per geom pair, friction pyramid (dContactApprox1)
// with mu = sqrt(mu_a * mu_b) of the dynamic frictions and restitution max(e_a, e_b) above 1 m/s,
// the same mixing and threshold as Box2D; softness stays at the world's ERP and CFM.
// Polygons are rejected: ODE 0.16's convex-box collider returns one contact point, so a convex
// prism cannot rest on a face (a triangle dropped on the ground sinks 2 cm and slides 4 cm).
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
// run, the hash space stays and larger scenes are refused (ode_capabilities.max_bodies), before anything is created.
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

#include "common/errors.h"
#include "engines/engines.h"

namespace fxbench {
namespace {

constexpr dReal box_depth = 1.0;  // metres; the 2D density becomes kg/m^3 over this depth
constexpr int max_contacts_per_pair = 4;
// Box2D's b2_velocityThreshold: slower impacts are inelastic, so restitution acts alike in both.
constexpr dReal bounce_threshold = 1.0;  // m/s

void ensure_ode_ready_on_this_thread() {
  static const int initialised = dInitODE2(0);
  if (initialised == 0) throw std::runtime_error("ode: dInitODE2 failed");
  // Collision needs per-thread data; allocating it again on the same thread is a no-op.
  if (dAllocateODEDataForThread(dAllocateMaskAll) == 0) {
    throw std::runtime_error("ode: dAllocateODEDataForThread failed");
  }
}

double angle_about_z(const dReal* rotation) { return std::atan2(rotation[4], rotation[0]); }

Vec2 rotate_by_angle(double angle, Vec2 v) {
  const double c = std::cos(angle);
  const double s = std::sin(angle);
  return {c * v.x - s * v.y, s * v.x + c * v.y};
}

Vec2 world_point(const BodySpec& body, Vec2 local) {
  const Vec2 offset = rotate_by_angle(body.angle, local);
  return {body.position.x + offset.x, body.position.y + offset.y};
}

struct BodyRecord {
  dBodyID body = nullptr;  // null for a static body, which is a geom alone
  dGeomID geom = nullptr;
  double friction = 0.0;
  double restitution = 0.0;
};

bool is_dynamic(dBodyID body) { return body != nullptr && dBodyIsKinematic(body) == 0; }

class OdeEngine final : public Engine {
 public:
  OdeEngine() {
    ensure_ode_ready_on_this_thread();
    world_ = dWorldCreate();
    space_ = dHashSpaceCreate(nullptr);
    contact_group_ = dJointGroupCreate(0);
  }
  OdeEngine(const OdeEngine&) = delete;
  OdeEngine& operator=(const OdeEngine&) = delete;

  // The space destroys its geoms and the world its bodies and joints.
  ~OdeEngine() override {
    dJointGroupDestroy(contact_group_);
    dSpaceDestroy(space_);
    dWorldDestroy(world_);
  }

  // ODE times nothing but the whole step.
  std::vector<std::string> phase_names() const override { return {}; }

  void build(const SceneSpec& scene) override {
    if (!bodies_.empty()) throw std::logic_error("ode: build() called twice");
    // Read here, not copied into a namespace-scope constant: ode_capabilities is an inline
    // variable initialised at run time, and another translation unit's copy of it may be made
    // before it is (Clang's build read 0).
    const std::size_t max_bodies = ode_capabilities.max_bodies;
    if (scene.bodies.size() > max_bodies) {
      throw InputError("ode: scene '" + scene.name + "' has " + std::to_string(scene.bodies.size()) +
                       " bodies; the ODE adapter takes at most " + std::to_string(max_bodies) +
                       " (ODE's hash space clears an n x n bit table every step)");
    }
    dt_ = scene.dt;
    dWorldSetGravity(world_, scene.gravity.x, scene.gravity.y, 0.0);
    dWorldSetQuickStepNumIterations(world_, scene.ode.iterations);
    dWorldSetERP(world_, scene.ode.erp);
    dWorldSetCFM(world_, scene.ode.cfm);
    // Bodies copy the world's flag when created, so it is set first; thresholds stay ODE's defaults.
    dWorldSetAutoDisableFlag(world_, scene.ode.auto_disable ? 1 : 0);

    // Sized once: geoms point at their record (dGeomSetData), so it must never move.
    bodies_.resize(scene.bodies.size());
    for (size_t i = 0; i < scene.bodies.size(); ++i) create_body(scene.bodies[i], bodies_[i]);
    for (const JointSpec& joint : scene.joints) create_joint(scene, joint);
    std::ranges::sort(jointed_pairs_);
  }

  void step() override {
    touching_pairs_ = 0;
    dSpaceCollide(space_, this, &OdeEngine::near_callback);
    dRandSetSeed(random_seed_);
    dWorldQuickStep(world_, dt_);
    random_seed_ = dRandGetSeed();
    dJointGroupEmpty(contact_group_);
    flatten_dynamic_bodies();
  }

  void read_phases(std::span<double>) const override {}

  int contact_count() const override { return touching_pairs_; }

  void read_state(std::vector<BodyState>& out) const override {
    out.resize(bodies_.size());
    for (size_t i = 0; i < bodies_.size(); ++i) out[i] = state_of(bodies_[i]);
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
  dGeomID create_geom(const BodySpec& spec) {
    switch (spec.shape) {
      case ShapeKind::circle: return dCreateSphere(space_, spec.radius);
      case ShapeKind::box: return dCreateBox(space_, 2.0 * spec.half_extents.x, 2.0 * spec.half_extents.y, box_depth);
      case ShapeKind::polygon: break;
    }
    throw std::runtime_error(
        "ode: polygons are not supported (ODE 0.16's convex-box collider yields one contact point, so a "
        "polygon cannot rest on a face); use boxes and circles with --engine ode");
  }

  static dMass mass_of(const BodySpec& spec) {
    dMass mass;
    switch (spec.shape) {
      case ShapeKind::circle:
        dMassSetSphereTotal(&mass, spec.material.density * std::numbers::pi * spec.radius * spec.radius, spec.radius);
        return mass;
      case ShapeKind::box:
        dMassSetBox(&mass, spec.material.density / box_depth, 2.0 * spec.half_extents.x,
                    2.0 * spec.half_extents.y, box_depth);
        return mass;
      case ShapeKind::polygon: break;
    }
    throw std::logic_error("ode: create_geom() lets no polygon through");
  }

  void create_body(const BodySpec& spec, BodyRecord& record) {
    record.friction = spec.material.dynamic_friction;
    record.restitution = spec.material.restitution;
    record.geom = create_geom(spec);
    dGeomSetData(record.geom, &record);

    // Box and sphere have their centre of mass at the geometric centre, which ODE requires of the
    // body frame, so the body frame is the spec's body origin.
    dMatrix3 rotation;
    dRFromAxisAndAngle(rotation, 0, 0, 1, spec.angle);
    if (spec.type == BodyType::static_body) {
      dGeomSetPosition(record.geom, spec.position.x, spec.position.y, 0);
      dGeomSetRotation(record.geom, rotation);
      return;
    }
    record.body = dBodyCreate(world_);
    dBodySetPosition(record.body, spec.position.x, spec.position.y, 0);
    dBodySetRotation(record.body, rotation);
    dBodySetLinearVel(record.body, spec.linear_velocity.x, spec.linear_velocity.y, 0);
    dBodySetAngularVel(record.body, 0, 0, spec.angular_velocity);
    dGeomSetBody(record.geom, record.body);
    if (spec.type == BodyType::kinematic) {
      dBodySetKinematic(record.body);
      return;
    }
    const dMass mass = mass_of(spec);
    dBodySetMass(record.body, &mass);
    dJointAttach(dJointCreatePlane2D(world_, nullptr), record.body, nullptr);
  }

  void create_joint(const SceneSpec& scene, const JointSpec& spec) {
    for (const int index : {spec.body_a, spec.body_b}) {
      if (index < 0 || static_cast<size_t>(index) >= bodies_.size()) {
        throw std::runtime_error("ode: joint names body " + std::to_string(index) + ", which does not exist");
      }
    }
    const auto a = static_cast<size_t>(spec.body_a);
    const auto b = static_cast<size_t>(spec.body_b);
    jointed_pairs_.push_back(ordered_pair(a, b));
    const Vec2 anchor_a = world_point(scene.bodies[a], spec.local_anchor_a);
    const Vec2 anchor_b = world_point(scene.bodies[b], spec.local_anchor_b);
    dBodyID body_a = bodies_[a].body;
    dBodyID body_b = bodies_[b].body;
    if (body_a == nullptr && body_b == nullptr) throw std::runtime_error("ode: a joint between two static bodies");

    // A missing second body is the static world to every ODE joint; giving the first one a body
    // keeps the adapter clear of ODE's reversed-joint handling.
    const bool swap = body_a == nullptr;
    dBodyID first = swap ? body_b : body_a;
    dBodyID second = swap ? body_a : body_b;
    const Vec2 first_anchor = swap ? anchor_b : anchor_a;
    const Vec2 second_anchor = swap ? anchor_a : anchor_b;
    switch (spec.kind) {
      case JointKind::distance: {
        dJointID joint = dJointCreateDBall(world_, nullptr);
        dJointAttach(joint, first, second);
        dJointSetDBallAnchor1(joint, first_anchor.x, first_anchor.y, 0);
        dJointSetDBallAnchor2(joint, second_anchor.x, second_anchor.y, 0);
        const double as_built = std::hypot(anchor_b.x - anchor_a.x, anchor_b.y - anchor_a.y);
        dJointSetDBallDistance(joint, spec.length >= 0.0 ? spec.length : as_built);
        return;
      }
      case JointKind::revolute: {
        dJointID joint = dJointCreateHinge(world_, nullptr);
        dJointAttach(joint, first, second);
        dJointSetHingeAnchor(joint, first_anchor.x, first_anchor.y, 0);
        dJointSetHingeAxis(joint, 0, 0, 1);
        return;
      }
    }
  }

  // Jointed bodies do not collide, as in Box2D (collideConnected = false). ODE's own
  // dAreConnected cannot tell one static body from another, so the adapter keeps the pairs.
  bool are_jointed(const BodyRecord& a, const BodyRecord& b) const {
    if (jointed_pairs_.empty()) return false;
    return std::ranges::binary_search(jointed_pairs_, ordered_pair(index_of(a), index_of(b)));
  }

  size_t index_of(const BodyRecord& record) const { return static_cast<size_t>(&record - bodies_.data()); }

  static std::pair<size_t, size_t> ordered_pair(size_t a, size_t b) { return std::minmax(a, b); }

  static void near_callback(void* engine, dGeomID a, dGeomID b) {
    static_cast<OdeEngine*>(engine)->collide_pair(a, b);
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
      dContact& contact = contacts[static_cast<size_t>(i)];
      contact.surface = surface;
      dJointAttach(dJointCreateContact(world_, contact_group_, &contact), body_a, body_b);
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

  static BodyState state_of(const BodyRecord& record) {
    if (record.body == nullptr) {
      const dReal* p = dGeomGetPosition(record.geom);
      return BodyState{{p[0], p[1]}, angle_about_z(dGeomGetRotation(record.geom)), {}, 0.0};
    }
    const dReal* p = dBodyGetPosition(record.body);
    const dReal* v = dBodyGetLinearVel(record.body);
    return BodyState{{p[0], p[1]}, angle_about_z(dBodyGetRotation(record.body)), {v[0], v[1]},
                     dBodyGetAngularVel(record.body)[2]};
  }

  dWorldID world_ = nullptr;
  dSpaceID space_ = nullptr;
  dJointGroupID contact_group_ = nullptr;
  std::vector<BodyRecord> bodies_;
  double dt_ = 0.0;
  std::vector<std::pair<size_t, size_t>> jointed_pairs_;  // sorted (lower, higher) body indices
  int touching_pairs_ = 0;  // geom pairs with at least one contact point in the last step
  unsigned long random_seed_ = 0;  // this world's state of ODE's shared generator, between steps
};

}  // namespace

std::unique_ptr<Engine> make_ode_engine() { return std::make_unique<OdeEngine>(); }

OutOfPlaneDrift ode_out_of_plane_drift(const Engine& engine) {
  const auto* ode = dynamic_cast<const OdeEngine*>(&engine);
  if (ode == nullptr) throw std::invalid_argument("ode_out_of_plane_drift: not an ODE engine");
  return ode->drift();
}

}  // namespace fxbench
