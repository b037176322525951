// The one interface through which the harness knows a physics engine.
//
// An adapter builds a SceneSpec into its engine (untimed), steps it (timed by the caller), and
// reports state in the spec's body order so that the harness can measure every engine with the
// same geometry. Adapters are listed in engines/registry.cpp; nothing else names an engine.
// Besides the registry's own, an engine can be a plugin: any engine behind the C ABI of
// plugin/fx2d_plugin_abi.h loaded from a shared library (engines/plugin_engine.h), named
// "plugin:/path/to/plugin.so".
#pragma once

#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "scene/scene_spec.h"

namespace fxbench {

struct BodyState {
  Vec2 position;          // body origin, metres
  double angle = 0.0;     // radians
  Vec2 linear_velocity;   // m/s
  double angular_velocity = 0.0;
};

class Engine {
 public:
  virtual ~Engine() = default;

  // Names of this engine's own phase split, in the order read_phases() fills them. Empty for an
  // engine that reports only its total.
  virtual std::vector<std::string> phase_names() const = 0;
  // Creates every body and joint of `scene` with the settings scene.<engine> gives. Called once
  // per instance, never timed. Throws std::runtime_error on what the engine cannot represent.
  virtual void build(const SceneSpec& scene) = 0;
  // Advances one time step of scene.dt.
  virtual void step() = 0;
  // The last step's phase split in milliseconds, one entry per phase_names() entry.
  virtual void read_phases(std::span<double> ms) const = 0;
  // Touching contact manifolds (body pairs in contact) after the last step.
  virtual int contact_count() const = 0;
  // Poses and velocities of all bodies, in SceneSpec::bodies order; `out` is resized to fit.
  virtual void read_state(std::vector<BodyState>& out) const = 0;
};

// What an engine can build. Every command checks each scene against it before measuring anything,
// so a scene an engine cannot represent is refused up front (or, when the engine was not named but
// taken from `all`, skipped) rather than failing after the engines before it were measured.
struct EngineCapabilities {
  std::vector<ShapeKind> shapes{ShapeKind::circle, ShapeKind::box, ShapeKind::polygon};
  std::vector<JointKind> joints{JointKind::distance, JointKind::revolute};
  std::size_t max_bodies = std::numeric_limits<std::size_t>::max();
  double max_linear_speed = std::numeric_limits<double>::infinity();  // m/s, of any body at the start
  bool bullets = true;   // honours a body's bullet flag; false: a scene with a bullet is refused
  bool sleeping = true;  // resting bodies can sleep (listed, never a reason to refuse)
};

// What `scene` needs that `capabilities` lack, as a phrase that completes "cannot build ..."
// ("polygons", "distance joints", "bullets", "more than 65536 bodies", "bodies faster than 1000 m/s");
// nullopt when it can build it all.
std::optional<std::string> missing_capability(const EngineCapabilities& capabilities, const SceneSpec& scene);

// One solver setting an engine reads from /solver/<EngineInfo::solver>/<name> (a plugin's
// Fx2dBenchKnob): what `engines` lists, the harness validates and `sweep --axis` sweeps.
struct Knob {
  enum class Type { integer, number, boolean };
  std::string name;
  Type type = Type::integer;
  double min = 0.0;  // inclusive bounds
  double max = 0.0;
  double default_value = 0.0;
  std::string description;
};

struct EngineInfo {
  std::string name;       // what --engine selects: "fx2d", "box2d", "ode", or a plugin's name
  std::string version;    // the library's version, e.g. "2.4.1"; a plugin adds which build it is
  std::string settings;   // one line describing the solver settings it reads from a scene
  // Makes a fresh, unbuilt instance. A function object, so a plugin's entry can hold its library.
  std::function<std::unique_ptr<Engine>()> make;
  std::string solver;     // the scene's /solver/<solver> block it reads: "fx2d" for an Fx2D plugin
  EngineCapabilities capabilities;
  std::vector<Knob> knobs;
  // The plugin file the engine was loaded from, absolute; empty for one linked into the binary.
  std::string plugin_path;
  // Why a plugin of the registry cannot run (it failed to load: a broken install), as one line;
  // empty when it can. Such an engine is listed, and refused when a command selects it.
  std::string unavailable;
};

// The value of each of `knobs` in `scene`, in their order: the resolved scene's
// /solver/<solver>/<knob>, or the knob's default where the scene leaves it out. Throws InputError
// naming the scene's file (or, for a scene of no file, the scene) and the JSON pointer of a key
// that is no knob or a value out of its range.
std::vector<double> knob_values(const std::string& solver, std::span<const Knob> knobs,
                                const SceneSpec& scene);
// What `knob` takes, as errors and listings say it: "an integer from 1 to 1000", "true or false".
std::string knob_range_text(const Knob& knob);
// The engine's settings in `scene` as a JSON object: the resolved /solver/<solver> block, with
// every knob it leaves out at its default. What result files record as the settings of a run.
std::string engine_settings_json(const EngineInfo& engine, const SceneSpec& scene);

// Every engine the harness knows, in a fixed order.
std::span<const EngineInfo> engine_registry();
// The entry named `name`, or nullptr. A name "plugin:PATH" or "plugin:PATH|LABEL" loads the
// plugin at PATH once per process (named LABEL, or the whole name) and returns its entry, which
// lives as long as the process; a plugin that cannot be loaded throws InputError.
const EngineInfo* find_engine(const std::string& name);

}  // namespace fxbench
