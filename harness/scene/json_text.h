// Where a value sits in a scene file: JSON pointers (RFC 6901) and the line:column of the value a
// pointer names, so that every message about a scene names the place in the text.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace fxbench::scene_detail {

std::string child_pointer(const std::string& parent, std::string_view key);
std::string child_pointer(const std::string& parent, std::size_t index);

// Splits a pointer into unescaped tokens; nullopt when it is not a well-formed pointer.
std::optional<std::vector<std::string>> split_pointer(std::string_view pointer);

// An array index as RFC 6901 spells it: digits, no leading zero.
std::optional<std::size_t> parse_array_index(std::string_view token);

bool pointer_is_within(std::string_view pointer, std::string_view ancestor);

// A pointer as a message shows it: "(root)" for the whole document, otherwise escaped as in JSON.
std::string display_pointer(const std::string& pointer);

struct TextPosition {
  int line = 1;
  int column = 1;  // bytes, as nlohmann counts them
};

TextPosition position_at(std::string_view text, std::size_t offset);

// Offset in `text` (valid JSON) of the value at `tokens` (of its key instead, when `at_key` and
// it has one). For a pointer the text does not hold, the offset of its deepest ancestor that it
// does hold. A duplicated key resolves to its last occurrence, as nlohmann keeps the last value.
std::size_t locate_in_text(std::string_view text, const std::vector<std::string>& tokens, bool at_key);

}  // namespace fxbench::scene_detail
