// Pads cells to their column's width; the last cell of a row is never padded, so no line ends in
// spaces.
#include "format/text_table.h"

#include <algorithm>

namespace fxbench {

std::string aligned_columns(const std::vector<std::vector<std::string>>& rows) {
  std::vector<std::size_t> widths;
  for (const auto& row : rows) {
    widths.resize(std::max(widths.size(), row.size()), 0);
    for (std::size_t column = 0; column < row.size(); ++column) widths[column] = std::max(widths[column], row[column].size());
  }
  std::string text;
  for (const auto& row : rows) {
    for (std::size_t column = 0; column < row.size(); ++column) {
      text += row[column];
      if (column + 1 < row.size()) text += std::string(widths[column] - row[column].size() + 2, ' ');
    }
    text += '\n';
  }
  return text;
}

std::string markdown_table(const std::vector<std::vector<std::string>>& table) {
  std::string text;
  for (std::size_t line = 0; line < table.size(); ++line) {
    text += "|";
    for (const std::string& cell : table[line]) text += " " + cell + " |";
    text += "\n";
    if (line == 0) {
      text += "|";
      for (std::size_t column = 0; column < table[0].size(); ++column) text += "---|";
      text += "\n";
    }
  }
  return text;
}

}  // namespace fxbench
