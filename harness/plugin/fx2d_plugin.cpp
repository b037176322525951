// Fx2D behind the plugin C ABI (fx2d_plugin_abi.h): the one place where a flat C scene becomes an
// FxScene, and where Fx2D declares its knobs (FxSceneSettings' solver fields) and capabilities. fx2d-bench
// links this file statically as its built-in "fx2d" engine (through the internal name
// fx2d_bench_plugin_table) and builds it, against any revision of Fx2D, into a plugin that exports only
// fx2d_bench_plugin_v1 (compiled with FX2D_BENCH_PLUGIN_MODULE).
//
// The table is made from the class Fx2dWorld by the SDK's C++ layer (fx2d_bench_plugin.hpp), which
// keeps every exception inside; Fx2D's own refusals read "fx2d: ...", any other "fx2d plugin: ...".
// Conversions to Fx2D's floats are exactly those the harness always made, so the built-in
// engine's trajectories (and goldens) are the same bit for bit.
//
// FX2D_BENCH_INJECT_SLOWDOWN (test plugin only, never the product): after each step, spin for a
// fraction of that step's own measured time, the fraction read at create() from the environment
// variable FX2D_BENCH_TEST_SLOWDOWN (e.g. "0.05"), so one test plugin gives every injected cost.
#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "fx2d/fx2d.h"
#include "fx2d_bench_plugin.hpp"

#ifdef FX2D_BENCH_INJECT_SLOWDOWN
#include <chrono>
#include <cstdlib>
#endif

// Which build this is: given by whoever configures a plugin (ab: the revision it built), except for
// the plugin of the tree being built, which names the revision read on each build.
#ifdef FX2D_BENCH_PLUGIN_THIS_BUILD
#include "fx2d_bench_git_revision.h"  // generated in the build tree (harness/git_revision.cmake)
#define FX2D_BENCH_PLUGIN_DESCRIPTION FX2D_BENCH_GIT_REVISION " (this build)"
#endif
#ifndef FX2D_BENCH_PLUGIN_DESCRIPTION
#define FX2D_BENCH_PLUGIN_DESCRIPTION ""
#endif
// Threads per step of a scene that leaves fx2d.workers out (CMake FX2D_BENCH_WORKERS); 0: the
// engine's default.
#ifndef FX2D_BENCH_WORKERS
#define FX2D_BENCH_WORKERS 0
#endif

namespace {

fx2d::FxVec2f to_fx(Fx2dBenchVec2 v) { return {static_cast<float>(v.x), static_cast<float>(v.y)}; }

// The SDK's create() lets through only known body types and the shape kinds Fx2D declares.
fx2d::FxShape make_shape(const Fx2dBenchBody& body) {
  if (body.shape == FX2D_BENCH_CIRCLE) return fx2d::FxShape::circle(static_cast<float>(body.radius));
  if (body.shape == FX2D_BENCH_BOX)
    return fx2d::FxShape::box(static_cast<float>(body.half_extents.x),
                              static_cast<float>(body.half_extents.y));
  return fx2d::FxShape::polygon(fx2d_bench::vertices(body, to_fx));
}

fx2d::FxBodyType body_type(int32_t type) {
  if (type == FX2D_BENCH_STATIC_BODY) return fx2d::FxBodyType::static_body;
  if (type == FX2D_BENCH_KINEMATIC_BODY) return fx2d::FxBodyType::kinematic;
  return fx2d::FxBodyType::dynamic;
}

// ab builds this file around older revisions of Fx2D too, some from before FxEntityDef::bullet;
// a scene that asks such a revision for a bullet is refused rather than run without one.
template <class Def>
constexpr bool has_bullets = requires(Def def) {
  def.bullet;
};

template <class Def>
void mark_bullet(Def& def, bool bullet) {
  if constexpr (has_bullets<Def>) {
    def.bullet = bullet;
  } else if (bullet) {
    throw std::invalid_argument("this revision of Fx2D has no bullets (FxEntityDef::bullet)");
  }
}

fx2d::FxEntityDef make_def(const Fx2dBenchBody& body) {
  fx2d::FxEntityDef def;
  def.type = body_type(body.type);
  def.shape = make_shape(body);
  def.position = to_fx(body.position);
  def.angle = static_cast<float>(body.angle);
  def.linear_velocity = to_fx(body.linear_velocity);
  def.angular_velocity = static_cast<float>(body.angular_velocity);
  def.material.density = static_cast<float>(body.density);
  def.material.static_friction = static_cast<float>(body.static_friction);
  def.material.dynamic_friction = static_cast<float>(body.dynamic_friction);
  def.material.restitution = static_cast<float>(body.restitution);
  mark_bullet(def, body.bullet != 0);
  return def;
}

// A revolute joint's anchor is one world point: body A's local anchor placed at A's start pose.
std::shared_ptr<fx2d::FxConstraint> make_joint(const std::vector<std::shared_ptr<fx2d::FxEntity>>& entities,
                                               const Fx2dBenchJoint& joint) {
  const auto& a = fx2d_bench::joint_body(entities, joint.body_a);
  const auto& b = fx2d_bench::joint_body(entities, joint.body_b);
  const fx2d::FxVec2f anchor_a = to_fx(joint.local_anchor_a);
  if (joint.kind == FX2D_BENCH_DISTANCE_JOINT) {
    return std::make_shared<fx2d::FxDistanceJoint>(a, b, anchor_a, to_fx(joint.local_anchor_b),
                                                   static_cast<float>(joint.length));
  }
  return std::make_shared<fx2d::FxRevoluteJoint>(a, b, a->position() + rotate(a->rotation(), anchor_a));
}

// The knobs, in the order create() receives their values; each default is this revision's own.
enum Knob {
  substeps,
  velocity_passes,
  sleeping,
  relax_passes,
  max_push_speed,
  workers,
  rest_schedule,
  shallow_schedule,
  impact_velocity_passes,
  joint_relax_passes,
  knob_count
};

const fx2d::FxSceneSettings engine_defaults{};

// ab builds this file against older revisions too, whose settings have no worker count: there
// every step runs on one thread, with the same results. FX2D_BENCH_WORKERS (CMake) sets this
// build's default, so that one build at 1 and 2 workers can be timed against each other.
template <class Settings>
int default_workers(const Settings& settings) {
  if constexpr (requires { settings.workers; }) {
    return FX2D_BENCH_WORKERS > 0 ? FX2D_BENCH_WORKERS : settings.workers;
  } else {
    return 1;
  }
}

template <class Settings>
void set_workers(Settings& settings, int workers) {
  if constexpr (requires { settings.workers; }) settings.workers = workers;
}

// A setting of FxSceneSettings that older revisions lack, where `before` is what they did:
// default_<name>() reads this revision's default, set_<name>() sets it where it exists.
#define FX2D_BENCH_OPTIONAL_SETTING(name, type, before)               \
  template <class Settings>                                           \
  type default_##name(const Settings& settings) {                     \
    if constexpr (requires { settings.name; }) {                      \
      return settings.name;                                           \
    } else {                                                          \
      return before;                                                  \
    }                                                                 \
  }                                                                   \
  template <class Settings>                                           \
  void set_##name(Settings& settings, type value) {                   \
    if constexpr (requires { settings.name; }) settings.name = value; \
  }

// Revisions from before the rest schedule take every step's passes from the settings, those from
// before the shallow schedule every step's that is not at rest, and those from before the impact
// schedule give an impact's step no more soft passes than another's.
FX2D_BENCH_OPTIONAL_SETTING(rest_schedule, bool, false)
FX2D_BENCH_OPTIONAL_SETTING(shallow_schedule, bool, false)
FX2D_BENCH_OPTIONAL_SETTING(impact_velocity_passes, int, 1)
// Those from before joint_relax_passes take the joints into every rigid pass.
FX2D_BENCH_OPTIONAL_SETTING(joint_relax_passes, int, 1000)

const Fx2dBenchKnob knobs[knob_count] = {
    {"substeps", FX2D_BENCH_KNOB_INTEGER, 1, 1000, static_cast<double>(engine_defaults.substeps),
     "velocity substeps per step"},
    {"velocity_passes", FX2D_BENCH_KNOB_INTEGER, 0, 1000,
     static_cast<double>(engine_defaults.velocity_passes), "soft sequential-impulse passes per substep"},
    {"sleeping", FX2D_BENCH_KNOB_BOOLEAN, 0, 1, engine_defaults.sleeping ? 1.0 : 0.0,
     "let resting bodies sleep"},
    {"relax_passes", FX2D_BENCH_KNOB_INTEGER, 1, 1000, static_cast<double>(engine_defaults.relax_passes),
     "relaxation passes per substep"},
    {"max_push_speed", FX2D_BENCH_KNOB_NUMBER, 1e-3, 1e6, static_cast<double>(engine_defaults.max_push_speed),
     "fastest an overlap is pushed apart, m/s"},
    {"workers", FX2D_BENCH_KNOB_INTEGER, 1, 64, static_cast<double>(default_workers(engine_defaults)),
     "threads a step may use; the results are the same on any number"},
    {"rest_schedule", FX2D_BENCH_KNOB_BOOLEAN, 0, 1, default_rest_schedule(engine_defaults) ? 1.0 : 0.0,
     "one soft and one rigid pass per substep while every awake body rests"},
    {"shallow_schedule", FX2D_BENCH_KNOB_BOOLEAN, 0, 1, default_shallow_schedule(engine_defaults) ? 1.0 : 0.0,
     "one soft and one rigid pass per substep while no contact closes fast and no support chain is deep"},
    {"impact_velocity_passes", FX2D_BENCH_KNOB_INTEGER, 1, 1000,
     static_cast<double>(default_impact_velocity_passes(engine_defaults)),
     "soft passes per substep, at least, in a step with a contact closing fast for its bodies' size (impact "
     "schedule)"},
    {"joint_relax_passes", FX2D_BENCH_KNOB_INTEGER, 1, 1000,
     static_cast<double>(default_joint_relax_passes(engine_defaults)),
     "rigid passes per substep that include the joints; the others sweep the contacts alone"},
};

// Revisions from before FxSceneSettings::max_linear_speed accept any speed.
template <class Settings>
double max_linear_speed(const Settings& settings) {
  if constexpr (requires { settings.max_linear_speed; }) {
    return static_cast<double>(settings.max_linear_speed);
  } else {
    return 0.0;
  }
}

fx2d::FxSceneSettings scene_settings(const Fx2dBenchScene& scene) {
  const double* knob = scene.settings;
  fx2d::FxSceneSettings settings;
  settings.gravity = to_fx(scene.gravity);
  settings.dt = static_cast<float>(scene.dt);
  settings.substeps = static_cast<int>(knob[substeps]);
  settings.velocity_passes = static_cast<int>(knob[velocity_passes]);
  settings.sleeping = knob[sleeping] != 0.0;
  settings.relax_passes = static_cast<int>(knob[relax_passes]);
  settings.max_push_speed = static_cast<float>(knob[max_push_speed]);
  set_workers(settings, static_cast<int>(knob[workers]));
  set_rest_schedule(settings, knob[rest_schedule] != 0.0);
  set_shallow_schedule(settings, knob[shallow_schedule] != 0.0);
  set_impact_velocity_passes(settings, static_cast<int>(knob[impact_velocity_passes]));
  set_joint_relax_passes(settings, static_cast<int>(knob[joint_relax_passes]));
  return settings;
}

#ifdef FX2D_BENCH_INJECT_SLOWDOWN
double slowdown_from_environment() {
  const char* text = std::getenv("FX2D_BENCH_TEST_SLOWDOWN");
  return text != nullptr ? std::max(0.0, std::atof(text)) : 0.0;
}

// Busy-waits, so the cost is CPU time like the step's own, for `fraction` of the step just taken.
void step_with_injected_cost(fx2d::FxScene& scene, double fraction) {
  using clock = std::chrono::steady_clock;
  const clock::time_point start = clock::now();
  scene.step();
  const clock::time_point end = clock::now();
  const auto until = end + std::chrono::duration_cast<clock::duration>((end - start) * fraction);
  while (clock::now() < until) {
  }
}
#endif

class Fx2dWorld {
 public:
  explicit Fx2dWorld(const Fx2dBenchScene& scene) try : scene_(scene_settings(scene)) {
    for (int32_t i = 0; i < scene.body_count; ++i) entities_.push_back(scene_.create_entity(make_def(scene.bodies[i])));
    for (int32_t i = 0; i < scene.joint_count; ++i) scene_.add_constraint(make_joint(entities_, scene.joints[i]));
  } catch (const fx2d::FxInvalidArgument& failure) {
    throw fx2d_bench::Refusal(std::string("fx2d: ") + failure.what());
  }

  void step() {
#ifdef FX2D_BENCH_INJECT_SLOWDOWN
    step_with_injected_cost(scene_, slowdown_fraction_);
#else
    scene_.step();
#endif
  }

  static int32_t phase_count() { return fx2d::fx_stage_count; }

  static const char* phase_name(int32_t phase) {
    static const auto names = [] {
      std::vector<std::string> all;
      for (int i = 0; i < fx2d::fx_stage_count; ++i) all.emplace_back(fx2d::stage_name(static_cast<fx2d::FxStage>(i)));
      return all;
    }();
    return phase >= 0 && phase < fx2d::fx_stage_count ? names[static_cast<std::size_t>(phase)].c_str() : "";
  }

  void read_phases(double* ms, int32_t count) const {
    const fx2d::FxProfile& profile = scene_.profile();
    for (int32_t i = 0; i < std::min(count, phase_count()); ++i) ms[i] = profile.stage_ms[static_cast<std::size_t>(i)];
  }

  int32_t contact_count() const { return scene_.contact_count(); }

  Fx2dBenchBodyState body_state(std::size_t index) const {
    const fx2d::FxEntity& e = *entities_[index];
    return {{e.precise_x(), e.precise_y()},
            e.angle(),
            {e.linear_velocity().x, e.linear_velocity().y},
            e.angular_velocity()};
  }

 private:
  fx2d::FxScene scene_;
  std::vector<std::shared_ptr<fx2d::FxEntity>> entities_;
#ifdef FX2D_BENCH_INJECT_SLOWDOWN
  double slowdown_fraction_ = slowdown_from_environment();
#endif
};

const char* library_version() {
  static const std::string version(fx2d::fx_version());
  return version.c_str();
}

const fx2d_bench::EngineDescription fx2d_engine{
    .name = "fx2d",
    .library_version = &library_version,
    .build_description = [] { return FX2D_BENCH_PLUGIN_DESCRIPTION; },
    .knobs = knobs,
    .capabilities = {fx2d_bench::all_shapes, fx2d_bench::all_joints, 1, has_bullets<fx2d::FxEntityDef> ? 1 : 0, 0,
                     max_linear_speed(engine_defaults)},
};

}  // namespace

extern "C" const Fx2dBenchPlugin* fx2d_bench_plugin_table(void) {
  static const Fx2dBenchPlugin table = fx2d_bench::plugin_table<Fx2dWorld, fx2d_engine>();
  return &table;
}

#ifdef FX2D_BENCH_PLUGIN_MODULE
// The plugin's only exported symbol; everything else in the library is hidden.
extern "C" FX2D_BENCH_PLUGIN_EXPORT const Fx2dBenchPlugin* fx2d_bench_plugin_v1(void) {
  return fx2d_bench_plugin_table();
}
#endif
