// Reading a scene document value by value: every read checks one value against what is
// expected there and writes the resolved value back, and every rejection is one InputError line
// naming where the value came from (a file's line:column, or the command-line override that set
// it), its JSON pointer, and what was expected.
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "common/errors.h"
#include "scene/json_text.h"
#include "scene/scene_spec.h"

namespace fxbench::scene_detail {

using Json = nlohmann::json;

// Any length (m), speed (m/s), angle (rad), acceleration (m/s^2) or material constant beyond this
// is a typo, and squaring it stays far from overflow inside an engine.
inline constexpr double kMaxMagnitude = 1e6;

// A command-line override and the part of the document it wrote: errors at or below `written`
// are reported against the override, since the file never held that value.
struct OverrideOrigin {
  std::string label;    // e.g. "--set /dt=-1", "--bodies 600"
  std::string written;  // pointer of the value set, or of the first object the set had to create
};

// `text` parsed as JSON; a syntax error, or nesting deeper than 64 levels (refused before the
// parser allocates for it), is one InputError line naming `origin`, the line and column, and what
// was expected there (`expected` names the document, e.g. "a scene").
Json parse_json_text(const std::string& text, const std::string& origin, std::string_view expected);

// What a value is, for "got ...": its JSON text, shortened to stay on one readable line.
std::string describe_value(const Json& value);

std::string in_quotes(std::string_view text);
std::string join_quoted(std::span<const std::string> names);

// The name of `known` within a third of its length (at least 2 edits) of `key`, if any.
std::optional<std::string> near_key(std::string_view key, std::span<const std::string> known);
// "did you mean" the near_key, else the list of names accepted there.
std::string unknown_key_message(std::string_view key, std::span<const std::string> known);

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

  // Where the value at `pointer` (its key, when `at_key`) came from: "origin:line:column", or the
  // command-line override that set it.
  std::string where(const std::string& pointer, bool at_key = false) const;

 private:
  std::string_view text_;
  std::string origin_;
  std::vector<OverrideOrigin> overrides_;
};

// A range's bound as a message prints it: integers without a decimal point.
std::string format_bound(double value);

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

inline constexpr Range kPositive{0.0, kMaxMagnitude, true};
inline constexpr Range kNonNegative{0.0, kMaxMagnitude};
inline constexpr Range kSigned{-kMaxMagnitude, kMaxMagnitude, false, false};
inline constexpr Range kUnitInterval{0.0, 1.0, false, false};

// The value at `pointer`, checked against `range` and written back resolved (an integral float
// becomes an integer); anything else is refused through `errors`.
double read_number(const ErrorReporter& errors, Json& value, const std::string& pointer, const Range& range);
int read_integer(const ErrorReporter& errors, Json& value, const std::string& pointer, const Range& range);
Vec2 read_vec2(const ErrorReporter& errors, Json& value, const std::string& pointer, const Range& range);

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

}  // namespace fxbench::scene_detail
