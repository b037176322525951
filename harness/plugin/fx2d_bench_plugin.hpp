// The C++ side of the plugin SDK: turns one engine class into the C table of fx2d_plugin_abi.h, so
// that an adapter holds only what is its engine's own (harness/plugin/README.md walks through it).
//
// An adapter writes a class World:
//   explicit World(const Fx2dBenchScene& scene);  // builds the scene; throws to refuse it
//   void step();                                  // one step of the scene's dt
//   int32_t contact_count() const;                // touching body pairs after the last step
//   Fx2dBenchBodyState body_state(std::size_t body) const;  // the scene's body number `body`
// and, if the engine times its own phases,
//   static int32_t phase_count(); static const char* phase_name(int32_t phase);
//   void read_phases(double* ms, int32_t count) const;
// then describes the engine and exports the table in one line:
//   constexpr fx2d_bench::EngineDescription my_engine{.name = "my_engine", .knobs = knobs, ...};
//   FX2D_BENCH_EXPORT_PLUGIN(World, my_engine)
//
// Invariant: no exception leaves the table. create() checks the settings' count and that every
// body's type, shape and joint's kind is one the description's capabilities name (so a World
// never meets an unknown kind), builds a World and turns any exception into the one-line error
// "<name> plugin: <what>"; an exception of type fx2d_bench::Refusal gives its message alone, for
// an engine that names itself. Each World is handed out inside an Instance, as the opaque
// Fx2dBenchInstance* it was cast to, and cast back only to that Instance.
#ifndef FX2D_BENCH_PLUGIN_HPP
#define FX2D_BENCH_PLUGIN_HPP

#include <algorithm>
#include <concepts>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "fx2d_plugin_abi.h"

namespace fx2d_bench {

// An exception whose message is the whole error line, without the "<name> plugin: " prefix.
class Refusal : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

inline const char* no_text() { return ""; }

// Everything of the table that is not a function of a built scene.
struct EngineDescription {
  const char* name = "";  // lower case, digits, '_': also the scene's /solver/<name> block
  const char* (*library_version)() = &no_text;
  const char* (*build_description)() = &no_text;  // which build this is; may stay empty
  std::span<const Fx2dBenchKnob> knobs;
  Fx2dBenchCapabilities capabilities{};
};

// Capabilities' bits for an engine that builds every shape kind, or every joint kind.
constexpr uint32_t all_shapes =
    FX2D_BENCH_BIT(FX2D_BENCH_CIRCLE) | FX2D_BENCH_BIT(FX2D_BENCH_BOX) | FX2D_BENCH_BIT(FX2D_BENCH_POLYGON);
constexpr uint32_t all_joints =
    FX2D_BENCH_BIT(FX2D_BENCH_DISTANCE_JOINT) | FX2D_BENCH_BIT(FX2D_BENCH_REVOLUTE_JOINT);

// A polygon body's vertices, each converted to the engine's point type by `convert`.
template <class Convert>
auto vertices(const Fx2dBenchBody& body, Convert convert) {
  std::vector<decltype(convert(Fx2dBenchVec2{}))> points;
  for (int32_t i = 0; i < body.vertex_count; ++i) points.push_back(convert(body.vertices[i]));
  return points;
}

// One object of a C engine's, freed by the engine's own `free_function` (e.g. cpBodyFree), so that
// a World's members free what a constructor that throws half way has allocated.
template <auto free_function>
struct FreeWith {
  template <class T>
  void operator()(T* object) const {
    free_function(object);
  }
};
template <class T, auto free_function>
using Owned = std::unique_ptr<T, FreeWith<free_function>>;

// The engine body a joint names by its index into the scene's bodies, refused when out of range.
template <class Body>
const Body& joint_body(const std::vector<Body>& bodies, int32_t index) {
  if (index < 0 || static_cast<std::size_t>(index) >= bodies.size())
    throw std::invalid_argument("joint body index " + std::to_string(index) + " out of range");
  return bodies[static_cast<std::size_t>(index)];
}

namespace detail {

// One built scene: the adapter's World and the scene's body count, the most read_state() reads.
template <class World>
struct Instance {
  World world;
  std::size_t body_count;
};

template <class World>
World& world(Fx2dBenchInstance* instance) {
  return reinterpret_cast<Instance<World>*>(instance)->world;
}

template <class World>
const Instance<World>& instance_of(const Fx2dBenchInstance* instance) {
  return *reinterpret_cast<const Instance<World>*>(instance);
}

template <class World>
const World& world(const Fx2dBenchInstance* instance) {
  return instance_of<World>(instance).world;
}

inline void copy_error(const std::string& message, char* error, size_t error_size) {
  if (error != nullptr && error_size > 0) std::snprintf(error, error_size, "%s", message.c_str());
}

// Refuses a body or joint of a kind outside `capabilities` (the harness checks them before
// creating, so this meets only a plugin driven by hand), so that an adapter needs no case for it.
inline void check_kinds(const Fx2dBenchScene& scene, const Fx2dBenchCapabilities& capabilities) {
  const auto within = [](int32_t kind, uint32_t kinds) {
    return kind >= 0 && kind < 32 && (kinds & FX2D_BENCH_BIT(kind)) != 0;
  };
  for (int32_t i = 0; i < scene.body_count; ++i) {
    const Fx2dBenchBody& body = scene.bodies[i];
    if (body.type < FX2D_BENCH_STATIC_BODY || body.type > FX2D_BENCH_DYNAMIC_BODY)
      throw std::invalid_argument("body " + std::to_string(i) + ": unknown body type " +
                                  std::to_string(body.type));
    if (!within(body.shape, capabilities.shapes))
      throw std::invalid_argument("body " + std::to_string(i) + ": shape kind " + std::to_string(body.shape) +
                                  " is not one the engine builds");
  }
  for (int32_t i = 0; i < scene.joint_count; ++i) {
    if (!within(scene.joints[i].kind, capabilities.joints))
      throw std::invalid_argument("joint " + std::to_string(i) + ": joint kind " +
                                  std::to_string(scene.joints[i].kind) + " is not one the engine builds");
  }
}

template <class World>
constexpr bool has_phases = requires(const World& world, double* ms) {
  { World::phase_count() } -> std::same_as<int32_t>;
  { World::phase_name(0) } -> std::same_as<const char*>;
  world.read_phases(ms, 0);
};

// One table's functions; `engine` is the description the table was made from.
template <class World, const EngineDescription& engine>
struct Functions {
  static Fx2dBenchInstance* create(const Fx2dBenchScene* scene, char* error, size_t error_size) {
    const std::string prefix = std::string(engine.name) + " plugin: ";
    try {
      if (static_cast<std::size_t>(scene->setting_count) != engine.knobs.size())
        throw std::invalid_argument("expected one setting per knob");
      check_kinds(*scene, engine.capabilities);
      return reinterpret_cast<Fx2dBenchInstance*>(
          new Instance<World>{World(*scene), static_cast<std::size_t>(std::max(scene->body_count, 0))});
    } catch (const Refusal& refusal) {
      copy_error(refusal.what(), error, error_size);
    } catch (const std::exception& failure) {
      copy_error(prefix + failure.what(), error, error_size);
    } catch (...) {
      copy_error(prefix + "unknown error while building the scene", error, error_size);
    }
    return nullptr;
  }
  static void destroy(Fx2dBenchInstance* instance) { delete reinterpret_cast<Instance<World>*>(instance); }
  static void step(Fx2dBenchInstance* instance) { world<World>(instance).step(); }
  static int32_t contact_count(const Fx2dBenchInstance* instance) {
    return world<World>(instance).contact_count();
  }
  static void read_state(const Fx2dBenchInstance* instance, Fx2dBenchBodyState* out, int32_t count) {
    const Instance<World>& built = instance_of<World>(instance);
    const std::size_t bodies = std::min(static_cast<std::size_t>(std::max(count, 0)), built.body_count);
    for (std::size_t i = 0; i < bodies; ++i) out[i] = built.world.body_state(i);
  }
  static int32_t phase_count() {
    if constexpr (has_phases<World>) return World::phase_count();
    return 0;
  }
  static const char* phase_name(int32_t phase) {
    if constexpr (has_phases<World>) return World::phase_name(phase);
    return "";
  }
  static void read_phases(const Fx2dBenchInstance* instance, double* ms, int32_t count) {
    if constexpr (has_phases<World>) world<World>(instance).read_phases(ms, count);
  }
};

}  // namespace detail

// The World inside an instance that plugin_table<World, ...>()'s create() made: for a program that
// links the table in (as fx2d-bench does its built-in engines) and reads more of its own World
// than the table carries, such as a test's diagnostic. Nothing else may call it.
template <class World>
const World& built_world(const Fx2dBenchInstance* instance) {
  return detail::world<World>(instance);
}

// The C table of World, described by `engine` (a constant of static storage, which the table's
// create() reads for the name and the knob count).
template <class World, const EngineDescription& engine>
constexpr Fx2dBenchPlugin plugin_table() {
  using F = detail::Functions<World, engine>;
  return {FX2D_BENCH_PLUGIN_ABI_VERSION,
          engine.name,
          engine.library_version,
          engine.build_description,
          engine.knobs.data(),
          static_cast<int32_t>(engine.knobs.size()),
          engine.capabilities,
          &F::create,
          &F::destroy,
          &F::step,
          &F::phase_count,
          &F::phase_name,
          &F::read_phases,
          &F::contact_count,
          &F::read_state};
}

}  // namespace fx2d_bench

// Defines the plugin's one exported symbol, returning the table of class `World` described by
// `description` (an fx2d_bench::EngineDescription of static storage).
#define FX2D_BENCH_EXPORT_PLUGIN(World, description)                                      \
  extern "C" FX2D_BENCH_PLUGIN_EXPORT const Fx2dBenchPlugin* fx2d_bench_plugin_v1(void) { \
    static const Fx2dBenchPlugin table = fx2d_bench::plugin_table<World, description>();  \
    return &table;                                                                        \
  }

#endif  // FX2D_BENCH_PLUGIN_HPP
