// Plugin loading and the Engine over a plugin table; invariants in plugin_engine.h.
#include "engines/plugin_engine.h"

#ifdef _WIN32
#define WIN32_LEAN_AND_MEAN
#include <windows.h>
#else
#include <dlfcn.h>
#endif

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <utility>
#include <vector>

#include "common/bounded_read.h"
#include "common/errors.h"

namespace fxbench {
namespace {

// The platform's loader: dlopen on POSIX, LoadLibrary on Windows (ci/cross-mingw's build), where
// every DLL keeps its symbols to itself as RTLD_LOCAL does.
#ifdef _WIN32
void* open_library(const std::string& path) { return LoadLibraryA(path.c_str()); }
void* find_symbol(void* library, const char* name) {
  return reinterpret_cast<void*>(GetProcAddress(static_cast<HMODULE>(library), name));
}
void close_library(void* library) { FreeLibrary(static_cast<HMODULE>(library)); }
std::string loader_error() { return "Windows error " + std::to_string(GetLastError()); }
#else
void* open_library(const std::string& path) { return dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL); }
void* find_symbol(void* library, const char* name) { return dlsym(library, name); }
void close_library(void* library) { dlclose(library); }
std::string loader_error() { return dlerror(); }
#endif

Fx2dBenchVec2 to_c(Vec2 v) { return {v.x, v.y}; }

int32_t body_type_of(BodyType type) {
  switch (type) {
    case BodyType::static_body: return FX2D_BENCH_STATIC_BODY;
    case BodyType::kinematic: return FX2D_BENCH_KINEMATIC_BODY;
    case BodyType::dynamic: return FX2D_BENCH_DYNAMIC_BODY;
  }
  throw std::logic_error("plugin engine: unknown body type");
}

int32_t shape_of(ShapeKind shape) {
  switch (shape) {
    case ShapeKind::circle: return FX2D_BENCH_CIRCLE;
    case ShapeKind::box: return FX2D_BENCH_BOX;
    case ShapeKind::polygon: return FX2D_BENCH_POLYGON;
  }
  throw std::logic_error("plugin engine: unknown shape kind");
}

int32_t joint_of(JointKind joint) {
  return joint == JointKind::distance ? FX2D_BENCH_DISTANCE_JOINT : FX2D_BENCH_REVOLUTE_JOINT;
}

int32_t count_of(std::size_t size) { return static_cast<int32_t>(size); }

// The scene as the flat structs of the ABI, holding everything the structs point to.
class FlatScene {
 public:
  FlatScene(const SceneSpec& spec, std::vector<double> settings) : settings_(std::move(settings)) {
    std::size_t vertex_count = 0;
    for (const BodySpec& body : spec.bodies) vertex_count += body.vertices.size();
    vertices_.reserve(vertex_count);  // bodies point into it: it must never reallocate
    bodies_.reserve(spec.bodies.size());
    for (const BodySpec& body : spec.bodies) bodies_.push_back(flat_body(body));
    joints_.reserve(spec.joints.size());
    for (const JointSpec& joint : spec.joints) {
      joints_.push_back({joint_of(joint.kind), joint.body_a, joint.body_b, to_c(joint.local_anchor_a),
                         to_c(joint.local_anchor_b), joint.length});
    }
    scene_ = {to_c(spec.gravity), spec.dt,
              bodies_.data(),     count_of(bodies_.size()),
              joints_.data(),     count_of(joints_.size()),
              settings_.data(),   count_of(settings_.size())};
  }

  const Fx2dBenchScene& scene() const { return scene_; }

 private:
  Fx2dBenchBody flat_body(const BodySpec& body) {
    const Fx2dBenchVec2* vertices = vertices_.data() + vertices_.size();
    for (const Vec2& v : body.vertices) vertices_.push_back(to_c(v));
    return {body_type_of(body.type),
            shape_of(body.shape),
            body.radius,
            to_c(body.half_extents),
            vertices,
            count_of(body.vertices.size()),
            to_c(body.position),
            body.angle,
            to_c(body.linear_velocity),
            body.angular_velocity,
            body.material.density,
            body.material.static_friction,
            body.material.dynamic_friction,
            body.material.restitution,
            body.bullet ? 1 : 0};
  }

  std::vector<Fx2dBenchVec2> vertices_;
  std::vector<Fx2dBenchBody> bodies_;
  std::vector<Fx2dBenchJoint> joints_;
  std::vector<double> settings_;
  Fx2dBenchScene scene_{};
};

class PluginEngine final : public Engine {
 public:
  explicit PluginEngine(std::shared_ptr<const Plugin> plugin) : plugin_(std::move(plugin)), table_(plugin_->table()) {}
  PluginEngine(const PluginEngine&) = delete;
  PluginEngine& operator=(const PluginEngine&) = delete;
  ~PluginEngine() override {
    if (instance_ != nullptr) table_.destroy(instance_);
  }

  std::vector<std::string> phase_names() const override {
    std::vector<std::string> names;
    for (int32_t i = 0; i < table_.phase_count(); ++i) names.emplace_back(table_.phase_name(i));
    return names;
  }

  void build(const SceneSpec& scene) override {
    const FlatScene flat(scene, knob_values(plugin_->name(), plugin_->knobs(), scene));
    char error[512] = "";
    Fx2dBenchInstance* instance = table_.create(&flat.scene(), error, sizeof error);
    if (instance == nullptr) throw std::runtime_error(error[0] != '\0' ? error : "plugin: create failed");
    if (instance_ != nullptr) table_.destroy(instance_);
    instance_ = instance;
    states_.resize(scene.bodies.size());
  }

  void step() override { table_.step(instance_); }

  void read_phases(std::span<double> ms) const override {
    table_.read_phases(instance_, ms.data(), count_of(ms.size()));
  }

  int contact_count() const override { return table_.contact_count(instance_); }

  const Fx2dBenchInstance* instance_of(const Fx2dBenchPlugin& table) const {
    return &table == &table_ ? instance_ : nullptr;
  }

  void read_state(std::vector<BodyState>& out) const override {
    table_.read_state(instance_, states_.data(), count_of(states_.size()));
    out.resize(states_.size());
    for (std::size_t i = 0; i < states_.size(); ++i) {
      const Fx2dBenchBodyState& s = states_[i];
      out[i] = {{s.position.x, s.position.y}, s.angle, {s.linear_velocity.x, s.linear_velocity.y}, s.angular_velocity};
    }
  }

 private:
  std::shared_ptr<const Plugin> plugin_;  // keeps the library that holds table_ loaded
  const Fx2dBenchPlugin& table_;
  Fx2dBenchInstance* instance_ = nullptr;
  mutable std::vector<Fx2dBenchBodyState> states_;  // read_state's buffer, sized once per build
};

// An engine's name is also a key of the scene format's /solver object: kept to what a JSON
// pointer and a command line take without quoting.
bool is_engine_name(const char* name) {
  const std::string_view text = name != nullptr ? name : "";
  return !text.empty() && std::ranges::all_of(text, [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
  });
}

Knob::Type knob_type(int32_t type) {
  switch (type) {
    case FX2D_BENCH_KNOB_INTEGER:
      return Knob::Type::integer;
    case FX2D_BENCH_KNOB_NUMBER:
      return Knob::Type::number;
    case FX2D_BENCH_KNOB_BOOLEAN:
      return Knob::Type::boolean;
    default:
      throw std::invalid_argument("knob type " + std::to_string(type) +
                                  " is none of integer, number, boolean");
  }
}

// The table's knobs, each checked: a name of its own, a known type, a default inside its range.
std::vector<Knob> knobs_of(const Fx2dBenchPlugin& table) {
  std::vector<Knob> knobs;
  for (int32_t i = 0; i < table.knob_count; ++i) {
    const Fx2dBenchKnob& knob = table.knobs[i];
    if (!is_engine_name(knob.name))
      throw std::invalid_argument("knob " + std::to_string(i) +
                                  ": name is not lower case letters, digits and '_'");
    if (std::ranges::find(knobs, std::string(knob.name), &Knob::name) != knobs.end())
      throw std::invalid_argument(std::string("knob ") + knob.name + " is declared twice");
    if (!(knob.min <= knob.default_value && knob.default_value <= knob.max))
      throw std::invalid_argument(std::string("knob ") + knob.name + ": default outside [min, max]");
    knobs.push_back({knob.name, knob_type(knob.type), knob.min, knob.max, knob.default_value,
                     knob.description != nullptr ? knob.description : ""});
  }
  return knobs;
}

// "chipmunk.iterations, chipmunk.sleeping, ...": the keys it reads, for `engines`.
std::string settings_description(const Plugin& plugin) {
  std::string text;
  // Appended piece by piece: GCC 12 with -flto took the temporaries of `", " + name + ...` for a
  // copy of unbounded size (-Wstringop-overflow) once this was inlined into the test binaries.
  for (const Knob& knob : plugin.knobs()) {
    if (!text.empty()) text += ", ";
    text += plugin.name();
    text += '.';
    text += knob.name;
  }
  return text.empty() ? "no settings" : text;
}

}  // namespace

Plugin::Plugin(void* library, const Fx2dBenchPlugin* table, std::string path)
    : library_(library), table_(table), path_(std::move(path)) {
  if (!is_engine_name(table->name))
    throw std::invalid_argument("engine name is not lower case letters, digits and '_'");
  if (table->knob_count < 0 || (table->knob_count > 0 && table->knobs == nullptr))
    throw std::invalid_argument("knob_count " + std::to_string(table->knob_count) + " without knobs");
  knobs_ = knobs_of(*table);
}

std::shared_ptr<const Plugin> Plugin::load(const std::string& path) {
  const std::string absolute = std::filesystem::absolute(path).lexically_normal().string();
  require_regular_file(absolute, "plugin " + path);
  void* library = open_library(absolute);
  if (library == nullptr) throw InputError("plugin " + path + ": cannot load: " + loader_error());
  const auto close_and_fail = [&](const std::string& message) {
    close_library(library);
    throw InputError("plugin " + path + ": " + message);
  };
  void* entry = find_symbol(library, FX2D_BENCH_PLUGIN_ENTRY);
  if (entry == nullptr) close_and_fail("not an fx2d-bench plugin (no " FX2D_BENCH_PLUGIN_ENTRY " symbol)");
  const Fx2dBenchPlugin* table = reinterpret_cast<Fx2dBenchPluginEntry>(entry)();
  if (table == nullptr) close_and_fail(FX2D_BENCH_PLUGIN_ENTRY " returned no table");
  if (table->abi_version != FX2D_BENCH_PLUGIN_ABI_VERSION) {
    close_and_fail("plugin ABI version " + std::to_string(table->abi_version) +
                   ", this fx2d-bench reads version " + std::to_string(FX2D_BENCH_PLUGIN_ABI_VERSION) +
                   "; rebuild the plugin against this fx2d-bench");
  }
  try {
    return std::shared_ptr<const Plugin>(new Plugin(library, table, absolute));
  } catch (const std::invalid_argument& malformed) {
    close_and_fail(malformed.what());
  }
  return nullptr;
}

std::shared_ptr<const Plugin> Plugin::linked(const Fx2dBenchPlugin& table) {
  return std::shared_ptr<const Plugin>(new Plugin(nullptr, &table, {}));
}

Plugin::~Plugin() {
  if (library_ != nullptr) close_library(library_);
}

std::string Plugin::version() const {
  std::string version = table_->library_version();
  const std::string build = table_->build_description();
  return build.empty() ? version : version + " " + build;
}

EngineCapabilities Plugin::capabilities() const {
  const Fx2dBenchCapabilities& declared = table_->capabilities;
  EngineCapabilities capabilities{.shapes = {}, .joints = {}};
  for (ShapeKind shape : {ShapeKind::circle, ShapeKind::box, ShapeKind::polygon})
    if ((declared.shapes & FX2D_BENCH_BIT(shape_of(shape))) != 0) capabilities.shapes.push_back(shape);
  for (JointKind joint : {JointKind::distance, JointKind::revolute})
    if ((declared.joints & FX2D_BENCH_BIT(joint_of(joint))) != 0) capabilities.joints.push_back(joint);
  if (declared.max_bodies > 0) capabilities.max_bodies = static_cast<std::size_t>(declared.max_bodies);
  if (declared.max_linear_speed > 0.0) capabilities.max_linear_speed = declared.max_linear_speed;
  capabilities.bullets = declared.bullets != 0;
  capabilities.sleeping = declared.sleeping != 0;
  return capabilities;
}

std::unique_ptr<Engine> make_plugin_engine(std::shared_ptr<const Plugin> plugin) {
  return std::make_unique<PluginEngine>(std::move(plugin));
}

const Fx2dBenchInstance* built_instance(const Engine& engine, const Plugin& plugin) {
  const auto* over_a_plugin = dynamic_cast<const PluginEngine*>(&engine);
  return over_a_plugin != nullptr ? over_a_plugin->instance_of(plugin.table()) : nullptr;
}

EngineInfo plugin_engine_info(std::shared_ptr<const Plugin> plugin, std::string name) {
  EngineInfo info;
  info.name = std::move(name);
  info.version = plugin->version();
  info.settings = settings_description(*plugin);
  info.solver = plugin->name();
  info.capabilities = plugin->capabilities();
  info.knobs = plugin->knobs();
  info.plugin_path = plugin->path();
  info.make = [plugin = std::move(plugin)] { return make_plugin_engine(plugin); };
  return info;
}

bool is_plugin_engine_name(std::string_view name) { return name.starts_with(plugin_name_prefix); }

EngineInfo plugin_engine_info(const std::string& engine_name) {
  const std::string spec = engine_name.substr(plugin_name_prefix.size());
  const auto bar = spec.find('|');
  const std::string path = spec.substr(0, bar);
  const std::string label = bar == std::string::npos ? engine_name : spec.substr(bar + 1);
  if (path.empty() || label.empty())
    throw InputError("engine " + engine_name + ": expected plugin:PATH or plugin:PATH|LABEL");
  return plugin_engine_info(Plugin::load(path), label);
}

}  // namespace fxbench
