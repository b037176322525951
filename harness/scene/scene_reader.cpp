// Reads a parsed scene document into a SceneSpec part by part (scene_reader.h): schema and
// settings, solver, bounds, materials, generators expanded into explicit bodies, bodies, joints.
#include "scene/scene_reader.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <span>
#include <string>
#include <vector>

namespace fxbench::scene_detail {
namespace {

constexpr std::string_view kSchema = "fx2d.scene/1";
// Far above the largest scene we benchmark, and refused before any body is allocated.
constexpr int kMaxBodies = 1'000'000;
// Steps, and bodies per row or column: anything larger is a typo.
constexpr int kMaxCount = 1'000'000'000;
// An "auto" ground reaches this far beyond the outermost body, so that nothing that slides or
// tumbles a little falls off its edge.
constexpr double kAutoGroundMargin = 10.0;
// Box2D 2.4's b2_maxPolygonVertices: the smallest limit among the engines.
constexpr std::size_t kMaxPolygonVertices = 8;

// `inherited` supplies every field the object leaves out; "friction" sets both frictions and is
// folded into them, so that the two spellings of one material resolve (and hash) the same.
MaterialSpec read_material(ObjectReader& parent, const MaterialSpec& inherited) {
  ObjectReader reader(parent.errors(), parent.slot("material", Json::object()), parent.at("material"));
  MaterialSpec material;
  material.density = reader.number("density", inherited.density, kPositive);
  const std::optional<double> friction = reader.optional_number("friction", kNonNegative);
  material.static_friction =
      reader.number("static_friction", friction.value_or(inherited.static_friction), kNonNegative);
  material.dynamic_friction =
      reader.number("dynamic_friction", friction.value_or(inherited.dynamic_friction), kNonNegative);
  material.restitution = reader.number("restitution", inherited.restitution, kUnitInterval);
  reader.finish();
  reader.erase("friction");
  return material;
}

// An engine's block of knobs (Fx2D's, Box2D's, ODE's, or a plugin engine's): an object of numbers and
// true/false under the engine's name, kept as given; the engine checks it against its knobs
// (engines/engine.h, knob_values) when a command selects it, the one check of its values. A name a typo away
// from one of the format's own blocks is that typo, refused. Each value's place is kept for that check.
void read_knob_blocks(ObjectReader& solver, const Json& blocks, std::map<std::string, std::string>& places) {
  const std::vector<std::string> format_blocks(format_solver_blocks.begin(), format_solver_blocks.end());
  for (const auto& [name, block] : blocks.items()) {
    if (std::ranges::find(format_blocks, name) == format_blocks.end() && near_key(name, format_blocks))
      solver.errors().fail(solver.at(name), unknown_key_message(name, format_blocks), true);
    const bool is_engine_name = !name.empty() && std::ranges::all_of(name, [](char c) {
      return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
    });
    if (!is_engine_name)
      solver.errors().fail(solver.at(name), "expected an engine's name: lower case letters, digits and '_'",
                           true);
    ObjectReader settings(solver.errors(), solver.slot(name, Json::object()), solver.at(name));
    for (const auto& [key, value] : block.items()) {
      if (!value.is_number() && !value.is_boolean())
        settings.errors().expected(settings.at(key), "a number or true or false", value);
      places[settings.at(key)] = settings.errors().where(settings.at(key));
    }
  }
}

// A number is recorded in the kind of its key's default, as the format wrote these keys before
// the engines declared knobs (an erp of 1 as 1.0, iterations of 20.0 as 20), so that the two
// spellings of one value resolve, and hash, the same. Anything else is left for the knobs to refuse.
void record_in_kind_of(Json& value, const Json& default_value) {
  if (!value.is_number()) return;
  const double number = value.get<double>();
  if (default_value.is_number_float()) {
    value = number;
  } else if (default_value.is_number_integer() && value.is_number_float() && number == std::floor(number) &&
             std::abs(number) <= std::numeric_limits<int>::max()) {
    value = static_cast<int>(number);
  }
}

// Keys of Fx2D's, Box2D's and ODE's blocks that the format wrote into every resolved scene before
// those engines declared knobs, still written when left out (at the engines' defaults) so that a
// scene's resolved form names its schedule and keeps its hash (scenes/README.md). Their values
// are checked by the engine's knobs, as the block's others are.
void record_defaults(ObjectReader& solver, const std::string& engine, const Json& defaults) {
  ObjectReader block(solver.errors(), solver.slot(engine, Json::object()), solver.at(engine));
  for (const auto& [key, value] : defaults.items()) record_in_kind_of(block.slot(key, value), value);
}

void read_solver(ObjectReader& scene, SceneSpec& spec) {
  Json& blocks = scene.slot("solver", Json::object());
  ObjectReader solver(scene.errors(), blocks, scene.at("solver"));
  read_knob_blocks(solver, blocks, spec.knob_places);
  record_defaults(solver, "fx2d", {{"substeps", 8}, {"velocity_passes", 1}, {"sleeping", true}});
  record_defaults(solver, "box2d",
                  {{"velocity_iterations", 8}, {"position_iterations", 3}, {"sleeping", true}});
  record_defaults(solver, "ode", {{"iterations", 20}, {"erp", 0.2}, {"cfm", 1e-5}, {"auto_disable", true}});
  solver.finish();
}

void read_bounds(ObjectReader& scene, SceneSpec& spec) {
  ObjectReader bounds(scene.errors(), scene.slot("bounds", Json::object()), scene.at("bounds"));
  spec.bounds_lower = bounds.vec2("lower", SceneSpec{}.bounds_lower, kSigned);
  spec.bounds_upper = bounds.vec2("upper", SceneSpec{}.bounds_upper, kSigned);
  if (spec.bounds_upper.x <= spec.bounds_lower.x || spec.bounds_upper.y <= spec.bounds_lower.y) {
    bounds.errors().fail(bounds.at("upper"),
                         "expected a corner above and right of /bounds/lower, got " +
                             describe_value(Json::array({spec.bounds_upper.x, spec.bounds_upper.y})));
  }
  bounds.finish();
}

// Half the body's extent along x, whatever its angle.
double half_width_along_x(const BodySpec& body) {
  switch (body.shape) {
    case ShapeKind::circle:
      return body.radius;
    case ShapeKind::box:
      return body.half_extents.x * std::abs(std::cos(body.angle)) +
             body.half_extents.y * std::abs(std::sin(body.angle));
    case ShapeKind::polygon: {
      double reach = 0.0;
      for (const Vec2& v : body.vertices) reach = std::max(reach, std::hypot(v.x, v.y));
      return reach;
    }
  }
  return 0.0;
}

BodySpec make_box(BodyType type, Vec2 center, Vec2 half_extents, const MaterialSpec& material) {
  BodySpec body;
  body.type = type;
  body.shape = ShapeKind::box;
  body.half_extents = half_extents;
  body.position = center;
  body.material = material;
  return body;
}

// A ground whose half-width is "auto", sized once every other body is known.
struct PendingGround {
  std::size_t body_index;
  std::size_t generator_index;
};

struct GeneratorInput {
  ObjectReader& reader;
  int size;
  const MaterialSpec& scene_material;
  std::size_t generator_index;
  bool size_read = false;  // whether the generator's count defaulted to the scene's size
};

// How many bodies a generator adds: `count` (default: the scene's size), refused before any
// allocation if the scene would then exceed kMaxBodies.
int read_count(GeneratorInput& in, const std::vector<BodySpec>& bodies) {
  // A count left to default is the scene's size, so a scene too large is blamed on /size (and on
  // the --bodies that set it).
  in.size_read = !in.reader.has("count");
  const std::string blamed = in.size_read ? "/size" : in.reader.at("count");
  const int count = in.reader.integer("count", in.size, Range{0.0, kMaxBodies});
  const std::size_t total = bodies.size() + static_cast<std::size_t>(count);
  if (total > static_cast<std::size_t>(kMaxBodies)) {
    in.reader.errors().fail(blamed, "expected at most " + std::to_string(kMaxBodies) +
                                        " bodies in the scene, got " + std::to_string(total));
  }
  return count;
}

void expand_ground(GeneratorInput& in, std::vector<BodySpec>& bodies, std::vector<PendingGround>& pending) {
  const double top = in.reader.number("top", 0.0, kSigned);
  const double thickness = in.reader.number("thickness", 1.0, kPositive);
  const double center_x = in.reader.number("center_x", 0.0, kSigned);
  const std::optional<double> half_width = in.reader.number_or("half_width", "auto", kPositive);
  const MaterialSpec material = read_material(in.reader, in.scene_material);
  if (!half_width) pending.push_back({bodies.size(), in.generator_index});
  bodies.push_back(make_box(BodyType::static_body, {center_x, top - 0.5 * thickness},
                            {half_width.value_or(0.0), 0.5 * thickness}, material));
}

void expand_walls(GeneratorInput& in, std::vector<BodySpec>& bodies, std::vector<PendingGround>&) {
  const double inner = in.reader.number("inner", 10.0, kPositive);
  const double thickness = in.reader.number("thickness", 1.0, kPositive);
  const double height = in.reader.number("height", 100.0, kPositive);
  const double bottom = in.reader.number("bottom", 0.0, kSigned);
  const MaterialSpec material = read_material(in.reader, in.scene_material);
  const Vec2 half_extents{0.5 * thickness, 0.5 * height};
  const double center_y = bottom + half_extents.y;
  bodies.push_back(
      make_box(BodyType::static_body, {-inner - half_extents.x, center_y}, half_extents, material));
  bodies.push_back(
      make_box(BodyType::static_body, {inner + half_extents.x, center_y}, half_extents, material));
}

void expand_box_columns(GeneratorInput& in, std::vector<BodySpec>& bodies, std::vector<PendingGround>&) {
  const int count = read_count(in, bodies);
  const int per_column = in.reader.integer("per_column", 10, Range{1.0, kMaxCount});
  const double x0 = in.reader.number("x0", 0.0, kSigned);
  const double column_spacing = in.reader.number("column_spacing", 2.0, kSigned);
  const double bottom = in.reader.number("bottom", 0.0, kSigned);
  const Vec2 half = in.reader.vec2("half_extents", {0.5, 0.5}, kPositive);
  const MaterialSpec material = read_material(in.reader, in.scene_material);
  bodies.reserve(bodies.size() + static_cast<std::size_t>(count));
  for (int k = 0; k < count; ++k) {
    const int column = k / per_column;
    const int level = k % per_column;
    const Vec2 center{x0 + column_spacing * column, bottom + half.y + 2.0 * half.y * level};
    bodies.push_back(make_box(BodyType::dynamic, center, half, material));
  }
}

void expand_circle_rows(GeneratorInput& in, std::vector<BodySpec>& bodies, std::vector<PendingGround>&) {
  const int count = read_count(in, bodies);
  const int per_row = in.reader.integer("per_row", 10, Range{1.0, kMaxCount});
  const double radius = in.reader.number("radius", 0.5, kPositive);
  const Vec2 origin = in.reader.vec2("origin", {0.0, 0.5}, kSigned);
  const Vec2 spacing = in.reader.vec2("spacing", {1.0, 1.0}, kSigned);
  const double odd_row_offset = in.reader.number("odd_row_offset", 0.0, kSigned);
  const MaterialSpec material = read_material(in.reader, in.scene_material);
  bodies.reserve(bodies.size() + static_cast<std::size_t>(count));
  for (int k = 0; k < count; ++k) {
    const int row = k / per_row;
    const int column = k % per_row;
    BodySpec body;
    body.shape = ShapeKind::circle;
    body.radius = radius;
    body.position = {origin.x + spacing.x * column + (row % 2 == 1 ? odd_row_offset : 0.0),
                     origin.y + spacing.y * row};
    body.material = material;
    bodies.push_back(body);
  }
}

// Angle of box i: step * (((multiplier * i) mod modulus) - offset), a deterministic spread of
// tilts that needs no random numbers.
struct TiltRule {
  double step = 0.0;
  int multiplier = 1;
  int modulus = 1;
  int offset = 0;

  double angle(int i) const {
    const long long residue = (static_cast<long long>(multiplier) * i) % modulus;
    return step * static_cast<double>(residue - offset);
  }
};

TiltRule read_tilt(ObjectReader& parent) {
  ObjectReader reader(parent.errors(), parent.slot("tilt", Json::object()), parent.at("tilt"));
  TiltRule tilt;
  tilt.step = reader.number("step", 0.0, kSigned);
  tilt.multiplier = reader.integer("multiplier", 1, Range{0.0, kMaxCount});
  tilt.modulus = reader.integer("modulus", 1, Range{1.0, kMaxCount});
  tilt.offset = reader.integer("offset", 0, Range{-kMaxCount, kMaxCount, false, false});
  reader.finish();
  return tilt;
}

void expand_box_grid(GeneratorInput& in, std::vector<BodySpec>& bodies, std::vector<PendingGround>&) {
  const int count = read_count(in, bodies);
  const int per_row = in.reader.integer("per_row", 10, Range{1.0, kMaxCount});
  const Vec2 origin = in.reader.vec2("origin", {0.0, 0.5}, kSigned);
  const Vec2 spacing = in.reader.vec2("spacing", {1.0, 1.0}, kSigned);
  const Vec2 half = in.reader.vec2("half_extents", {0.5, 0.5}, kPositive);
  const TiltRule tilt = read_tilt(in.reader);
  const MaterialSpec material = read_material(in.reader, in.scene_material);
  bodies.reserve(bodies.size() + static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    BodySpec body = make_box(BodyType::dynamic,
                             {origin.x + spacing.x * (i % per_row), origin.y + spacing.y * (i / per_row)},
                             half, material);
    body.angle = tilt.angle(i);
    bodies.push_back(body);
  }
}

using ExpandFn = void (*)(GeneratorInput&, std::vector<BodySpec>&, std::vector<PendingGround>&);

const std::vector<std::string> kGeneratorTypes{"ground", "walls", "box_columns", "circle_rows", "box_grid"};
constexpr ExpandFn kGeneratorExpanders[] = {expand_ground, expand_walls, expand_box_columns,
                                            expand_circle_rows, expand_box_grid};

// A generator whose spacing multiplies a count can put bodies anywhere; keep them within range.
void check_generated_positions(const ObjectReader& reader, std::span<const BodySpec> generated) {
  for (const BodySpec& body : generated) {
    if (std::abs(body.position.x) > kMaxMagnitude || std::abs(body.position.y) > kMaxMagnitude) {
      reader.errors().fail(reader.pointer(),
                           "expected bodies within " + format_bound(kMaxMagnitude) +
                               " m of the origin, got one at " +
                               describe_value(Json::array({body.position.x, body.position.y})));
    }
  }
}

// Expands every generator; whether any took its count from the scene's size.
bool expand_generators(ObjectReader& scene, SceneSpec& spec, const MaterialSpec& material,
                       std::vector<PendingGround>& pending) {
  bool size_read = false;
  for_each_element(scene, "generators", [&](Json& element, const std::string& pointer, std::size_t index) {
    ObjectReader reader(scene.errors(), element, pointer, "a generator object with a \"type\"");
    const std::size_t type = reader.choice("type", std::nullopt, kGeneratorTypes);
    const std::size_t first = spec.bodies.size();
    GeneratorInput input{reader, spec.size, material, index};
    kGeneratorExpanders[type](input, spec.bodies, pending);
    size_read |= input.size_read;
    reader.finish();
    check_generated_positions(reader, std::span(spec.bodies).subspan(first));
  });
  return size_read;
}

const std::string kShapeForms = R"({"circle": radius}, {"box": [hw, hh]} or {"polygon": [[x, y], ...]})";

// Convex, counter-clockwise, no repeated points: every other vertex lies strictly left of
// every edge.
bool is_convex_counter_clockwise(std::span<const Vec2> vertices) {
  const std::size_t n = vertices.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 a = vertices[i];
    const Vec2 b = vertices[(i + 1) % n];
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i || j == (i + 1) % n) continue;
      const Vec2 p = vertices[j];
      if ((b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x) <= 0.0) return false;
    }
  }
  return true;
}

void read_polygon(const ErrorReporter& errors, Json& value, const std::string& pointer, BodySpec& body) {
  const std::string what = "a convex counter-clockwise polygon of 3 to " +
                           std::to_string(kMaxPolygonVertices) + " [x, y] vertices";
  if (!value.is_array() || value.size() < 3 || value.size() > kMaxPolygonVertices)
    errors.expected(pointer, what, value);
  body.vertices.clear();
  for (std::size_t i = 0; i < value.size(); ++i) {
    body.vertices.push_back(read_vec2(errors, value[i], child_pointer(pointer, i), kSigned));
  }
  if (!is_convex_counter_clockwise(body.vertices)) errors.expected(pointer, what, value);
}

const std::vector<std::string> kShapeKinds{"circle", "box", "polygon"};

void read_shape(ObjectReader& parent, BodySpec& body) {
  const ErrorReporter& errors = parent.errors();
  Json& shape = parent.required("shape", kShapeForms);
  if (!shape.is_object() || shape.size() != 1) errors.expected(parent.at("shape"), kShapeForms, shape);
  const std::string kind = shape.begin().key();
  const std::string pointer = child_pointer(parent.at("shape"), kind);
  Json& value = shape.begin().value();
  if (kind == "circle") {
    body.shape = ShapeKind::circle;
    body.radius = read_number(errors, value, pointer, kPositive);
  } else if (kind == "box") {
    body.shape = ShapeKind::box;
    body.half_extents = read_vec2(errors, value, pointer, kPositive);
  } else if (kind == "polygon") {
    body.shape = ShapeKind::polygon;
    read_polygon(errors, value, pointer, body);
  } else {
    errors.fail(pointer, unknown_key_message(kind, kShapeKinds), true);
  }
}

const std::vector<std::string> kBodyTypes{"static", "kinematic", "dynamic"};
constexpr BodyType kBodyTypeValues[] = {BodyType::static_body, BodyType::kinematic, BodyType::dynamic};

void read_explicit_bodies(ObjectReader& scene, SceneSpec& spec, const MaterialSpec& material) {
  for_each_element(scene, "bodies", [&](Json& element, const std::string& pointer, std::size_t) {
    if (spec.bodies.size() >= static_cast<std::size_t>(kMaxBodies)) {
      scene.errors().fail(
          pointer, "expected at most " + std::to_string(kMaxBodies) + " bodies in the scene, got more");
    }
    ObjectReader reader(scene.errors(), element, pointer);
    BodySpec body;
    body.type = kBodyTypeValues[reader.choice("type", "dynamic", kBodyTypes)];
    read_shape(reader, body);
    body.position = reader.vec2("position", {}, kSigned);
    body.angle = reader.number("angle", 0.0, kSigned);
    body.linear_velocity = reader.vec2("velocity", {}, kSigned);
    body.angular_velocity = reader.number("angular_velocity", 0.0, kSigned);
    body.material = read_material(reader, material);
    body.bullet = reader.optional_flag("bullet");
    reader.finish();
    spec.bodies.push_back(std::move(body));
  });
}

const std::vector<std::string> kJointTypes{"distance", "revolute"};
constexpr JointKind kJointKindValues[] = {JointKind::distance, JointKind::revolute};

void read_joints(ObjectReader& scene, SceneSpec& spec) {
  for_each_element(scene, "joints", [&](Json& element, const std::string& pointer, std::size_t) {
    ObjectReader reader(scene.errors(), element, pointer);
    JointSpec joint;
    joint.kind = kJointKindValues[reader.choice("type", std::nullopt, kJointTypes)];
    const std::string index_what = spec.bodies.empty()
                                       ? "a body index, of which the scene has none"
                                       : "a body index from 0 to " + std::to_string(spec.bodies.size() - 1);
    const auto read_body = [&](std::string_view key) {
      const Json& value = reader.required(key, index_what);
      const bool valid = value.is_number_unsigned() && value.get<std::size_t>() < spec.bodies.size();
      if (!valid) reader.errors().expected(reader.at(key), index_what, value);
      return value.get<int>();
    };
    joint.body_a = read_body("a");
    joint.body_b = read_body("b");
    if (joint.body_b == joint.body_a) {
      reader.errors().expected(reader.at("b"), "a body other than a (" + std::to_string(joint.body_a) + ")",
                               Json(joint.body_b));
    }
    // A joint acts only through a dynamic body; between two others no engine can build it (Fx2D and
    // ODE refused it mid-build, Chipmunk2D aborted the process).
    const auto dynamic = [&](int body) { return spec.bodies[static_cast<std::size_t>(body)].type == BodyType::dynamic; };
    if (!dynamic(joint.body_a) && !dynamic(joint.body_b)) {
      reader.errors().expected(reader.at("b"), "a dynamic body, since body a (" + std::to_string(joint.body_a) +
                                                   ") is not dynamic",
                               Json(joint.body_b));
    }
    joint.local_anchor_a = reader.vec2("anchor_a", {}, kSigned);
    joint.local_anchor_b = reader.vec2("anchor_b", {}, kSigned);
    if (joint.kind == JointKind::distance) {
      joint.length = reader.number_or("length", "as_built", kNonNegative).value_or(-1.0);
    }
    reader.finish();
    spec.joints.push_back(joint);
  });
}

// Sizes each "auto" ground to reach kAutoGroundMargin beyond every other body, and records the
// width in the document so that the resolved scene states it.
void size_auto_grounds(Json& document, SceneSpec& spec, std::span<const PendingGround> pending) {
  for (const PendingGround& ground : pending) {
    BodySpec& body = spec.bodies[ground.body_index];
    double reach = 0.0;
    for (std::size_t i = 0; i < spec.bodies.size(); ++i) {
      const bool is_auto_ground =
          std::ranges::any_of(pending, [&](const PendingGround& p) { return p.body_index == i; });
      if (is_auto_ground) continue;
      const BodySpec& other = spec.bodies[i];
      reach = std::max(reach, std::abs(other.position.x - body.position.x) + half_width_along_x(other));
    }
    body.half_extents.x = reach + kAutoGroundMargin;
    document["generators"][ground.generator_index]["half_width"] = body.half_extents.x;
  }
}

const std::vector<std::string> kMetrics{"penetration", "displacement"};
constexpr PrimaryMetric kMetricValues[] = {PrimaryMetric::penetration, PrimaryMetric::displacement};

}  // namespace

SceneSpec read_scene(const ErrorReporter& errors, Json& document, bool size_must_be_read) {
  ObjectReader scene(errors, document, "", "a scene object");
  Json& schema = scene.required("schema", in_quotes(kSchema));
  if (!schema.is_string() || schema.get<std::string>() != kSchema)
    errors.expected(scene.at("schema"), in_quotes(kSchema), schema);

  SceneSpec spec;
  spec.name = scene.text("name", std::filesystem::path(errors.origin()).stem().string());
  scene.text("description", "");
  spec.size = scene.integer("size", 0, Range{0.0, kMaxBodies});
  spec.steps = scene.integer("steps", spec.steps, Range{0.0, kMaxCount});
  spec.dt = scene.number("dt", spec.dt, Range{1.0e-6, 1.0});  // Fx2D's own bounds (FxSceneSettings::dt)
  spec.gravity = scene.vec2("gravity", spec.gravity, kSigned);
  spec.primary_metric = kMetricValues[scene.choice("primary_metric", "penetration", kMetrics)];
  read_bounds(scene, spec);
  read_solver(scene, spec);
  const MaterialSpec material = read_material(scene, MaterialSpec{});

  std::vector<PendingGround> pending_grounds;
  const bool size_read = expand_generators(scene, spec, material, pending_grounds);
  // A size nothing reads would only mislabel the results: a listed scene run "at 150 bodies"
  // would still hold the bodies it lists. (A resolved scene keeps its size beside the counts it
  // gave every generator: read from a file, an unread size is no mistake.)
  if (size_must_be_read && !size_read) {
    scene.errors().fail("/size", scene.errors().origin() +
                                     " has no size parameter (no generator takes its count "
                                     "from /size); expected none, got " +
                                     std::to_string(spec.size));
  }
  read_explicit_bodies(scene, spec, material);
  read_joints(scene, spec);
  scene.finish();
  size_auto_grounds(document, spec, pending_grounds);
  return spec;
}

}  // namespace fxbench::scene_detail
