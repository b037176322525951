// Plain-text tables for the terminal: columns padded to their widest cell, two spaces apart.
#pragma once

#include <string>
#include <vector>

namespace fxbench {

// One line per row, each ending in a newline; rows may differ in length.
std::string aligned_columns(const std::vector<std::vector<std::string>>& rows);

}  // namespace fxbench
