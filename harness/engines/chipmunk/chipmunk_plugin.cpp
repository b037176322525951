// Chipmunk2D 7 behind the plugin C ABI (plugin/fx2d_plugin_abi.h), written with the SDK's C++ layer
// (fx2d_bench_plugin.hpp): fx2d-bench's fourth engine, and the proof that an engine adapter is one
// small class.
//
// Mapping: dynamic bodies take their mass and inertia from their shapes' density (Chipmunk finds
// the centre of gravity; positions read back are body origins, as the scene's); one friction,
// the dynamic one, given as its square root so that Chipmunk's product of two shapes' frictions is
// their geometric mean, as in Box2D; restitution as Chipmunk combines it (the product); distance
// joints are pin joints, revolute joints pivot joints at body A's anchor in the world, and the
// bodies of either never collide with each other.
// Chipmunk's defaults are tuned for pixels: the collision slop is a knob in metres instead.
#include <chipmunk/chipmunk.h>
extern "C" {  // chipmunk.h declares its own functions so; this header, outside it, does not
#include <chipmunk/cpHastySpace.h>
}

#include <fcntl.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "fx2d_bench_plugin.hpp"

namespace {

// Debian's Chipmunk is a debug build (runtime assertions on), which prints a banner on stdout at
// its first space. stdout is fx2d-bench's data (JSON, tables) and stderr says only what went wrong,
// so that first space is made with stdout sent to /dev/null. More than one thread takes a hasty space
// (cpHastySpace.h, two threads at most), stepped and freed by its own calls; one thread keeps the
// plain space, so results at the default are those of a build without the knob.
cpSpace* new_space(int threads) {
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
  if (!banner_dropped) return nullptr;
  if (threads == 1) return cpSpaceNew();
  cpSpace* space = cpHastySpaceNew();
  cpHastySpaceSetThreads(space, static_cast<unsigned long>(threads));
  return space;
}

struct FreeSpace {
  bool hasty;
  void operator()(cpSpace* space) const { hasty ? cpHastySpaceFree(space) : cpSpaceFree(space); }
};

enum Knob { iterations, sleeping, sleep_time, collision_slop, threads, knob_count };

constexpr Fx2dBenchKnob knobs[knob_count] = {
    {"iterations", FX2D_BENCH_KNOB_INTEGER, 1, 1000, 10, "solver iterations per step (cpSpaceSetIterations)"},
    {"sleeping", FX2D_BENCH_KNOB_BOOLEAN, 0, 1, 1, "let resting bodies sleep"},
    {"sleep_time", FX2D_BENCH_KNOB_NUMBER, 0.01, 100, 0.5, "seconds idle before a body sleeps, s"},
    {"collision_slop", FX2D_BENCH_KNOB_NUMBER, 0, 1, 0.005, "overlap allowed between shapes, m"},
    {"threads", FX2D_BENCH_KNOB_INTEGER, 1, 2, 1, "solver threads (cpHastySpaceSetThreads; 2 at most)"},
};

cpVect to_cp(Fx2dBenchVec2 v) { return cpv(v.x, v.y); }

// The SDK's create() lets through only the body types and shape kinds of the capabilities below.
cpBody* make_body(const Fx2dBenchBody& spec) {
  if (spec.type == FX2D_BENCH_STATIC_BODY) return cpBodyNewStatic();
  if (spec.type == FX2D_BENCH_KINEMATIC_BODY) return cpBodyNewKinematic();
  return cpBodyNew(0.0, 0.0);  // dynamic: mass and inertia from the shape's density
}

cpShape* make_shape(cpBody* body, const Fx2dBenchBody& spec) {
  if (spec.shape == FX2D_BENCH_CIRCLE) return cpCircleShapeNew(body, spec.radius, cpvzero);
  if (spec.shape == FX2D_BENCH_BOX)
    return cpBoxShapeNew(body, 2.0 * spec.half_extents.x, 2.0 * spec.half_extents.y, 0.0);
  const std::vector<cpVect> vertices = fx2d_bench::vertices(spec, to_cp);
  return cpPolyShapeNew(body, spec.vertex_count, vertices.data(), cpTransformIdentity, 0.0);
}

class ChipmunkWorld {
 public:
  explicit ChipmunkWorld(const Fx2dBenchScene& scene)
      : space_(new_space(static_cast<int>(scene.settings[threads])), FreeSpace{scene.settings[threads] > 1}),
        dt_(scene.dt) {
    const double* knob = scene.settings;
    cpSpaceSetGravity(space_.get(), to_cp(scene.gravity));
    cpSpaceSetIterations(space_.get(), static_cast<int>(knob[iterations]));
    cpSpaceSetSleepTimeThreshold(space_.get(), knob[sleeping] != 0.0 ? knob[sleep_time] : INFINITY);
    cpSpaceSetCollisionSlop(space_.get(), knob[collision_slop]);
    for (int32_t i = 0; i < scene.body_count; ++i) add_body(scene.bodies[i]);
    for (int32_t i = 0; i < scene.joint_count; ++i) {
      joints_.emplace_back(make_joint(scene.joints[i]));
      cpSpaceAddConstraint(space_.get(), joints_.back().get());
    }
  }

  // Chipmunk moves a sleeping body's contacts to a block of their own, freed when the body wakes,
  // which freeing the space does not do: every body is woken first, or those blocks leak (192
  // bytes a resting box, LeakSanitizer and valgrind). Not with cpSpaceEachBody: waking a sleeping
  // group removes it from the list that function walks, so the group after it would be skipped.
  ~ChipmunkWorld() {
    for (const auto& body : bodies_) cpBodyActivate(body.get());
  }

  void step() {
    space_.get_deleter().hasty ? cpHastySpaceStep(space_.get(), dt_) : cpSpaceStep(space_.get(), dt_);
  }

  // Touching pairs of bodies (one shape per body here), sleeping ones included: each arbiter is
  // seen from both its bodies but counted from one, the static one never being walked.
  int32_t contact_count() const {
    int32_t count = 0;
    for (const auto& body : bodies_) {
      if (cpBodyGetType(body.get()) == CP_BODY_TYPE_STATIC) continue;
      cpBodyEachArbiter(
          body.get(),
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

  Fx2dBenchBodyState body_state(std::size_t index) const {
    const cpBody* body = bodies_[index].get();
    const cpVect position = cpBodyGetPosition(body);
    const cpVect velocity = cpBodyGetVelocity(body);
    return {{position.x, position.y},
            cpBodyGetAngle(body),
            {velocity.x, velocity.y},
            cpBodyGetAngularVelocity(body)};
  }

 private:
  void add_body(const Fx2dBenchBody& spec) {
    cpBody* body = bodies_.emplace_back(make_body(spec)).get();
    cpBodySetPosition(body, to_cp(spec.position));
    cpBodySetAngle(body, spec.angle);
    cpShape* shape = shapes_.emplace_back(make_shape(body, spec)).get();
    if (spec.type == FX2D_BENCH_DYNAMIC_BODY) cpShapeSetDensity(shape, spec.density);
    cpShapeSetFriction(shape, std::sqrt(spec.dynamic_friction));
    cpShapeSetElasticity(shape, spec.restitution);
    cpSpaceAddBody(space_.get(), body);
    cpSpaceAddShape(space_.get(), shape);
    if (spec.type != FX2D_BENCH_STATIC_BODY) {
      cpBodySetVelocity(body, to_cp(spec.linear_velocity));
      cpBodySetAngularVelocity(body, spec.angular_velocity);
    }
  }

  // Chipmunk lets a constraint's bodies collide unless told not to; in every other engine here,
  // and in the scene format, bodies a joint connects never do.
  cpConstraint* make_joint(const Fx2dBenchJoint& spec) const {
    cpBody* a = fx2d_bench::joint_body(bodies_, spec.body_a).get();
    cpBody* b = fx2d_bench::joint_body(bodies_, spec.body_b).get();
    cpConstraint* joint = nullptr;
    if (spec.kind == FX2D_BENCH_REVOLUTE_JOINT) {
      joint = cpPivotJointNew(a, b, cpBodyLocalToWorld(a, to_cp(spec.local_anchor_a)));
    } else {
      joint = cpPinJointNew(a, b, to_cp(spec.local_anchor_a), to_cp(spec.local_anchor_b));
      if (spec.length >= 0.0) cpPinJointSetDist(joint, spec.length);
    }
    cpConstraintSetCollideBodies(joint, cpFalse);
    return joint;
  }

  // What Chipmunk allocated for the scene, freed even when building it failed part way: the space
  // first (declared last), which touches none of its children, then each child on its own
  // (removing each from the space would cost a linear search per body).
  std::vector<fx2d_bench::Owned<cpBody, cpBodyFree>> bodies_;  // in the scene's order
  std::vector<fx2d_bench::Owned<cpShape, cpShapeFree>> shapes_;
  std::vector<fx2d_bench::Owned<cpConstraint, cpConstraintFree>> joints_;
  std::unique_ptr<cpSpace, FreeSpace> space_;
  double dt_;
};

constexpr fx2d_bench::EngineDescription chipmunk{
    .name = "chipmunk",
    .library_version = [] { return cpVersionString; },
    .knobs = knobs,
    .capabilities = {fx2d_bench::all_shapes, fx2d_bench::all_joints, 1, 0, 0, 0.0},
};

}  // namespace

FX2D_BENCH_EXPORT_PLUGIN(ChipmunkWorld, chipmunk)
