// Tables as text, shared by every command: for the terminal, columns padded to their widest
// cell, two spaces apart; for Markdown, a pipe table whose first row is the header.
#pragma once

#include <string>
#include <vector>

namespace fxbench {

// One line per row, each ending in a newline; rows may differ in length.
std::string aligned_columns(const std::vector<std::vector<std::string>>& rows);

// The first row is the header; one line per row, each ending in a newline.
std::string markdown_table(const std::vector<std::vector<std::string>>& rows);

}  // namespace fxbench
