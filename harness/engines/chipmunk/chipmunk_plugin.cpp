// Chipmunk2D 7 behind the plugin C ABI (plugin/fx2d_plugin_abi.h), written with the SDK's C++ layer
// (fx2d_bench_plugin.hpp): fx2d-bench's fourth engine, and the proof that an engine adapter is one
// small class.
//
// Mapping: dynamic bodies take their mass and inertia from their shapes' density (Chipmunk finds
// the centre of gravity; positions read back are body origins, as the scene's); one friction,
// the dynamic one, given as its square root so that Chipmunk's product of two shapes' frictions is
// their geometric mean, as in Box2D; restitution as Chipmunk combines it (the product); distance
// joints are pin joints, revolute joints pivot joints at body A's anchor in the world.
// Chipmunk's defaults are tuned for pixels: the collision slop is a knob in metres instead.
#include <chipmunk/chipmunk.h>

#include <fcntl.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "fx2d_bench_plugin.hpp"

namespace {

// Debian's Chipmunk is a debug build (runtime assertions on), which prints a banner on stdout at
// its first space. stdout is fx2d-bench's data (JSON, tables) and stderr says only what went wrong,
// so that first space is made with stdout sent to /dev/null.
cpSpace* new_space() {
  static const bool banner_dropped = [] {
    std::fflush(stdout);
    const int saved = dup(STDOUT_FILENO);
    const int null = open("/dev/null", O_WRONLY);
    dup2(null, STDOUT_FILENO);
    cpSpaceFree(cpSpaceNew());
    std::fflush(stdout);
    dup2(saved, STDOUT_FILENO);
    close(null);
    close(saved);
    return true;
  }();
  return banner_dropped ? cpSpaceNew() : nullptr;
}

enum Knob { iterations, sleeping, sleep_time, collision_slop, knob_count };

constexpr Fx2dBenchKnob knobs[knob_count] = {
    {"iterations", FX2D_BENCH_KNOB_INTEGER, 1, 1000, 10, "solver iterations per step (cpSpaceSetIterations)"},
    {"sleeping", FX2D_BENCH_KNOB_BOOLEAN, 0, 1, 1, "let resting bodies sleep"},
    {"sleep_time", FX2D_BENCH_KNOB_NUMBER, 0.01, 100, 0.5, "seconds idle before a body sleeps, s"},
    {"collision_slop", FX2D_BENCH_KNOB_NUMBER, 0, 1, 0.005, "overlap allowed between shapes, m"},
};

cpVect to_cp(Fx2dBenchVec2 v) { return cpv(v.x, v.y); }

cpBody* make_body(const Fx2dBenchBody& spec) {
  switch (spec.type) {
    case FX2D_BENCH_STATIC_BODY:
      return cpBodyNewStatic();
    case FX2D_BENCH_KINEMATIC_BODY:
      return cpBodyNewKinematic();
    case FX2D_BENCH_DYNAMIC_BODY:
      return cpBodyNew(0.0, 0.0);  // mass and inertia from the shape's density
    default:
      throw std::invalid_argument("unknown body type " + std::to_string(spec.type));
  }
}

cpShape* make_shape(cpBody* body, const Fx2dBenchBody& spec) {
  switch (spec.shape) {
    case FX2D_BENCH_CIRCLE:
      return cpCircleShapeNew(body, spec.radius, cpvzero);
    case FX2D_BENCH_BOX:
      return cpBoxShapeNew(body, 2.0 * spec.half_extents.x, 2.0 * spec.half_extents.y, 0.0);
    case FX2D_BENCH_POLYGON: {
      std::vector<cpVect> vertices;
      for (int32_t i = 0; i < spec.vertex_count; ++i) vertices.push_back(to_cp(spec.vertices[i]));
      return cpPolyShapeNew(body, spec.vertex_count, vertices.data(), cpTransformIdentity, 0.0);
    }
    default:
      throw std::invalid_argument("unknown shape kind " + std::to_string(spec.shape));
  }
}

// What Chipmunk allocated for one scene, freed even when building it failed part way. The space
// first: freeing it touches none of its children, which are then freed one by one (removing each
// from the space would cost a linear search per body).
struct ChipmunkObjects {
  cpSpace* space = new_space();
  std::vector<cpBody*> bodies;  // in the scene's order
  std::vector<cpShape*> shapes;
  std::vector<cpConstraint*> joints;

  ChipmunkObjects() = default;
  ChipmunkObjects(const ChipmunkObjects&) = delete;
  ChipmunkObjects& operator=(const ChipmunkObjects&) = delete;
  ~ChipmunkObjects() {
    cpSpaceFree(space);
    for (cpConstraint* joint : joints) cpConstraintFree(joint);
    for (cpShape* shape : shapes) cpShapeFree(shape);
    for (cpBody* body : bodies) cpBodyFree(body);
  }
};

class ChipmunkWorld {
 public:
  explicit ChipmunkWorld(const Fx2dBenchScene& scene) : dt_(scene.dt) {
    const double* knob = scene.settings;
    cpSpaceSetGravity(chipmunk_.space, to_cp(scene.gravity));
    cpSpaceSetIterations(chipmunk_.space, static_cast<int>(knob[iterations]));
    cpSpaceSetSleepTimeThreshold(chipmunk_.space, knob[sleeping] != 0.0 ? knob[sleep_time] : INFINITY);
    cpSpaceSetCollisionSlop(chipmunk_.space, knob[collision_slop]);
    for (int32_t i = 0; i < scene.body_count; ++i) add_body(scene.bodies[i]);
    for (int32_t i = 0; i < scene.joint_count; ++i) {
      chipmunk_.joints.push_back(make_joint(scene.joints[i]));
      cpSpaceAddConstraint(chipmunk_.space, chipmunk_.joints.back());
    }
  }

  void step() { cpSpaceStep(chipmunk_.space, dt_); }

  // Touching pairs of bodies (one shape per body here), sleeping ones included: each arbiter is
  // seen from both its bodies but counted from one, the static one never being walked.
  int32_t contact_count() const {
    int32_t count = 0;
    for (cpBody* body : chipmunk_.bodies) {
      if (cpBodyGetType(body) == CP_BODY_TYPE_STATIC) continue;
      cpBodyEachArbiter(
          body,
          [](cpBody* self, cpArbiter* arbiter, void* data) {
            cpBody* first = nullptr;
            cpBody* other = nullptr;
            cpArbiterGetBodies(arbiter, &first, &other);  // `first` is `self`
            const bool counted_here = cpBodyGetType(other) == CP_BODY_TYPE_STATIC || self < other;
            if (counted_here && cpArbiterGetCount(arbiter) > 0) ++*static_cast<int32_t*>(data);
          },
          &count);
    }
    return count;
  }

  void read_state(Fx2dBenchBodyState* out, int32_t count) const {
    for (std::size_t i = 0; i < chipmunk_.bodies.size() && static_cast<int32_t>(i) < count; ++i) {
      const cpBody* body = chipmunk_.bodies[i];
      const cpVect position = cpBodyGetPosition(body);
      const cpVect velocity = cpBodyGetVelocity(body);
      out[i] = {{position.x, position.y},
                cpBodyGetAngle(body),
                {velocity.x, velocity.y},
                cpBodyGetAngularVelocity(body)};
    }
  }

 private:
  void add_body(const Fx2dBenchBody& spec) {
    cpBody* body = make_body(spec);
    chipmunk_.bodies.push_back(body);
    cpBodySetPosition(body, to_cp(spec.position));
    cpBodySetAngle(body, spec.angle);
    cpShape* shape = make_shape(body, spec);
    chipmunk_.shapes.push_back(shape);
    if (spec.type == FX2D_BENCH_DYNAMIC_BODY) cpShapeSetDensity(shape, spec.density);
    cpShapeSetFriction(shape, std::sqrt(spec.dynamic_friction));
    cpShapeSetElasticity(shape, spec.restitution);
    cpSpaceAddBody(chipmunk_.space, body);
    cpSpaceAddShape(chipmunk_.space, shape);
    if (spec.type != FX2D_BENCH_STATIC_BODY) {
      cpBodySetVelocity(body, to_cp(spec.linear_velocity));
      cpBodySetAngularVelocity(body, spec.angular_velocity);
    }
  }

  cpConstraint* make_joint(const Fx2dBenchJoint& spec) const {
    cpBody* a = fx2d_bench::joint_body(chipmunk_.bodies, spec.body_a);
    cpBody* b = fx2d_bench::joint_body(chipmunk_.bodies, spec.body_b);
    if (spec.kind == FX2D_BENCH_REVOLUTE_JOINT)
      return cpPivotJointNew(a, b, cpBodyLocalToWorld(a, to_cp(spec.local_anchor_a)));
    cpConstraint* pin = cpPinJointNew(a, b, to_cp(spec.local_anchor_a), to_cp(spec.local_anchor_b));
    if (spec.length >= 0.0) cpPinJointSetDist(pin, spec.length);
    return pin;
  }

  ChipmunkObjects chipmunk_;
  double dt_;
};

constexpr fx2d_bench::EngineDescription chipmunk{
    .name = "chipmunk",
    .library_version = [] { return cpVersionString; },
    .knobs = knobs,
    .capabilities = {FX2D_BENCH_BIT(FX2D_BENCH_CIRCLE) | FX2D_BENCH_BIT(FX2D_BENCH_BOX) |
                         FX2D_BENCH_BIT(FX2D_BENCH_POLYGON),
                     FX2D_BENCH_BIT(FX2D_BENCH_DISTANCE_JOINT) | FX2D_BENCH_BIT(FX2D_BENCH_REVOLUTE_JOINT), 1, 0, 0,
                     0.0},
};

}  // namespace

FX2D_BENCH_EXPORT_PLUGIN(ChipmunkWorld, chipmunk)
