// Loads scene files (format: scenes/README.md) into SceneSpecs: parse, apply command-line
// overrides, validate, fill defaults, expand generators into explicit bodies.
//
// Invariant: every value is taken through one reader call that checks it and writes the resolved
// value back into the document, so resolved_json holds exactly what the SceneSpec was built from
// and nothing else; every rejection is one InputError line naming where the value came from (a
// file's line:column, or the command-line override that set it), its JSON pointer, and what was
// expected.
#include "scene_loader.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <span>
#include <string_view>

#include "bounded_read.h"
#include "errors.h"
#include "hash.h"

namespace fxbench {
namespace {

using Json = nlohmann::json;

constexpr std::string_view kSchema = "fx2d.scene/1";
// Far above the largest scene we benchmark, and refused before any body is allocated.
constexpr int kMaxBodies = 1'000'000;
// Any length (m), speed (m/s), angle (rad), acceleration (m/s^2) or material constant beyond this
// is a typo, and squaring it stays far from overflow inside an engine.
constexpr double kMaxMagnitude = 1e6;
// Steps, and bodies per row or column: anything larger is a typo.
constexpr int kMaxCount = 1'000'000'000;
// An "auto" ground reaches this far beyond the outermost body, so that nothing that slides or
// tumbles a little falls off its edge.
constexpr double kAutoGroundMargin = 10.0;
// Box2D 2.4's b2_maxPolygonVertices: the smallest limit among the engines.
constexpr std::size_t kMaxPolygonVertices = 8;

// ---------------------------------------------------------------------------------------------
// JSON pointers (RFC 6901)

std::string escape_pointer_token(std::string_view token) {
  std::string escaped;
  for (const char c : token) {
    if (c == '~') {
      escaped += "~0";
    } else if (c == '/') {
      escaped += "~1";
    } else {
      escaped += c;
    }
  }
  return escaped;
}

std::string child_pointer(const std::string& parent, std::string_view key) {
  return parent + "/" + escape_pointer_token(key);
}

std::string child_pointer(const std::string& parent, std::size_t index) {
  return parent + "/" + std::to_string(index);
}

// Splits a pointer into unescaped tokens; nullopt when it is not a well-formed pointer.
std::optional<std::vector<std::string>> split_pointer(std::string_view pointer) {
  std::vector<std::string> tokens;
  if (pointer.empty()) return tokens;
  if (pointer.front() != '/') return std::nullopt;
  for (std::size_t start = 1;;) {
    const std::size_t end = std::min(pointer.find('/', start), pointer.size());
    std::string token;
    for (std::size_t i = start; i < end; ++i) {
      if (pointer[i] != '~') {
        token += pointer[i];
      } else if (i + 1 < end && (pointer[i + 1] == '0' || pointer[i + 1] == '1')) {
        token += pointer[++i] == '0' ? '~' : '/';
      } else {
        return std::nullopt;
      }
    }
    tokens.push_back(std::move(token));
    if (end == pointer.size()) return tokens;
    start = end + 1;
  }
}

// An array index as RFC 6901 spells it: digits, no leading zero.
std::optional<std::size_t> parse_array_index(std::string_view token) {
  if (token.empty() || token.size() > 9 || (token.size() > 1 && token.front() == '0')) return std::nullopt;
  std::size_t index = 0;
  for (const char c : token) {
    if (c < '0' || c > '9') return std::nullopt;
    index = index * 10 + static_cast<std::size_t>(c - '0');
  }
  return index;
}

bool pointer_is_within(std::string_view pointer, std::string_view ancestor) {
  return pointer.starts_with(ancestor) &&
         (pointer.size() == ancestor.size() || pointer[ancestor.size()] == '/');
}

std::string display_pointer(const std::string& pointer) { return pointer.empty() ? "(root)" : pointer; }

// ---------------------------------------------------------------------------------------------
// Source positions. nlohmann reports byte offsets only for syntax errors, so for a semantic error
// the offending value is found again in the text (already known to be valid JSON) by walking the
// pointer's tokens and skipping whatever does not match.

struct TextPosition {
  int line = 1;
  int column = 1;  // bytes, as nlohmann counts them
};

TextPosition position_at(std::string_view text, std::size_t offset) {
  offset = std::min(offset, text.size());
  TextPosition position;
  std::size_t line_start = 0;
  for (std::size_t i = 0; i < offset; ++i) {
    if (text[i] == '\n') {
      ++position.line;
      line_start = i + 1;
    }
  }
  position.column = static_cast<int>(offset - line_start) + 1;
  return position;
}

class JsonTextScanner {
 public:
  explicit JsonTextScanner(std::string_view text) : text_(text) {}

  // Offset of the value at `tokens` (of its key instead, when `at_key` and it has one). For a
  // pointer the text does not hold, the offset of its deepest ancestor that it does hold. A
  // duplicated key resolves to its last occurrence, as nlohmann keeps the last value.
  std::size_t locate(const std::vector<std::string>& tokens, bool at_key) const {
    std::size_t value = skip_whitespace(skip_byte_order_mark());
    std::size_t key = value;
    for (const std::string& token : tokens) {
      const std::optional<Member> member = find_member(value, token);
      if (!member) return value;
      value = member->value;
      key = member->key;
    }
    return at_key ? key : value;
  }

 private:
  struct Member {
    std::size_t key;
    std::size_t value;
  };

  std::optional<Member> find_member(std::size_t container, const std::string& token) const {
    if (container >= text_.size()) return std::nullopt;
    if (text_[container] == '{') return find_object_member(container, token);
    if (text_[container] == '[') return find_array_element(container, token);
    return std::nullopt;
  }

  std::optional<Member> find_object_member(std::size_t object, const std::string& key) const {
    std::optional<Member> found;
    std::size_t at = skip_whitespace(object + 1);
    while (at < text_.size() && text_[at] == '"') {
      const std::size_t key_end = skip_string(at);
      const std::size_t value = skip_whitespace(skip_whitespace(key_end) + 1);  // past the ':'
      if (decode_key(at, key_end) == key) found = Member{at, value};
      at = skip_separator(skip_value(value));
    }
    return found;
  }

  std::optional<Member> find_array_element(std::size_t array, const std::string& token) const {
    const std::optional<std::size_t> index = parse_array_index(token);
    if (!index) return std::nullopt;
    std::size_t at = skip_whitespace(array + 1);
    for (std::size_t i = 0; at < text_.size() && text_[at] != ']'; ++i) {
      if (i == *index) return Member{at, at};
      at = skip_separator(skip_value(at));
    }
    return std::nullopt;
  }

  std::string decode_key(std::size_t begin, std::size_t end) const {
    const std::string_view quoted = text_.substr(begin, end - begin);
    if (quoted.find('\\') == std::string_view::npos) return std::string(quoted.substr(1, quoted.size() - 2));
    return Json::parse(quoted).get<std::string>();
  }

  std::size_t skip_byte_order_mark() const { return text_.starts_with("\xEF\xBB\xBF") ? 3 : 0; }

  std::size_t skip_whitespace(std::size_t at) const {
    while (at < text_.size() &&
           (text_[at] == ' ' || text_[at] == '\t' || text_[at] == '\n' || text_[at] == '\r')) {
      ++at;
    }
    return at;
  }

  // Past the ',' after a member or element, and the whitespace around it.
  std::size_t skip_separator(std::size_t at) const {
    at = skip_whitespace(at);
    if (at < text_.size() && text_[at] == ',') at = skip_whitespace(at + 1);
    return at;
  }

  std::size_t skip_string(std::size_t quote) const {
    for (std::size_t at = quote + 1; at < text_.size(); ++at) {
      if (text_[at] == '\\') {
        ++at;
      } else if (text_[at] == '"') {
        return at + 1;
      }
    }
    return text_.size();
  }

  // Iterative, so that no nesting depth can exhaust the stack.
  std::size_t skip_value(std::size_t at) const {
    if (at >= text_.size()) return at;
    if (text_[at] == '"') return skip_string(at);
    if (text_[at] != '{' && text_[at] != '[') {
      while (at < text_.size() && std::string_view(",]} \t\r\n").find(text_[at]) == std::string_view::npos)
        ++at;
      return at;
    }
    int depth = 0;
    while (at < text_.size()) {
      const char c = text_[at];
      if (c == '"') {
        at = skip_string(at);
        continue;
      }
      if (c == '{' || c == '[') ++depth;
      if ((c == '}' || c == ']') && --depth == 0) return at + 1;
      ++at;
    }
    return at;
  }

  std::string_view text_;
};

// ---------------------------------------------------------------------------------------------
// Errors

// A command-line override and the part of the document it wrote: errors at or below `written`
// are reported against the override, since the file never held that value.
struct OverrideOrigin {
  std::string label;    // e.g. "--set /dt=-1", "--bodies 600"
  std::string written;  // pointer of the value set, or of the first object the set had to create
};

// What a value is, for "got ...": its JSON text, shortened to stay on one readable line.
std::string describe_value(const Json& value) {
  constexpr std::size_t kMaxShown = 60;
  std::string text = value.dump(-1, ' ', false, Json::error_handler_t::replace);
  if (text.size() > kMaxShown) text = text.substr(0, kMaxShown - 3) + "...";
  return text;
}

// Appended piece by piece: GCC 12 misreads "\"" + std::string as an overlapping copy (-Wrestrict).
std::string in_quotes(std::string_view text) {
  std::string quoted_text(1, '"');
  quoted_text.append(text).push_back('"');
  return quoted_text;
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> previous(b.size() + 1);
  std::vector<std::size_t> current(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) previous[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    current[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t substitution = previous[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      current[j] = std::min({previous[j] + 1, current[j - 1] + 1, substitution});
    }
    std::swap(previous, current);
  }
  return previous[b.size()];
}

std::string join_quoted(std::span<const std::string> names) {
  std::string joined;
  for (const std::string& name : names) joined += (joined.empty() ? "" : ", ") + in_quotes(name);
  return joined;
}

// "did you mean" when one name is within a third of its length (at least 2 edits) of `key`,
// else the list of names accepted there.
std::string unknown_key_message(std::string_view key, std::span<const std::string> known) {
  const auto closest =
      std::ranges::min_element(known, {}, [&](const std::string& name) { return edit_distance(key, name); });
  if (closest != known.end() &&
      edit_distance(key, *closest) <= std::max<std::size_t>(2, closest->size() / 3)) {
    return "unknown key; did you mean " + in_quotes(*closest) + "?";
  }
  return "unknown key; expected one of " + join_quoted(known);
}

class ErrorReporter {
 public:
  ErrorReporter(std::string_view text, std::string origin) : text_(text), origin_(std::move(origin)) {}

  void add_override(OverrideOrigin origin) { overrides_.push_back(std::move(origin)); }

  [[noreturn]] void fail(const std::string& pointer, const std::string& message, bool at_key = false) const {
    throw InputError(where(pointer, at_key) + ": " + display_pointer(pointer) + ": " + message);
  }

  [[noreturn]] void expected(const std::string& pointer, const std::string& what, const Json& got) const {
    fail(pointer, "expected " + what + ", got " + describe_value(got));
  }

  [[noreturn]] void missing(const std::string& pointer, const std::string& what) const {
    fail(pointer, "expected " + what + ", got nothing");
  }

  const std::string& origin() const { return origin_; }

 private:
  std::string where(const std::string& pointer, bool at_key) const {
    // The last override wins, as it was applied last.
    for (auto it = overrides_.rbegin(); it != overrides_.rend(); ++it) {
      if (pointer_is_within(pointer, it->written)) return it->label;
    }
    const std::size_t offset =
        JsonTextScanner(text_).locate(split_pointer(pointer).value_or(std::vector<std::string>{}), at_key);
    const TextPosition position = position_at(text_, offset);
    return origin_ + ":" + std::to_string(position.line) + ":" + std::to_string(position.column);
  }

  std::string_view text_;
  std::string origin_;
  std::vector<OverrideOrigin> overrides_;
};

// ---------------------------------------------------------------------------------------------
// Values

std::string format_bound(double value) {
  if (value == std::floor(value) && std::abs(value) < 1e15)
    return std::to_string(static_cast<long long>(value));
  return Json(value).dump();
}

// The accepted interval of a number. A `cap` upper bound guards against typos rather than being
// part of the value's meaning, so messages mention it only to a value that exceeds it.
struct Range {
  double min;
  double max;
  bool min_exclusive = false;
  bool max_is_cap = true;

  bool contains(double value) const { return (min_exclusive ? value > min : value >= min) && value <= max; }
  std::string describe(std::string_view kind, bool exceeded_max) const {
    const std::string article_kind = std::string(kind == "integer" ? "an " : "a ") + std::string(kind);
    if (!max_is_cap) return article_kind + " from " + format_bound(min) + " to " + format_bound(max);
    if (exceeded_max) return article_kind + " <= " + format_bound(max);
    return article_kind + (min_exclusive ? " > " : " >= ") + format_bound(min);
  }
};

constexpr Range kPositive{0.0, kMaxMagnitude, true};
constexpr Range kNonNegative{0.0, kMaxMagnitude};
constexpr Range kSigned{-kMaxMagnitude, kMaxMagnitude, false, false};
constexpr Range kUnitInterval{0.0, 1.0, false, false};

double read_number(const ErrorReporter& errors, Json& value, const std::string& pointer, const Range& range) {
  if (!value.is_number()) errors.expected(pointer, range.describe("number", false), value);
  const double number = value.get<double>();
  if (!range.contains(number)) errors.expected(pointer, range.describe("number", number > range.max), value);
  value = number;
  return number;
}

int read_integer(const ErrorReporter& errors, Json& value, const std::string& pointer, const Range& range) {
  const bool integral = value.is_number_integer() ||
                        (value.is_number_float() && value.get<double>() == std::floor(value.get<double>()));
  if (!integral) errors.expected(pointer, range.describe("integer", false), value);
  const double number = value.get<double>();
  if (!range.contains(number)) errors.expected(pointer, range.describe("integer", number > range.max), value);
  const int integer = static_cast<int>(number);
  value = integer;
  return integer;
}

Vec2 read_vec2(const ErrorReporter& errors, Json& value, const std::string& pointer, const Range& range) {
  if (!value.is_array() || value.size() != 2) {
    errors.expected(pointer, "[x, y] with each " + range.describe("number", false), value);
  }
  return {read_number(errors, value[0], child_pointer(pointer, 0), range),
          read_number(errors, value[1], child_pointer(pointer, 1), range)};
}

// Reads one JSON object key by key. Each read names a key the object may hold, validates its
// value, and stores the resolved value (default included) back; finish() rejects any key no read
// named, which is how misspellings are caught.
class ObjectReader {
 public:
  ObjectReader(const ErrorReporter& errors, Json& object, std::string pointer,
               std::string_view what = "an object")
      : errors_(errors), object_(object), pointer_(std::move(pointer)) {
    if (object_.is_null()) object_ = Json::object();
    if (!object_.is_object()) errors_.expected(pointer_, std::string(what), object_);
  }

  double number(std::string_view key, double fallback, const Range& range) {
    return read_number(errors_, slot(key, fallback), at(key), range);
  }
  int integer(std::string_view key, int fallback, const Range& range) {
    return read_integer(errors_, slot(key, fallback), at(key), range);
  }
  Vec2 vec2(std::string_view key, Vec2 fallback, const Range& range) {
    return read_vec2(errors_, slot(key, Json::array({fallback.x, fallback.y})), at(key), range);
  }
  bool boolean(std::string_view key, bool fallback) {
    const Json& value = slot(key, fallback);
    if (!value.is_boolean()) errors_.expected(at(key), "true or false", value);
    return value.get<bool>();
  }
  std::string text(std::string_view key, std::string fallback) {
    const Json& value = slot(key, std::move(fallback));
    if (!value.is_string()) errors_.expected(at(key), "a string", value);
    return value.get<std::string>();
  }
  // One of `allowed`; returns its index there.
  std::size_t choice(std::string_view key, std::optional<std::string_view> fallback,
                     std::span<const std::string> allowed) {
    const Json* value =
        fallback ? &slot(key, std::string(*fallback)) : &required(key, "one of " + join_quoted(allowed));
    const auto found =
        value->is_string() ? std::ranges::find(allowed, value->get<std::string>()) : allowed.end();
    if (found == allowed.end()) errors_.expected(at(key), "one of " + join_quoted(allowed), *value);
    return static_cast<std::size_t>(found - allowed.begin());
  }
  // A number, or the string `keyword` (also the default) to let the loader compute it later.
  std::optional<double> number_or(std::string_view key, std::string_view keyword, const Range& range) {
    Json& value = slot(key, std::string(keyword));
    if (value.is_string() && value.get<std::string>() == keyword) return std::nullopt;
    if (!value.is_number())
      errors_.expected(at(key), range.describe("number", false) + " or " + in_quotes(keyword), value);
    return read_number(errors_, value, at(key), range);
  }
  // A flag that is false when absent and then is not written back, so a scene that leaves it out
  // keeps the hash it had before the key existed.
  bool optional_flag(std::string_view key) {
    note(key);
    if (!object_.contains(key)) return false;
    const Json& value = object_[key];
    if (!value.is_boolean()) errors_.expected(at(key), "true or false", value);
    return value.get<bool>();
  }
  std::optional<double> optional_number(std::string_view key, const Range& range) {
    note(key);
    if (!object_.contains(key) || object_[key].is_null()) return std::nullopt;
    return read_number(errors_, object_[key], at(key), range);
  }
  std::optional<int> optional_integer(std::string_view key, const Range& range) {
    note(key);
    if (!object_.contains(key) || object_[key].is_null()) return std::nullopt;
    return read_integer(errors_, object_[key], at(key), range);
  }
  Json& required(std::string_view key, const std::string& what) {
    note(key);
    if (!object_.contains(key)) errors_.missing(at(key), what);
    return object_[key];
  }
  // The value at `key`, created as `fallback` if absent; the caller validates it.
  Json& slot(std::string_view key, Json fallback) {
    note(key);
    Json& value = object_[key];
    if (value.is_null()) value = std::move(fallback);
    return value;
  }
  void erase(std::string_view key) { object_.erase(std::string(key)); }
  bool has(std::string_view key) const { return object_.contains(key); }

  void finish() const {
    for (const auto& [key, value] : object_.items()) {
      if (std::ranges::find(known_, key) == known_.end())
        errors_.fail(at(key), unknown_key_message(key, known_), true);
    }
  }

  std::string at(std::string_view key) const { return child_pointer(pointer_, key); }
  const std::string& pointer() const { return pointer_; }
  const ErrorReporter& errors() const { return errors_; }

 private:
  void note(std::string_view key) {
    if (std::ranges::find(known_, key) == known_.end()) known_.emplace_back(key);
  }

  const ErrorReporter& errors_;
  Json& object_;
  std::string pointer_;
  std::vector<std::string> known_;
};

// The elements of the array at `key` (absent means empty), each with its pointer.
template <typename ReadElement>
void for_each_element(ObjectReader& reader, std::string_view key, ReadElement&& read_element) {
  Json& array = reader.slot(key, Json::array());
  if (!array.is_array()) reader.errors().expected(reader.at(key), "an array", array);
  for (std::size_t i = 0; i < array.size(); ++i) read_element(array[i], child_pointer(reader.at(key), i), i);
}

// ---------------------------------------------------------------------------------------------
// Scene parts

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

void read_solver(ObjectReader& scene, SceneSpec& spec) {
  ObjectReader solver(scene.errors(), scene.slot("solver", Json::object()), scene.at("solver"));
  constexpr Range kPasses{1.0, 1000.0};
  constexpr Range kPassesOrNone{0.0, 1000.0};

  ObjectReader fx2d(solver.errors(), solver.slot("fx2d", Json::object()), solver.at("fx2d"));
  spec.fx2d.substeps = fx2d.integer("substeps", Fx2dSettings{}.substeps, kPasses);
  spec.fx2d.velocity_passes = fx2d.integer("velocity_passes", Fx2dSettings{}.velocity_passes, kPassesOrNone);
  spec.fx2d.sleeping = fx2d.boolean("sleeping", Fx2dSettings{}.sleeping);
  spec.fx2d.relax_passes = fx2d.optional_integer("relax_passes", kPasses);
  spec.fx2d.max_push_speed = fx2d.optional_number("max_push_speed", kPositive);
  fx2d.finish();

  ObjectReader box2d(solver.errors(), solver.slot("box2d", Json::object()), solver.at("box2d"));
  spec.box2d.velocity_iterations =
      box2d.integer("velocity_iterations", Box2dSettings{}.velocity_iterations, kPasses);
  spec.box2d.position_iterations =
      box2d.integer("position_iterations", Box2dSettings{}.position_iterations, kPassesOrNone);
  spec.box2d.sleeping = box2d.boolean("sleeping", Box2dSettings{}.sleeping);
  box2d.finish();

  ObjectReader ode(solver.errors(), solver.slot("ode", Json::object()), solver.at("ode"));
  spec.ode.iterations = ode.integer("iterations", OdeSettings{}.iterations, kPasses);
  spec.ode.erp = ode.number("erp", OdeSettings{}.erp, kUnitInterval);
  spec.ode.cfm = ode.number("cfm", OdeSettings{}.cfm, kNonNegative);
  spec.ode.auto_disable = ode.boolean("auto_disable", OdeSettings{}.auto_disable);
  ode.finish();

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
};

// How many bodies a generator adds: `count` (default: the scene's size), refused before any
// allocation if the scene would then exceed kMaxBodies.
int read_count(GeneratorInput& in, const std::vector<BodySpec>& bodies) {
  // A count left to default is the scene's size, so a scene too large is blamed on /size (and on
  // the --bodies that set it).
  const std::string blamed = in.reader.has("count") ? in.reader.at("count") : "/size";
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

void expand_generators(ObjectReader& scene, SceneSpec& spec, const MaterialSpec& material,
                       std::vector<PendingGround>& pending) {
  for_each_element(scene, "generators", [&](Json& element, const std::string& pointer, std::size_t index) {
    ObjectReader reader(scene.errors(), element, pointer, "a generator object with a \"type\"");
    const std::size_t type = reader.choice("type", std::nullopt, kGeneratorTypes);
    const std::size_t first = spec.bodies.size();
    GeneratorInput input{reader, spec.size, material, index};
    kGeneratorExpanders[type](input, spec.bodies, pending);
    reader.finish();
    check_generated_positions(reader, std::span(spec.bodies).subspan(first));
  });
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

SceneSpec read_scene(const ErrorReporter& errors, Json& document) {
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
  expand_generators(scene, spec, material, pending_grounds);
  read_explicit_bodies(scene, spec, material);
  read_joints(scene, spec);
  scene.finish();
  size_auto_grounds(document, spec, pending_grounds);
  return spec;
}

// ---------------------------------------------------------------------------------------------
// Overrides

// Writes `value` at `pointer`, creating the objects on the way that the document leaves out (a
// file says only what differs from the defaults). Returns the pointer of what it wrote: the
// value's, or that of the first object it had to create.
std::string write_override(Json& document, const std::string& pointer, Json value, const std::string& label) {
  const auto tokens = split_pointer(pointer);
  if (!tokens || tokens->empty()) {
    throw InputError(label + ": expected a JSON pointer such as /solver/fx2d/substeps, got " +
                     in_quotes(pointer));
  }
  Json* node = &document;
  std::string at;
  std::optional<std::string> first_created;
  for (std::size_t i = 0; i < tokens->size(); ++i) {
    const std::string& token = (*tokens)[i];
    const bool last = i + 1 == tokens->size();
    const std::string parent = at;
    at = child_pointer(at, token);
    if (node->is_object()) {
      if (!node->contains(token) && !first_created) first_created = at;
      node = &(*node)[token];
      if (!last && node->is_null()) *node = (*tokens)[i + 1] == "-" ? Json::array() : Json::object();
    } else if (node->is_array()) {
      if (last && token == "-") {
        node->push_back(Json());
        node = &node->back();
        if (!first_created) first_created = child_pointer(parent, node->size() - 1);
        continue;
      }
      const std::optional<std::size_t> index = parse_array_index(token);
      if (!index || *index >= node->size()) {
        throw InputError(label + ": " + display_pointer(parent) + ": expected an index below " +
                         std::to_string(node->size()) + (last ? " or \"-\"" : "") + ", got " +
                         in_quotes(token));
      }
      node = &(*node)[*index];
    } else {
      throw InputError(label + ": " + display_pointer(parent) + ": expected an object or an array to hold " +
                       in_quotes(token) + ", got " + describe_value(*node));
    }
  }
  *node = std::move(value);
  return first_created.value_or(pointer);
}

// The text as JSON if it parses, else as a string, so --set /name=pile2 needs no quotes.
Json parse_override_value(const std::string& text, const std::string& label) {
  Json value = Json::parse(text, nullptr, false);
  if (!value.is_discarded()) return value;
  value = text;
  try {
    value.dump();
  } catch (const Json::type_error&) {
    throw InputError(label + ": expected UTF-8 text, got bytes that are not");
  }
  return value;
}

void apply_overrides(Json& document, const SceneOverrides& overrides, ErrorReporter& errors) {
  const auto apply = [&](const std::string& label, const std::string& pointer, Json value) {
    errors.add_override({label, write_override(document, pointer, std::move(value), label)});
  };
  if (overrides.bodies) apply("--bodies " + std::to_string(*overrides.bodies), "/size", *overrides.bodies);
  if (overrides.steps) apply("--steps " + std::to_string(*overrides.steps), "/steps", *overrides.steps);
  for (const auto& [pointer, value_text] : overrides.sets) {
    const std::string label = "--set " + pointer + "=" + value_text;
    apply(label, pointer, parse_override_value(value_text, label));
  }
}

// ---------------------------------------------------------------------------------------------
// Parsing

// nlohmann's "syntax error while parsing value - unexpected ']'; expected ..." loses its prefix
// and position (we give our own, from the byte offset it reports).
std::string readable_syntax_error(const Json::parse_error& error) {
  std::string reason = error.what();
  if (const std::size_t column = reason.find(": "); column != std::string::npos)
    reason = reason.substr(column + 2);
  if (const std::size_t dash = reason.find(" - ");
      reason.starts_with("syntax error") && dash != std::string::npos) {
    reason = reason.substr(dash + 3);
  }
  return "syntax error: " + reason;
}

Json parse_document(const std::string& text, const std::string& origin) {
  try {
    return Json::parse(text);
  } catch (const Json::parse_error& error) {
    const TextPosition position = position_at(text, error.byte == 0 ? 0 : error.byte - 1);
    throw InputError(origin + ":" + std::to_string(position.line) + ":" + std::to_string(position.column) +
                     ": " + readable_syntax_error(error));
  } catch (const Json::out_of_range& error) {
    // A number literal beyond double range ("1e400"); nlohmann gives no position for it.
    std::string reason = error.what();
    if (const std::size_t column = reason.find("] "); column != std::string::npos) reason = reason.substr(column + 2);
    throw InputError(origin + ": " + reason + "; expected numbers within double range");
  }
}

}  // namespace

// Arrays and objects nested deeper than any scene needs are refused before parsing: the parser
// recurses and allocates per level, so a file of '[' could otherwise take gigabytes.
void require_shallow(const std::string& text, const std::string& origin) {
  constexpr int max_depth = 64;
  int depth = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > max_depth) {
        const TextPosition position = position_at(text, i);
        throw InputError(origin + ":" + std::to_string(position.line) + ":" + std::to_string(position.column) +
                         ": nesting deeper than " + std::to_string(max_depth) + " levels, expected a scene");
      }
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
}

SceneSpec load_scene_text(const std::string& text, const std::string& origin,
                          const SceneOverrides& overrides) {
  require_shallow(text, origin);
  Json document = parse_document(text, origin);
  ErrorReporter errors(text, origin);
  apply_overrides(document, overrides, errors);
  SceneSpec spec = read_scene(errors, document);
  spec.resolved_json = document.dump(2);
  Fnv1a64 hash;
  hash.add(spec.resolved_json);
  spec.hash = hash.hex();
  return spec;
}

SceneSpec load_scene_file(const std::string& path, const SceneOverrides& overrides) {
  if (std::filesystem::is_directory(path)) throw InputError(path + ": cannot open: " + std::strerror(EISDIR));
  // Scenes are compact (generators, not body lists of millions); a larger file is not a scene,
  // and parsing one can cost gigabytes first.
  const std::string text = read_bounded_file(path, "a scene file");
  SceneSpec spec = load_scene_text(text, path, overrides);
  spec.source_path = path;
  return spec;
}

}  // namespace fxbench
