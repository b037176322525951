// Chipmunk2D 7 behind the plugin C ABI (plugin/fx2d_plugin_abi.h): fx2d-bench's fourth engine,
// and the proof that an engine adapter is one small file against that header alone.
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
#include <exception>
#include <stdexcept>
#include <string>
#include <vector>

#include "fx2d_plugin_abi.h"

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

}  // namespace

struct Fx2dBenchInstance {
  cpSpace* space = new_space();
  std::vector<cpBody*> bodies;  // in the scene's order
  std::vector<cpShape*> shapes;
  std::vector<cpConstraint*> joints;
  double dt = 0.0;

  Fx2dBenchInstance() = default;
  Fx2dBenchInstance(const Fx2dBenchInstance&) = delete;
  Fx2dBenchInstance& operator=(const Fx2dBenchInstance&) = delete;
  // The space first: freeing it touches none of its children, which are then freed one by one
  // (removing each from the space would cost a linear search per body).
  ~Fx2dBenchInstance() {
    cpSpaceFree(space);
    for (cpConstraint* joint : joints) cpConstraintFree(joint);
    for (cpShape* shape : shapes) cpShapeFree(shape);
    for (cpBody* body : bodies) cpBodyFree(body);
  }
};

namespace {

enum Knob { iterations, sleeping, sleep_time, collision_slop, knob_count };

const Fx2dBenchKnob knobs[knob_count] = {
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

void add_body(Fx2dBenchInstance& instance, const Fx2dBenchBody& spec) {
  cpBody* body = make_body(spec);
  instance.bodies.push_back(body);
  cpBodySetPosition(body, to_cp(spec.position));
  cpBodySetAngle(body, spec.angle);
  cpShape* shape = make_shape(body, spec);
  instance.shapes.push_back(shape);
  if (spec.type == FX2D_BENCH_DYNAMIC_BODY) cpShapeSetDensity(shape, spec.density);
  cpShapeSetFriction(shape, std::sqrt(spec.dynamic_friction));
  cpShapeSetElasticity(shape, spec.restitution);
  cpSpaceAddBody(instance.space, body);
  cpSpaceAddShape(instance.space, shape);
  if (spec.type != FX2D_BENCH_STATIC_BODY) {
    cpBodySetVelocity(body, to_cp(spec.linear_velocity));
    cpBodySetAngularVelocity(body, spec.angular_velocity);
  }
}

cpConstraint* make_joint(const Fx2dBenchInstance& instance, const Fx2dBenchJoint& spec) {
  const auto body = [&](int32_t index) {
    if (index < 0 || static_cast<std::size_t>(index) >= instance.bodies.size())
      throw std::invalid_argument("joint body index " + std::to_string(index) + " out of range");
    return instance.bodies[static_cast<std::size_t>(index)];
  };
  cpBody* a = body(spec.body_a);
  cpBody* b = body(spec.body_b);
  if (spec.kind == FX2D_BENCH_REVOLUTE_JOINT)
    return cpPivotJointNew(a, b, cpBodyLocalToWorld(a, to_cp(spec.local_anchor_a)));
  cpConstraint* pin = cpPinJointNew(a, b, to_cp(spec.local_anchor_a), to_cp(spec.local_anchor_b));
  if (spec.length >= 0.0) cpPinJointSetDist(pin, spec.length);
  return pin;
}

void build(Fx2dBenchInstance& instance, const Fx2dBenchScene& scene) {
  if (scene.setting_count != knob_count) throw std::invalid_argument("expected one setting per knob");
  const double* knob = scene.settings;
  instance.dt = scene.dt;
  cpSpaceSetGravity(instance.space, to_cp(scene.gravity));
  cpSpaceSetIterations(instance.space, static_cast<int>(knob[iterations]));
  cpSpaceSetSleepTimeThreshold(instance.space, knob[sleeping] != 0.0 ? knob[sleep_time] : INFINITY);
  cpSpaceSetCollisionSlop(instance.space, knob[collision_slop]);
  for (int32_t i = 0; i < scene.body_count; ++i) add_body(instance, scene.bodies[i]);
  for (int32_t i = 0; i < scene.joint_count; ++i) {
    instance.joints.push_back(make_joint(instance, scene.joints[i]));
    cpSpaceAddConstraint(instance.space, instance.joints.back());
  }
}

// --- the table --------------------------------------------------------------------------------

const char* library_version() { return cpVersionString; }

const char* build_description() { return ""; }

Fx2dBenchInstance* create(const Fx2dBenchScene* scene, char* error, size_t error_size) {
  auto* instance = new Fx2dBenchInstance;
  try {
    build(*instance, *scene);
    return instance;
  } catch (const std::exception& failure) {
    std::snprintf(error, error_size, "chipmunk plugin: %s", failure.what());
  }
  delete instance;
  return nullptr;
}

void destroy(Fx2dBenchInstance* instance) { delete instance; }

void step(Fx2dBenchInstance* instance) { cpSpaceStep(instance->space, instance->dt); }

int32_t phase_count() { return 0; }
const char* phase_name(int32_t) { return ""; }
void read_phases(const Fx2dBenchInstance*, double*, int32_t) {}

// Touching pairs of bodies (one shape per body here), sleeping ones included: each arbiter is
// seen from both its bodies but counted from one, the static one never being walked.
int32_t contact_count(const Fx2dBenchInstance* instance) {
  int32_t count = 0;
  for (cpBody* body : instance->bodies) {
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

void read_state(const Fx2dBenchInstance* instance, Fx2dBenchBodyState* out, int32_t count) {
  for (std::size_t i = 0; i < instance->bodies.size() && static_cast<int32_t>(i) < count; ++i) {
    const cpBody* body = instance->bodies[i];
    const cpVect position = cpBodyGetPosition(body);
    const cpVect velocity = cpBodyGetVelocity(body);
    out[i] = {{position.x, position.y},
              cpBodyGetAngle(body),
              {velocity.x, velocity.y},
              cpBodyGetAngularVelocity(body)};
  }
}

const Fx2dBenchPlugin plugin_table = {
    FX2D_BENCH_PLUGIN_ABI_VERSION,
    "chipmunk",
    &library_version,
    &build_description,
    knobs,
    knob_count,
    {FX2D_BENCH_BIT(FX2D_BENCH_CIRCLE) | FX2D_BENCH_BIT(FX2D_BENCH_BOX) | FX2D_BENCH_BIT(FX2D_BENCH_POLYGON),
     FX2D_BENCH_BIT(FX2D_BENCH_DISTANCE_JOINT) | FX2D_BENCH_BIT(FX2D_BENCH_REVOLUTE_JOINT), 1, 0, 0, 0.0},
    &create,
    &destroy,
    &step,
    &phase_count,
    &phase_name,
    &read_phases,
    &contact_count,
    &read_state,
};

}  // namespace

extern "C" FX2D_BENCH_PLUGIN_EXPORT const Fx2dBenchPlugin* fx2d_bench_plugin_v1(void) {
  return &plugin_table;
}
