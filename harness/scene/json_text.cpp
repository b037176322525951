// JSON pointers and source positions for scene files (json_text.h). nlohmann reports byte
// offsets only for syntax errors, so for a semantic error the offending value is found again in
// the text (already known to be valid JSON) by walking the pointer's tokens and skipping whatever
// does not match.
#include "scene/json_text.h"

#include <algorithm>
#include <nlohmann/json.hpp>

namespace fxbench::scene_detail {
namespace {

using Json = nlohmann::json;

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

}  // namespace

std::string child_pointer(const std::string& parent, std::string_view key) {
  return parent + "/" + escape_pointer_token(key);
}

std::string child_pointer(const std::string& parent, std::size_t index) {
  return parent + "/" + std::to_string(index);
}

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

// Spelt as the file's JSON string spells it, without the quotes: a key holding a newline or a
// terminal's escape shows as \n or \u001b, so the message stays one line and shows what the file says.
std::string display_pointer(const std::string& pointer) {
  if (pointer.empty()) return "(root)";
  const std::string quoted = Json(pointer).dump(-1, ' ', false, Json::error_handler_t::replace);
  return quoted.substr(1, quoted.size() - 2);
}

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

namespace {

class JsonTextScanner {
 public:
  explicit JsonTextScanner(std::string_view text) : text_(text) {}

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

}  // namespace

std::size_t locate_in_text(std::string_view text, const std::vector<std::string>& tokens, bool at_key) {
  return JsonTextScanner(text).locate(tokens, at_key);
}

}  // namespace fxbench::scene_detail
