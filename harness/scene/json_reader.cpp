// Typed reads of scene values and the messages that reject them (json_reader.h).
#include "scene/json_reader.h"

#include <algorithm>
#include <cmath>

namespace fxbench::scene_detail {
namespace {

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

// Arrays and objects nested deeper than any scene or policy needs are refused before parsing: the
// parser allocates per level, so a file of '[' could otherwise take gigabytes (16 MiB of them: 616
// MB).
void require_shallow(const std::string& text, const std::string& origin, std::string_view expected) {
  constexpr int max_depth = 64;
  int depth = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > max_depth) {
        const TextPosition position = position_at(text, i);
        throw InputError(origin + ":" + std::to_string(position.line) + ":" +
                         std::to_string(position.column) + ": nesting deeper than " +
                         std::to_string(max_depth) + " levels, expected " + std::string(expected));
      }
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
}

}  // namespace

Json parse_json_text(const std::string& text, const std::string& origin, std::string_view expected) {
  require_shallow(text, origin, expected);
  try {
    return Json::parse(text);
  } catch (const Json::parse_error& error) {
    const TextPosition position = position_at(text, error.byte == 0 ? 0 : error.byte - 1);
    throw InputError(origin + ":" + std::to_string(position.line) + ":" + std::to_string(position.column) +
                     ": " + readable_syntax_error(error));
  } catch (const Json::out_of_range& error) {
    // A number literal beyond double range ("1e400"); nlohmann gives no position for it.
    std::string reason = error.what();
    if (const std::size_t column = reason.find("] "); column != std::string::npos)
      reason = reason.substr(column + 2);
    throw InputError(origin + ": " + reason + "; expected numbers within double range");
  }
}

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

std::string join_quoted(std::span<const std::string> names) {
  std::string joined;
  for (const std::string& name : names) {
    // Appended piece by piece: `", " + in_quotes(name)` makes GCC 12 report a false
    // -Wstringop-overflow when link-time optimisation inlines the string insert.
    if (!joined.empty()) joined += ", ";
    joined += in_quotes(name);
  }
  return joined;
}

std::optional<std::string> near_key(std::string_view key, std::span<const std::string> known) {
  const auto closest =
      std::ranges::min_element(known, {}, [&](const std::string& name) { return edit_distance(key, name); });
  if (closest != known.end() && edit_distance(key, *closest) <= std::max<std::size_t>(2, closest->size() / 3))
    return *closest;
  return std::nullopt;
}

std::string unknown_key_message(std::string_view key, std::span<const std::string> known) {
  if (const auto closest = near_key(key, known))
    return "unknown key; did you mean " + in_quotes(*closest) + "?";
  return "unknown key; expected one of " + join_quoted(known);
}

std::string ErrorReporter::where(const std::string& pointer, bool at_key) const {
  // The last override wins, as it was applied last.
  for (auto it = overrides_.rbegin(); it != overrides_.rend(); ++it) {
    if (pointer_is_within(pointer, it->written)) return it->label;
  }
  const std::size_t offset =
      locate_in_text(text_, split_pointer(pointer).value_or(std::vector<std::string>{}), at_key);
  const TextPosition position = position_at(text_, offset);
  return origin_ + ":" + std::to_string(position.line) + ":" + std::to_string(position.column);
}

std::string format_bound(double value) {
  if (value == std::floor(value) && std::abs(value) < 1e15)
    return std::to_string(static_cast<long long>(value));
  return Json(value).dump();
}

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

}  // namespace fxbench::scene_detail
