// The nightly history file; the layout is named once, in the column tables below, which both the
// writer and the reader walk. Invariants in history_h5.h.
#include "storage/history_h5.h"

#include <fcntl.h>
#include <hdf5.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <system_error>

#include "common/errors.h"
#include "storage/file_integrity.h"
#include "storage/h5_tables.h"
#include "storage/h5_types.h"

namespace fxbench {
namespace {

namespace fs = std::filesystem;

constexpr const char* history_group = "/history";

template <class Field>
struct Column {
  const char* name;
  Field HistoryRow::*field;
  const char* units;
};

constexpr Column<std::string> string_columns[] = {
    {"date_utc", &HistoryRow::date_utc, ""}, {"candidate", &HistoryRow::candidate, ""},
    {"baseline", &HistoryRow::baseline, ""}, {"engine", &HistoryRow::engine, ""},
    {"scene", &HistoryRow::scene, ""},       {"metric", &HistoryRow::metric, ""},
    {"verdict", &HistoryRow::verdict, ""},
};
constexpr Column<int> integer_columns[] = {{"bodies", &HistoryRow::bodies, "bodies"}};
// a and b are in the metric's own unit (ms, or instructions), the rest are ratios.
constexpr Column<double> number_columns[] = {
    {"a", &HistoryRow::a, "metric"},           {"b", &HistoryRow::b, "metric"},
    {"ratio", &HistoryRow::ratio, "ratio"},    {"ci_low", &HistoryRow::ci_low, "ratio"},
    {"ci_high", &HistoryRow::ci_high, "ratio"}, {"p_value", &HistoryRow::p_value, "probability"},
};
constexpr Column<bool> flag_columns[] = {{"step_detected", &HistoryRow::step_detected, "flag"},
                                         {"accepted", &HistoryRow::accepted, "flag"}};

// --- writing ----------------------------------------------------------------------------------------

template <class Stored, class Field>
H5Column column_of(const Column<Field>& column, std::span<const HistoryRow> rows) {
  std::vector<Stored> values;
  values.reserve(rows.size());
  for (const HistoryRow& row : rows) values.push_back(static_cast<Stored>(row.*column.field));
  return H5Column{column.name, column.units, std::move(values)};
}

H5Table history_table(std::span<const HistoryRow> rows) {
  H5Table table{history_group, {}, {}};
  for (const auto& column : string_columns) table.columns.push_back(column_of<std::string>(column, rows));
  for (const auto& column : integer_columns) table.columns.push_back(column_of<std::int32_t>(column, rows));
  for (const auto& column : number_columns) table.columns.push_back(column_of<double>(column, rows));
  for (const auto& column : flag_columns) table.columns.push_back(column_of<std::uint8_t>(column, rows));
  return table;
}

// Flushes a file, or a directory's entries, from the kernel to the disk.
void sync_to_disk(const std::string& path, int flags) {
  const int descriptor = ::open(path.c_str(), flags);
  if (descriptor < 0) throw std::runtime_error(path + ": cannot open to sync: " + std::strerror(errno));
  const int synced = ::fsync(descriptor);
  ::close(descriptor);
  if (synced != 0) throw std::runtime_error(path + ": fsync failed: " + std::strerror(errno));
}

// --- reading ----------------------------------------------------------------------------------------

class HistoryReader {
 public:
  explicit HistoryReader(std::string path) : path_(std::move(path)) {}

  std::vector<HistoryRow> read() {
    std::error_code ignored;
    if (!fs::exists(path_, ignored)) throw InputError(path_ + ": no such file");
    const std::string expected = std::string("; expected a nightly history file (schema ") + history_schema + ")";
    // Before libhdf5 sees a byte: it trusts its input, and crashes on some corrupt files. A file
    // without the seal was written by an fx2d-bench older than the seal on history files and is
    // read as before, for backward compatibility; the next append writes it sealed.
    if (carries_h5_seal(path_)) verify_h5_seal(path_);
    if (H5Fis_hdf5(path_.c_str()) <= 0) throw InputError(path_ + ": not an HDF5 file" + expected);
    const H5Handle file(H5Fopen(path_.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    if (!file.valid()) throw InputError(path_ + ": cannot open: the HDF5 file is truncated or damaged");
    const std::string schema = root_schema(file.get());
    if (schema != history_schema)
      throw InputError(path_ + ": schema '" + schema + "' is not supported" + expected);
    if (H5Lexists(file.get(), "history", H5P_DEFAULT) <= 0) fail("/history", "missing group");
    const H5Handle group(H5Gopen2(file.get(), "history", H5P_DEFAULT), H5Gclose);
    if (!group.valid()) fail("/history", "not a group");

    for (const auto& column : string_columns) fill(column, strings(group.get(), column.name));
    for (const auto& column : integer_columns) fill(column, numbers<std::int32_t>(group.get(), column.name));
    for (const auto& column : number_columns) fill(column, numbers<double>(group.get(), column.name));
    for (const auto& column : flag_columns) fill(column, numbers<std::uint8_t>(group.get(), column.name));
    return std::move(rows_);
  }

 private:
  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw InputError(path_ + ": " + where + ": " + what);
  }

  std::string root_schema(hid_t file) const {
    if (H5Aexists(file, "schema") <= 0) fail("/", "no root attribute 'schema'");
    const H5Handle attribute(H5Aopen(file, "schema", H5P_DEFAULT), H5Aclose);
    const H5Handle type(H5Aget_type(attribute.get()), H5Tclose);
    char* text = nullptr;
    if (H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()) <= 0 ||
        H5Aread(attribute.get(), type.get(), &text) < 0)
      fail("/", "attribute 'schema': expected a string");
    std::string schema = text != nullptr ? text : "";
    H5free_memory(text);
    return schema;
  }

  // Opens /history/<name>, checks its type class and that it is one-dimensional with as many rows
  // as the columns read before it; the first column read sets the row count.
  H5Handle open_column(hid_t group, const char* name, H5T_class_t type_class, const char* expected) {
    const std::string where = std::string(history_group) + "/" + name;
    if (H5Lexists(group, name, H5P_DEFAULT) <= 0) fail(where, "missing column");
    H5Handle dataset(H5Dopen2(group, name, H5P_DEFAULT), H5Dclose);
    const H5Handle type(H5Dget_type(dataset.get()), H5Tclose);
    if (!dataset.valid() || H5Tget_class(type.get()) != type_class ||
        (type_class == H5T_STRING && H5Tis_variable_str(type.get()) <= 0))
      fail(where, std::string("expected a column of ") + expected);
    const H5Handle space(H5Dget_space(dataset.get()), H5Sclose);
    hsize_t length = 0;
    if (H5Sget_simple_extent_ndims(space.get()) != 1 || H5Sget_simple_extent_dims(space.get(), &length, nullptr) < 0)
      fail(where, "expected a one-dimensional column");
    if (!row_count_known_) rows_.resize(length);
    if (length != rows_.size())
      fail(where, std::to_string(length) + " rows, but the columns before it have " + std::to_string(rows_.size()));
    row_count_known_ = true;
    return dataset;
  }

  std::vector<std::string> strings(hid_t group, const char* name) {
    const H5Handle dataset = open_column(group, name, H5T_STRING, "variable-length strings");
    const H5Handle type(H5Dget_type(dataset.get()), H5Tclose);
    std::vector<char*> raw(rows_.size(), nullptr);
    if (!raw.empty() && H5Dread(dataset.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, raw.data()) < 0)
      fail(std::string(history_group) + "/" + name, "cannot read its strings");
    std::vector<std::string> values;
    for (char* text : raw) {
      values.emplace_back(text != nullptr ? text : "");
      H5free_memory(text);
    }
    return values;
  }

  template <class T>
  std::vector<T> numbers(hid_t group, const char* name) {
    const bool is_float = H5Stored<T>::type_class == H5T_FLOAT;
    const H5Handle dataset = open_column(group, name, H5Stored<T>::type_class, is_float ? "numbers" : "integers");
    std::vector<T> values(rows_.size());
    if (!values.empty() &&
        H5Dread(dataset.get(), H5Stored<T>::memory_type(), H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0)
      fail(std::string(history_group) + "/" + name, "cannot read its values");
    return values;
  }

  template <class Field, class Stored>
  void fill(const Column<Field>& column, const std::vector<Stored>& values) {
    for (std::size_t i = 0; i < rows_.size(); ++i) rows_[i].*column.field = static_cast<Field>(values[i]);
  }

  std::string path_;
  std::vector<HistoryRow> rows_;
  bool row_count_known_ = false;
};

}  // namespace

std::vector<HistoryRow> read_history_h5(const std::string& path) {
  const SilentHdf5Errors quiet;
  return HistoryReader(path).read();
}

void append_history_h5(const std::string& path, std::span<const HistoryRow> rows, const AppendStageHook& at_stage) {
  const auto stage = [&](std::string_view name) {
    if (at_stage) at_stage(name);
  };
  std::error_code ignored;
  std::vector<HistoryRow> all = fs::exists(path, ignored) ? read_history_h5(path) : std::vector<HistoryRow>{};
  all.insert(all.end(), rows.begin(), rows.end());
  stage("read");
  // Beside the final name, so that the rename stays within one file system and is atomic.
  const std::string temporary = path + ".tmp." + std::to_string(::getpid());
  try {
    const std::pair<std::string, std::string> root[] = {{"schema", history_schema}};
    const H5Table tables[] = {history_table(all)};
    write_table_file_h5(temporary, root, tables);
    stage("written");
    sync_to_disk(temporary, O_RDONLY);
    stage("synced");
    if (std::rename(temporary.c_str(), path.c_str()) != 0)
      throw std::runtime_error(path + ": cannot rename " + temporary + " into place: " + std::strerror(errno));
  } catch (...) {
    fs::remove(temporary, ignored);
    throw;
  }
  const fs::path directory = fs::absolute(path).parent_path();
  sync_to_disk(directory.string(), O_RDONLY | O_DIRECTORY);
  stage("renamed");
}

}  // namespace fxbench
