// A template fx2d-bench engine plugin (harness/plugin/README.md walks through it). The "engine"
// here is a stand-in: bodies fall under gravity and nothing collides. Replace each marked part
// with calls into your engine; fx2d_bench_plugin.hpp makes the C table from the class.
#include <vector>

#include "fx2d_bench_plugin.hpp"

namespace {

// 1. Your engine's settings: each is /solver/my_engine/<name> in a scene, checked by fx2d-bench.
enum Knob { substeps, knob_count };
constexpr Fx2dBenchKnob knobs[knob_count] = {
    {"substeps", FX2D_BENCH_KNOB_INTEGER, 1, 64, 1, "integration substeps per step"},
};

// 2. One built scene: your engine's world and its bodies, in the scene's order.
class MyEngineWorld {
 public:
  // 3. Build the scene in your engine. Throw to refuse it; the message reaches the user.
  explicit MyEngineWorld(const Fx2dBenchScene& scene)
      : gravity_(scene.gravity), dt_(scene.dt), substeps_(static_cast<int>(scene.settings[substeps])) {
    for (int32_t i = 0; i < scene.body_count; ++i) {
      const Fx2dBenchBody& body = scene.bodies[i];
      bodies_.push_back({body.position, body.angle, body.linear_velocity, body.angular_velocity});
      moves_.push_back(body.type == FX2D_BENCH_DYNAMIC_BODY);
    }
  }

  // 4. Advance one step of the scene's dt.
  void step() {
    const double h = dt_ / substeps_;
    for (int substep = 0; substep < substeps_; ++substep) {
      for (std::size_t i = 0; i < bodies_.size(); ++i) {
        if (!moves_[i]) continue;
        Fx2dBenchBodyState& body = bodies_[i];
        body.linear_velocity.x += gravity_.x * h;
        body.linear_velocity.y += gravity_.y * h;
        body.position.x += body.linear_velocity.x * h;
        body.position.y += body.linear_velocity.y * h;
        body.angle += body.angular_velocity * h;
      }
    }
  }

  // 5. Read back one body's pose and velocity (the scene's body number `index`), and how many
  // pairs touch.
  Fx2dBenchBodyState body_state(std::size_t index) const { return bodies_[index]; }
  int32_t contact_count() const { return 0; }

  // Your engine's phase split, if it times its own stages: static phase_count() and
  // phase_name(phase), and read_phases(ms, count) const; none here.

 private:
  std::vector<Fx2dBenchBodyState> bodies_;  // stand-in for your engine's bodies
  std::vector<bool> moves_;
  Fx2dBenchVec2 gravity_;
  double dt_;
  int substeps_;
};

constexpr fx2d_bench::EngineDescription my_engine{
    .name = "my_engine",  // the engine's name: its scene block /solver/my_engine, and its builds' names in ab
    .library_version = [] { return "0.0.1"; },
    .knobs = knobs,
    // 6. What it can build: shapes, joints, sleeping, bullets, most bodies (0: any), fastest body (0: any).
    .capabilities = {FX2D_BENCH_BIT(FX2D_BENCH_CIRCLE) | FX2D_BENCH_BIT(FX2D_BENCH_BOX), 0, 0, 0, 0, 0.0},
};

}  // namespace

FX2D_BENCH_EXPORT_PLUGIN(MyEngineWorld, my_engine)
