// Box2D 2.4.1 behind the plugin C ABI (plugin/fx2d_plugin_abi.h), written with the SDK's C++ layer
// (plugin/fx2d_bench_plugin.hpp) and linked into fx2d-bench as the built-in "box2d" engine, so that
// the plugin engine (plugin_engine.h) is the one place a SceneSpec is converted for any engine.
//
// Mapping: one b2Body with one fixture per scene body, bodies_[i] being scene body i, so every
// read is in scene order. Box2D is single precision: doubles are rounded once, at build, and
// widened again on read. One friction per fixture, the dynamic one; Box2D mixes a pair's
// materials as sqrt(f1 * f2) for friction and max(r1, r2) for restitution, and applies restitution
// only above 1 m/s of approach speed (b2_velocityThreshold). Velocities read and written here are
// those of the body origin, matching the pose, not of the centre of mass that
// b2Body::GetLinearVelocity() returns (they differ for off-centre polygons).
#include <box2d/box2d.h>

#include <algorithm>
#include <array>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "engines/engines.h"
#include "engines/plugin_engine.h"
#include "plugin/fx2d_bench_plugin.hpp"

namespace fxbench {
namespace {

enum Knob { velocity_iterations, position_iterations, sleeping, knob_count };

constexpr Fx2dBenchKnob knobs[knob_count] = {
    {"velocity_iterations", FX2D_BENCH_KNOB_INTEGER, 1, 1000, 8,
     "velocity iterations per step (b2World::Step)"},
    {"position_iterations", FX2D_BENCH_KNOB_INTEGER, 0, 1000, 3,
     "position iterations per step (b2World::Step)"},
    {"sleeping", FX2D_BENCH_KNOB_BOOLEAN, 0, 1, 1, "let resting bodies sleep"},
};

b2Vec2 to_b2(Fx2dBenchVec2 v) { return {static_cast<float>(v.x), static_cast<float>(v.y)}; }

// The SDK's create() lets through only known body types.
b2BodyType body_type(int32_t type) {
  if (type == FX2D_BENCH_STATIC_BODY) return b2_staticBody;
  if (type == FX2D_BENCH_KINEMATIC_BODY) return b2_kinematicBody;
  return b2_dynamicBody;
}

// Box2D's polygon takes at most b2_maxPolygonVertices points and makes their convex hull itself.
b2PolygonShape make_polygon(const Fx2dBenchBody& body) {
  if (body.vertex_count < 3 || body.vertex_count > b2_maxPolygonVertices) {
    throw std::invalid_argument("a polygon needs 3 to " + std::to_string(b2_maxPolygonVertices) +
                                " vertices, got " + std::to_string(body.vertex_count));
  }
  const std::vector<b2Vec2> points = fx2d_bench::vertices(body, to_b2);
  b2PolygonShape polygon;
  polygon.Set(points.data(), body.vertex_count);
  return polygon;
}

// Creates the body's one fixture; the shape is copied by CreateFixture.
void add_fixture(b2Body& body, const Fx2dBenchBody& spec) {
  b2FixtureDef fixture;
  fixture.density = static_cast<float>(spec.density);
  fixture.friction = static_cast<float>(spec.dynamic_friction);
  fixture.restitution = static_cast<float>(spec.restitution);
  b2CircleShape circle;
  b2PolygonShape polygon;
  if (spec.shape == FX2D_BENCH_CIRCLE) {
    circle.m_radius = static_cast<float>(spec.radius);
    fixture.shape = &circle;
  } else if (spec.shape == FX2D_BENCH_BOX) {
    polygon.SetAsBox(static_cast<float>(spec.half_extents.x), static_cast<float>(spec.half_extents.y));
    fixture.shape = &polygon;
  } else {
    polygon = make_polygon(spec);
    fixture.shape = &polygon;
  }
  body.CreateFixture(&fixture);
}

class Box2dWorld {
 public:
  explicit Box2dWorld(const Fx2dBenchScene& scene)
      : world_(std::make_unique<b2World>(to_b2(scene.gravity))),
        dt_(static_cast<float>(scene.dt)),
        velocity_iterations_(static_cast<int>(scene.settings[velocity_iterations])),
        position_iterations_(static_cast<int>(scene.settings[position_iterations])) {
    world_->SetAllowSleeping(scene.settings[sleeping] != 0.0);
    bodies_.reserve(static_cast<std::size_t>(scene.body_count));
    for (int32_t i = 0; i < scene.body_count; ++i) bodies_.push_back(create_body(scene.bodies[i]));
    for (int32_t i = 0; i < scene.joint_count; ++i) create_joint(scene.joints[i]);
  }

  void step() { world_->Step(dt_, velocity_iterations_, position_iterations_); }

  // The disjoint parts of b2Profile. Its `solve` is the sum of the three solve_* phases, island
  // building and `broadphase` (which Box2D runs inside Solve); its `step` is the total. Both are
  // left out so that the listed phases never count a millisecond twice.
  static int32_t phase_count() { return static_cast<int32_t>(phase_names.size()); }
  static const char* phase_name(int32_t phase) {
    return phase >= 0 && phase < phase_count() ? phase_names[static_cast<std::size_t>(phase)] : "";
  }
  void read_phases(double* ms, int32_t count) const {
    const b2Profile& profile = world_->GetProfile();
    const std::array<float, 6> phases = {profile.collide,       profile.solveInit,  profile.solveVelocity,
                                         profile.solvePosition, profile.broadphase, profile.solveTOI};
    for (int32_t i = 0; i < std::min(count, phase_count()); ++i) ms[i] = phases[static_cast<std::size_t>(i)];
  }

  int32_t contact_count() const {
    int32_t touching = 0;
    for (const b2Contact* contact = world_->GetContactList(); contact != nullptr;
         contact = contact->GetNext()) {
      if (contact->IsTouching()) ++touching;
    }
    return touching;
  }

  Fx2dBenchBodyState body_state(std::size_t index) const {
    const b2Body& body = *bodies_[index];
    const b2Vec2 position = body.GetPosition();
    const b2Vec2 velocity = body.GetLinearVelocityFromLocalPoint(b2Vec2_zero);
    return {{position.x, position.y}, body.GetAngle(), {velocity.x, velocity.y}, body.GetAngularVelocity()};
  }

 private:
  static constexpr std::array<const char*, 6> phase_names = {"collide",        "solve_init", "solve_velocity",
                                                             "solve_position", "broadphase", "solve_toi"};

  b2Body* create_body(const Fx2dBenchBody& spec) {
    b2BodyDef def;
    def.type = body_type(spec.type);
    def.position = to_b2(spec.position);
    def.angle = static_cast<float>(spec.angle);
    // Box2D keeps the velocity of the body origin when a fixture moves the centre of mass, so
    // the scene's origin velocity can be given before the fixture exists.
    def.linearVelocity = to_b2(spec.linear_velocity);
    def.angularVelocity = static_cast<float>(spec.angular_velocity);
    def.bullet = spec.bullet != 0;
    b2Body* body = world_->CreateBody(&def);
    add_fixture(*body, spec);
    return body;
  }

  void create_joint(const Fx2dBenchJoint& spec) {
    b2Body* body_a = fx2d_bench::joint_body(bodies_, spec.body_a);
    b2Body* body_b = fx2d_bench::joint_body(bodies_, spec.body_b);
    if (spec.kind == FX2D_BENCH_DISTANCE_JOINT) {
      b2DistanceJointDef def;
      def.bodyA = body_a;
      def.bodyB = body_b;
      def.localAnchorA = to_b2(spec.local_anchor_a);
      def.localAnchorB = to_b2(spec.local_anchor_b);
      def.length = spec.length >= 0.0 ? static_cast<float>(spec.length)
                                      : b2Distance(body_a->GetWorldPoint(def.localAnchorA),
                                                   body_b->GetWorldPoint(def.localAnchorB));
      // Equal limits and no stiffness make the rod rigid rather than a spring.
      def.minLength = def.length;
      def.maxLength = def.length;
      def.stiffness = 0.0f;
      def.damping = 0.0f;
      world_->CreateJoint(&def);
      return;
    }
    b2RevoluteJointDef def;
    def.bodyA = body_a;
    def.bodyB = body_b;
    def.localAnchorA = to_b2(spec.local_anchor_a);
    def.localAnchorB = to_b2(spec.local_anchor_b);
    def.referenceAngle = body_b->GetAngle() - body_a->GetAngle();
    world_->CreateJoint(&def);
  }

  std::unique_ptr<b2World> world_;  // owns every body, fixture and joint; on the heap, as they point to it
  std::vector<b2Body*> bodies_;
  float dt_;
  int velocity_iterations_;
  int position_iterations_;
};

const fx2d_bench::EngineDescription box2d_engine{
    .name = "box2d",
    .library_version = [] { return FX2D_BENCH_BOX2D_VERSION; },
    .knobs = knobs,
    .capabilities = {fx2d_bench::all_shapes, fx2d_bench::all_joints, 1, 1, 0, 0.0},
};

std::shared_ptr<const Plugin> linked_box2d_plugin() {
  static const Fx2dBenchPlugin table = fx2d_bench::plugin_table<Box2dWorld, box2d_engine>();
  static const std::shared_ptr<const Plugin> linked = Plugin::linked(table);
  return linked;
}

}  // namespace

std::unique_ptr<Engine> make_box2d_engine() { return make_plugin_engine(linked_box2d_plugin()); }

// The table is linked in, so no library needs holding: the entry makes engines with the plain factory.
EngineInfo box2d_engine_info() {
  EngineInfo info = plugin_engine_info(linked_box2d_plugin(), "box2d");
  info.make = &make_box2d_engine;
  return info;
}

}  // namespace fxbench
