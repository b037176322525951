// One number as printf would print it, for messages and reports that quote figures.
#pragma once

#include <cstdio>
#include <string>

namespace fxbench {

// `format` holds one double conversion, e.g. "%.3f"; the text is cut at 63 characters.
inline std::string formatted(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

}  // namespace fxbench
