// libFuzzer target: a byte stream decoded into a sequence of calls on fx2d::FxScene — create,
// remove (also from inside the step callback), push, teleport, join, change settings and step —
// with arbitrary values, finite or not.
//
// Invariant checked: calls the engine refuses throw FxInvalidArgument; calls it accepts never
// lead to a crash, a sanitizer report, another exception, or a non-finite position, angle or
// velocity after a step (which aborts with a message naming the entity and the field). Each input
// is kept fast: at most kMaxEntities entities, kMaxConstraints joints and kMaxSteps steps, and
// solver iteration counts below 24.
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <optional>
#include <vector>

#include "fx2d/fx2d.h"

namespace {

using fx2d::FxVec2f;

constexpr std::size_t kMaxEntities = 64;
constexpr std::size_t kMaxConstraints = 64;
constexpr int kMaxSteps = 64;
constexpr int kMaxStepsPerCall = 8;

// Reads the input front to back; past its end every read is zero, so any prefix decodes.
class ByteStream {
 public:
  ByteStream(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  bool empty() const { return position_ >= size_; }
  std::uint8_t byte() { return empty() ? 0 : data_[position_++]; }
  std::uint32_t index(std::size_t count) { return static_cast<std::uint32_t>(byte() % count); }
  // -2 .. 21: a few invalid counts, and valid ones small enough to keep a step cheap.
  int small_count() { return static_cast<int>(byte() % 24) - 2; }

  // Mostly values of physical size, so the fuzzer explores the solver rather than only the
  // validation; sometimes any float at all, or one of the values at the edges of float.
  float value() {
    const std::uint8_t kind = byte();
    switch (kind % 8) {
      case 5: return static_cast<float>(static_cast<std::int8_t>(byte())) / 1024.0f;
      case 6: return raw_float();
      case 7: return edge_value();
      default: return static_cast<float>(static_cast<std::int16_t>(byte() << 8 | byte())) / 64.0f;
    }
  }
  FxVec2f vec2() {
    const float x = value();
    return {x, value()};
  }

 private:
  float raw_float() {
    std::uint32_t bits = 0;
    for (int i = 0; i < 4; ++i) bits = bits << 8 | byte();
    float result;
    std::memcpy(&result, &bits, sizeof result);
    return result;
  }
  float edge_value() {
    static constexpr std::array<float, 8> edges = {
        0.0f, -0.0f, 1e-30f, 1e30f, 3.4e38f, INFINITY, -INFINITY, NAN};
    return edges[byte() % edges.size()];
  }

  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t position_ = 0;
};

fx2d::FxShape decode_shape(ByteStream& in) {
  switch (in.byte() % 3) {
    case 0: {
      const float radius = in.value();
      return fx2d::FxShape::circle(radius, in.vec2());
    }
    case 1: {
      const float half_width = in.value();
      const float half_height = in.value();
      const FxVec2f center = in.vec2();
      return fx2d::FxShape::box(half_width, half_height, center, in.value());
    }
    default: {
      std::vector<FxVec2f> vertices(in.byte() % (fx2d::FxShape::max_vertices + 3));
      for (FxVec2f& vertex : vertices) vertex = in.vec2();
      return fx2d::FxShape::polygon(vertices);
    }
  }
}

fx2d::FxEntityDef decode_entity(ByteStream& in) {
  fx2d::FxEntityDef def;
  def.type = static_cast<fx2d::FxBodyType>(in.byte() % 3);
  def.shape = decode_shape(in);
  def.material.density = in.value();
  def.material.static_friction = in.value();
  def.material.dynamic_friction = in.value();
  def.material.restitution = in.value();
  def.position = in.vec2();
  def.angle = in.value();
  def.linear_velocity = in.vec2();
  def.angular_velocity = in.value();
  def.linear_damping = in.value();
  def.angular_damping = in.value();
  def.can_sleep = (in.byte() & 1) != 0;
  return def;
}

// One field of the settings, chosen by the stream; set_settings() validates the result.
fx2d::FxSceneSettings decode_settings_change(ByteStream& in, fx2d::FxSceneSettings s) {
  switch (in.byte() % 18) {
    case 0: s.gravity = in.vec2(); break;
    case 1: s.dt = in.value(); break;
    case 2: s.substeps = in.small_count(); break;
    case 3: s.velocity_passes = in.small_count(); break;
    case 4: s.relax_passes = in.small_count(); break;
    case 5: s.position_passes = in.small_count(); break;
    case 6: s.sleeping = (in.byte() & 1) != 0; break;
    case 7: s.time_to_sleep = in.value(); break;
    case 8: s.linear_sleep_speed = in.value(); break;
    case 9: s.angular_sleep_speed = in.value(); break;
    case 10: s.restitution_threshold = in.value(); break;
    case 11: s.contact_hertz = in.value(); break;
    case 12: s.contact_damping_ratio = in.value(); break;
    case 13: s.joint_hertz = in.value(); break;
    case 14: s.joint_damping_ratio = in.value(); break;
    case 15: s.max_push_speed = in.value(); break;
    case 16: s.linear_slop = in.value(); break;
    default: s.max_linear_speed = in.value(); break;
  }
  return s;
}

[[noreturn]] void report(const fx2d::FxScene& scene, std::uint32_t entity, const char* field,
                         const char* call) {
  std::fprintf(stderr, "engine_fuzz: entity %u has a non-finite %s after %s (%llu steps taken)\n", entity,
               field, call, static_cast<unsigned long long>(scene.step_index()));
  std::abort();
}

// Checked after every call, not only after steps, so a report names the call that broke the state.
void check_finite_state(const fx2d::FxScene& scene, const char* call) {
  if (scene.contact_count() < 0) {
    std::fprintf(stderr, "engine_fuzz: contact_count() is %d after %s\n", scene.contact_count(), call);
    std::abort();
  }
  for (std::uint32_t i = 0; i < scene.entity_count(); ++i) {
    const fx2d::FxEntity& entity = *scene.entity(i);
    if (!fx2d::is_finite(entity.position())) report(scene, i, "position", call);
    if (!std::isfinite(entity.angle())) report(scene, i, "angle", call);
    if (!fx2d::is_finite(entity.linear_velocity())) report(scene, i, "linear velocity", call);
    if (!std::isfinite(entity.angular_velocity())) report(scene, i, "angular velocity", call);
  }
}

// With FX2D_FUZZ_TRACE set, every call and step, and the state after it, go to stderr: how a reproducer
// from crashes/ is read.
void trace_call(const fx2d::FxScene& scene, const char* call) {
  std::fprintf(stderr, "after %s (step %llu):\n", call, static_cast<unsigned long long>(scene.step_index()));
  for (std::uint32_t i = 0; i < scene.entity_count(); ++i) {
    const fx2d::FxEntity& e = *scene.entity(i);
    std::fprintf(stderr, "  entity %u type %d mass %g p (%g, %g) angle %g v (%g, %g) w %g\n", i,
                 static_cast<int>(e.type()), static_cast<double>(e.mass()), static_cast<double>(e.position().x),
                 static_cast<double>(e.position().y), static_cast<double>(e.angle()),
                 static_cast<double>(e.linear_velocity().x), static_cast<double>(e.linear_velocity().y),
                 static_cast<double>(e.angular_velocity()));
  }
}


// What the step callback does after the next step: the stream arms it, the callback disarms it,
// so removal and creation happen inside the callback as a user's code would do them.
struct CallbackPlan {
  std::optional<std::uint8_t> remove_selector;
  bool create_circle = false;
};

void run_callback_plan(fx2d::FxScene& scene, CallbackPlan& plan) {
  if (plan.remove_selector && scene.entity_count() > 0) {
    const auto index = static_cast<std::uint32_t>(*plan.remove_selector % scene.entity_count());
    scene.remove_entity(*scene.entity(index));
  }
  if (plan.create_circle && scene.entity_count() < kMaxEntities) {
    fx2d::FxEntityDef def;
    def.shape = fx2d::FxShape::circle(0.25f);
    scene.create_entity(def);
  }
  plan = {};
}

class Session {
 public:
  Session() {
    scene_.set_step_callback([this](fx2d::FxScene& scene) { run_callback_plan(scene, plan_); });
  }

  // Decodes and makes one call; returns its name for reports.
  const char* apply(ByteStream& in) {
    switch (in.byte() % 12) {
      case 0: create(in); return "create_entity";
      case 1: with_entity(in, [&](fx2d::FxEntity& e) { remove(e); }); return "remove_entity";
      case 2: with_entity(in, [&](fx2d::FxEntity& e) { set_velocity(in, e); }); return "set_*_velocity";
      case 3: with_entity(in, [&](fx2d::FxEntity& e) { push(in, e); }); return "apply_linear_impulse";
      case 4: with_entity(in, [&](fx2d::FxEntity& e) { e.apply_force(in.vec2()); }); return "apply_force";
      case 5: with_entity(in, [&](fx2d::FxEntity& e) { set_transform(in, e); }); return "set_transform";
      case 6: join(in, /*distance=*/true); return "add_constraint(FxDistanceJoint)";
      case 7: join(in, /*distance=*/false); return "add_constraint(FxRevoluteJoint)";
      case 8: unjoin(in); return "remove_constraint";
      case 9: scene_.set_settings(decode_settings_change(in, scene_.settings())); return "set_settings";
      case 10: arm_callback(in); return "arming the step callback";
      default: step(in); return "step";
    }
  }

  const fx2d::FxScene& scene() const { return scene_; }

  bool out_of_steps() const { return steps_ >= kMaxSteps; }

 private:
  template <class Action>
  void with_entity(ByteStream& in, Action action) {
    const std::uint8_t selector = in.byte();
    if (scene_.entity_count() == 0) return;
    action(*scene_.entity(static_cast<std::uint32_t>(selector % scene_.entity_count())));
  }

  void remove(const fx2d::FxEntity& entity) { scene_.remove_entity(entity); }
  static void set_velocity(ByteStream& in, fx2d::FxEntity& entity) {
    entity.set_linear_velocity(in.vec2());
    entity.set_angular_velocity(in.value());
  }
  static void push(ByteStream& in, fx2d::FxEntity& entity) {
    const FxVec2f impulse = in.vec2();
    entity.apply_linear_impulse(impulse, in.vec2());
  }
  static void set_transform(ByteStream& in, fx2d::FxEntity& entity) {
    const FxVec2f position = in.vec2();
    entity.set_transform(position, in.value());
  }

  void create(ByteStream& in) {
    const fx2d::FxEntityDef def = decode_entity(in);
    if (scene_.entity_count() < kMaxEntities) scene_.create_entity(def);
  }

  void join(ByteStream& in, bool distance) {
    const std::uint8_t selector_a = in.byte();
    const std::uint8_t selector_b = in.byte();
    const FxVec2f anchor_a = in.vec2();
    const FxVec2f anchor_b = in.vec2();
    const float length = in.value();
    const std::size_t count = scene_.entity_count();
    if (count == 0 || constraints_.size() >= kMaxConstraints) return;
    const auto& a = scene_.entity(static_cast<std::uint32_t>(selector_a % count));
    const auto& b = scene_.entity(static_cast<std::uint32_t>(selector_b % count));
    std::shared_ptr<fx2d::FxConstraint> joint;
    if (distance) {
      joint = std::make_shared<fx2d::FxDistanceJoint>(a, b, anchor_a, anchor_b, length);
    } else {
      joint = std::make_shared<fx2d::FxRevoluteJoint>(a, b, anchor_a);
    }
    scene_.add_constraint(joint);
    constraints_.push_back(std::move(joint));
  }

  // A joint that went with a removed entity is no longer in the scene; removing it again must be
  // harmless too.
  void unjoin(ByteStream& in) {
    const std::uint8_t selector = in.byte();
    if (constraints_.empty()) return;
    scene_.remove_constraint(*constraints_[selector % constraints_.size()]);
  }

  void arm_callback(ByteStream& in) {
    const std::uint8_t action = in.byte();
    if (action & 1) plan_.remove_selector = in.byte();
    plan_.create_circle = (action & 2) != 0;
  }

  void step(ByteStream& in) {
    const int count = 1 + in.byte() % kMaxStepsPerCall;
    for (int i = 0; i < count && !out_of_steps(); ++i, ++steps_) {
      scene_.step();
      if (tracing_) trace_call(scene_, "one step");
      check_finite_state(scene_, "step");
    }
  }

  fx2d::FxScene scene_;
  std::vector<std::shared_ptr<fx2d::FxConstraint>> constraints_;
  CallbackPlan plan_;
  int steps_ = 0;
  const bool tracing_ = std::getenv("FX2D_FUZZ_TRACE") != nullptr;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool tracing = std::getenv("FX2D_FUZZ_TRACE") != nullptr;  // see trace_call
  ByteStream in(data, size);
  Session session;
  while (!in.empty() && !session.out_of_steps()) {
    try {
      const char* call = session.apply(in);
      if (tracing) trace_call(session.scene(), call);
      check_finite_state(session.scene(), call);
    } catch (const fx2d::FxInvalidArgument&) {
      // The engine refused an invalid call: the expected outcome. Decoding goes on from there.
    }
  }
  return 0;
}
