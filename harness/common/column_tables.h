// A table of named, equal-length columns, as plain data: what a command keeps beside its runs in a
// result file (/sweep, /stability, /history). format/ builds them from records, storage/ writes
// and reads them (storage/h5_tables.h), merge joins them; none of those needs the others to say
// what a table is.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace fxbench {

struct H5Column {
  std::string name;
  std::string units;  // stored as the dataset's `units` attribute; ignored for strings
  std::variant<std::vector<double>, std::vector<std::int32_t>, std::vector<std::uint8_t>, std::vector<std::string>>
      values;
};

struct H5Table {
  std::string path;  // an absolute group path, e.g. "/stability/evaluations"; parents are created
  std::vector<std::pair<std::string, std::variant<std::string, double, std::int32_t>>> attributes;
  std::vector<H5Column> columns;
};

}  // namespace fxbench
