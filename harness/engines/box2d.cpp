// The Box2D 2.4.1 adapter: builds a SceneSpec as one b2Body with one fixture per spec body and
// steps it with b2World::Step.
//
// Invariant: bodies_[i] is the b2Body of scene.bodies[i], so every read is in spec order.
// Box2D is single precision: doubles are rounded once, at build, and widened again on read.
// Box2D has one friction coefficient per fixture; it gets the spec's dynamic friction. It mixes
// a pair's materials as sqrt(f1 * f2) for friction and max(r1, r2) for restitution, and applies
// restitution only above 1 m/s of approach speed (b2_velocityThreshold).
// Velocities read and written here are those of the body origin, matching the pose, not of the
// centre of mass that b2Body::GetLinearVelocity() returns (they differ for off-centre polygons).
#include <box2d/box2d.h>

#include <array>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "engines/engines.h"

namespace fxbench {
namespace {

b2Vec2 to_b2(Vec2 v) { return {static_cast<float>(v.x), static_cast<float>(v.y)}; }

b2BodyType to_b2(BodyType type) {
  switch (type) {
    case BodyType::static_body: return b2_staticBody;
    case BodyType::kinematic: return b2_kinematicBody;
    case BodyType::dynamic: return b2_dynamicBody;
  }
  throw std::runtime_error("box2d: unknown body type");
}

// Box2D's polygon takes at most b2_maxPolygonVertices points and makes their convex hull itself.
b2PolygonShape make_polygon(const std::vector<Vec2>& vertices) {
  const auto count = static_cast<int>(vertices.size());
  if (count < 3 || count > b2_maxPolygonVertices) {
    throw std::runtime_error("box2d: a polygon needs 3 to " + std::to_string(b2_maxPolygonVertices) +
                             " vertices, got " + std::to_string(count));
  }
  std::array<b2Vec2, b2_maxPolygonVertices> points{};
  for (int i = 0; i < count; ++i) points[static_cast<size_t>(i)] = to_b2(vertices[static_cast<size_t>(i)]);
  b2PolygonShape polygon;
  polygon.Set(points.data(), count);
  return polygon;
}

void add_fixture(b2Body& body, const BodySpec& spec) {
  b2FixtureDef fixture;
  fixture.density = static_cast<float>(spec.material.density);
  fixture.friction = static_cast<float>(spec.material.dynamic_friction);
  fixture.restitution = static_cast<float>(spec.material.restitution);
  switch (spec.shape) {
    case ShapeKind::circle: {
      b2CircleShape circle;
      circle.m_radius = static_cast<float>(spec.radius);
      fixture.shape = &circle;
      body.CreateFixture(&fixture);
      return;
    }
    case ShapeKind::box: {
      b2PolygonShape box;
      box.SetAsBox(static_cast<float>(spec.half_extents.x), static_cast<float>(spec.half_extents.y));
      fixture.shape = &box;
      body.CreateFixture(&fixture);
      return;
    }
    case ShapeKind::polygon: {
      const b2PolygonShape polygon = make_polygon(spec.vertices);
      fixture.shape = &polygon;
      body.CreateFixture(&fixture);
      return;
    }
  }
}

class Box2dEngine final : public Engine {
 public:
  // The disjoint parts of b2Profile. Its `solve` is the sum of the three solve_* phases, island
  // building and `broadphase` (which Box2D runs inside Solve); its `step` is the total. Both are
  // left out so that the listed phases never count a millisecond twice.
  std::vector<std::string> phase_names() const override {
    return {"collide", "solve_init", "solve_velocity", "solve_position", "broadphase", "solve_toi"};
  }

  void build(const SceneSpec& scene) override {
    if (world_) throw std::logic_error("box2d: build() called twice");
    world_ = std::make_unique<b2World>(to_b2(scene.gravity));
    world_->SetAllowSleeping(scene.box2d.sleeping);
    dt_ = static_cast<float>(scene.dt);
    velocity_iterations_ = scene.box2d.velocity_iterations;
    position_iterations_ = scene.box2d.position_iterations;

    bodies_.reserve(scene.bodies.size());
    for (const BodySpec& spec : scene.bodies) bodies_.push_back(create_body(spec));
    for (const JointSpec& joint : scene.joints) create_joint(joint);
  }

  void step() override { world_->Step(dt_, velocity_iterations_, position_iterations_); }

  void read_phases(std::span<double> ms) const override {
    const b2Profile& profile = world_->GetProfile();
    const std::array<float, 6> phases = {profile.collide,       profile.solveInit,
                                         profile.solveVelocity, profile.solvePosition,
                                         profile.broadphase,    profile.solveTOI};
    for (size_t i = 0; i < phases.size() && i < ms.size(); ++i) ms[i] = phases[i];
  }

  int contact_count() const override {
    int touching = 0;
    for (const b2Contact* contact = world_->GetContactList(); contact != nullptr; contact = contact->GetNext()) {
      if (contact->IsTouching()) ++touching;
    }
    return touching;
  }

  void read_state(std::vector<BodyState>& out) const override {
    out.resize(bodies_.size());
    for (size_t i = 0; i < bodies_.size(); ++i) {
      const b2Body& body = *bodies_[i];
      const b2Vec2 position = body.GetPosition();
      const b2Vec2 velocity = body.GetLinearVelocityFromLocalPoint(b2Vec2_zero);
      out[i] = BodyState{{position.x, position.y}, body.GetAngle(), {velocity.x, velocity.y},
                         body.GetAngularVelocity()};
    }
  }

 private:
  b2Body* create_body(const BodySpec& spec) {
    b2BodyDef def;
    def.type = to_b2(spec.type);
    def.position = to_b2(spec.position);
    def.angle = static_cast<float>(spec.angle);
    // Box2D keeps the velocity of the body origin when a fixture moves the centre of mass, so
    // the spec's origin velocity can be given before the fixture exists.
    def.linearVelocity = to_b2(spec.linear_velocity);
    def.angularVelocity = static_cast<float>(spec.angular_velocity);
    def.bullet = spec.bullet;
    b2Body* body = world_->CreateBody(&def);
    add_fixture(*body, spec);
    return body;
  }

  b2Body* body_at(int index) const {
    if (index < 0 || static_cast<size_t>(index) >= bodies_.size()) {
      throw std::runtime_error("box2d: joint names body " + std::to_string(index) + ", which does not exist");
    }
    return bodies_[static_cast<size_t>(index)];
  }

  void create_joint(const JointSpec& spec) {
    b2Body* body_a = body_at(spec.body_a);
    b2Body* body_b = body_at(spec.body_b);
    switch (spec.kind) {
      case JointKind::distance: {
        b2DistanceJointDef def;
        def.bodyA = body_a;
        def.bodyB = body_b;
        def.localAnchorA = to_b2(spec.local_anchor_a);
        def.localAnchorB = to_b2(spec.local_anchor_b);
        def.length = spec.length >= 0.0
                         ? static_cast<float>(spec.length)
                         : b2Distance(body_a->GetWorldPoint(def.localAnchorA), body_b->GetWorldPoint(def.localAnchorB));
        // Equal limits and no stiffness make the rod rigid rather than a spring.
        def.minLength = def.length;
        def.maxLength = def.length;
        def.stiffness = 0.0f;
        def.damping = 0.0f;
        world_->CreateJoint(&def);
        return;
      }
      case JointKind::revolute: {
        b2RevoluteJointDef def;
        def.bodyA = body_a;
        def.bodyB = body_b;
        def.localAnchorA = to_b2(spec.local_anchor_a);
        def.localAnchorB = to_b2(spec.local_anchor_b);
        def.referenceAngle = body_b->GetAngle() - body_a->GetAngle();
        world_->CreateJoint(&def);
        return;
      }
    }
  }

  std::unique_ptr<b2World> world_;  // owns every body, fixture and joint
  std::vector<b2Body*> bodies_;
  float dt_ = 0.0f;
  int velocity_iterations_ = 0;
  int position_iterations_ = 0;
};

}  // namespace

std::unique_ptr<Engine> make_box2d_engine() { return std::make_unique<Box2dEngine>(); }

}  // namespace fxbench
