// A template fx2d-bench engine plugin (harness/plugin/README.md walks through it). The "engine"
// here is a stand-in: bodies fall under gravity and nothing collides. Replace each marked part
// with calls into your engine; the table at the end stays as it is.
#include <cstdio>
#include <exception>
#include <vector>

#include "fx2d_plugin_abi.h"

// 1. One built scene: your engine's world and its bodies, in the scene's order.
struct Fx2dBenchInstance {
  std::vector<Fx2dBenchBodyState> bodies;  // stand-in for your engine's bodies
  std::vector<bool> moves;
  Fx2dBenchVec2 gravity{};
  double dt = 0.0;
  int substeps = 1;
};

namespace {

// 2. Your engine's settings: each is /solver/my_engine/<name> in a scene, checked by fx2d-bench.
enum Knob { substeps, knob_count };
const Fx2dBenchKnob knobs[knob_count] = {
    {"substeps", FX2D_BENCH_KNOB_INTEGER, 1, 64, 1, "integration substeps per step"},
};

// 3. Build the scene in your engine. Throw to refuse it; the message reaches the user.
void build(Fx2dBenchInstance& world, const Fx2dBenchScene& scene) {
  world.gravity = scene.gravity;
  world.dt = scene.dt;
  world.substeps = static_cast<int>(scene.settings[substeps]);
  for (int32_t i = 0; i < scene.body_count; ++i) {
    const Fx2dBenchBody& body = scene.bodies[i];
    world.bodies.push_back({body.position, body.angle, body.linear_velocity, body.angular_velocity});
    world.moves.push_back(body.type == FX2D_BENCH_DYNAMIC_BODY);
  }
}

// 4. Advance one step of the scene's dt.
void step(Fx2dBenchInstance* world) {
  const double h = world->dt / world->substeps;
  for (int substep = 0; substep < world->substeps; ++substep) {
    for (std::size_t i = 0; i < world->bodies.size(); ++i) {
      if (!world->moves[i]) continue;
      Fx2dBenchBodyState& body = world->bodies[i];
      body.linear_velocity.x += world->gravity.x * h;
      body.linear_velocity.y += world->gravity.y * h;
      body.position.x += body.linear_velocity.x * h;
      body.position.y += body.linear_velocity.y * h;
      body.angle += body.angular_velocity * h;
    }
  }
}

// 5. Read back poses and velocities, in the scene's order, and how many pairs touch.
void read_state(const Fx2dBenchInstance* world, Fx2dBenchBodyState* out, int32_t count) {
  for (int32_t i = 0; i < count && static_cast<std::size_t>(i) < world->bodies.size(); ++i)
    out[i] = world->bodies[i];
}
int32_t contact_count(const Fx2dBenchInstance*) { return 0; }

const char* library_version() { return "0.0.1"; }
const char* build_description() { return ""; }

Fx2dBenchInstance* create(const Fx2dBenchScene* scene, char* error, size_t error_size) {
  auto* world = new Fx2dBenchInstance;
  try {
    build(*world, *scene);
    return world;
  } catch (const std::exception& failure) {
    std::snprintf(error, error_size, "my_engine: %s", failure.what());
  }
  delete world;
  return nullptr;
}
void destroy(Fx2dBenchInstance* world) { delete world; }

// Your engine's phase split, if it reports one; none here.
int32_t phase_count() { return 0; }
const char* phase_name(int32_t) { return ""; }
void read_phases(const Fx2dBenchInstance*, double*, int32_t) {}

const Fx2dBenchPlugin table = {
    FX2D_BENCH_PLUGIN_ABI_VERSION,
    "my_engine",  // the engine's name: its scene block /solver/my_engine, and its builds' names in ab
    &library_version,
    &build_description,
    knobs,
    knob_count,
    // 6. What it can build: shapes, joints, sleeping, bullets, most bodies (0: any), fastest body (0: any).
    {FX2D_BENCH_BIT(FX2D_BENCH_CIRCLE) | FX2D_BENCH_BIT(FX2D_BENCH_BOX), 0, 0, 0, 0, 0.0},
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

extern "C" FX2D_BENCH_PLUGIN_EXPORT const Fx2dBenchPlugin* fx2d_bench_plugin_v1(void) { return &table; }
