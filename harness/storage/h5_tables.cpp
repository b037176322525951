// Appends column tables to a freshly written result file; invariants in h5_tables.h.
#include "storage/h5_tables.h"

#include <hdf5.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <utility>

#include "common/errors.h"
#include "storage/atomic_file.h"
#include "storage/file_integrity.h"
#include "storage/h5_types.h"
#include "storage/results_h5.h"

namespace fxbench {
namespace {


class TableAppender {
 public:
  TableAppender(hid_t file, std::string path) : file_(file), path_(std::move(path)) {}

  void root_attribute(const std::string& name, const std::string& value) const {
    attribute(file_, "/ attribute " + name, name, value);
  }

  void append(const H5Table& table) const {
    const std::size_t rows = row_count(table);
    const H5Handle links(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
    H5Pset_create_intermediate_group(links.get(), 1);
    const H5Handle group(H5Gcreate2(file_, table.path.c_str(), links.get(), H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    if (!group.valid()) fail(table.path);
    for (const auto& [attribute_name, value] : table.attributes) {
      const std::string& name = attribute_name;  // Clang 14 cannot capture a structured binding
      std::visit([&](const auto& v) { attribute(group.get(), table.path + " attribute " + name, name, v); }, value);
    }
    for (const H5Column& column : table.columns) {
      const std::string where = table.path + "/" + column.name;
      std::visit([&](const auto& values) { write_column(group.get(), where, column, values, rows); }, column.values);
    }
  }

 private:
  [[noreturn]] void fail(const std::string& what) const { throw std::runtime_error(path_ + ": could not write " + what); }

  std::size_t row_count(const H5Table& table) const {
    std::size_t rows = 0;
    for (std::size_t i = 0; i < table.columns.size(); ++i) {
      const std::size_t length = std::visit([](const auto& values) { return values.size(); }, table.columns[i].values);
      if (i > 0 && length != rows)
        fail(table.path + "/" + table.columns[i].name + ": " + std::to_string(length) + " rows, not " + std::to_string(rows));
      rows = length;
    }
    return rows;
  }

  static H5Handle string_type() {
    H5Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(type.get(), H5T_VARIABLE);
    H5Tset_cset(type.get(), H5T_CSET_UTF8);
    return type;
  }

  void raw_attribute(hid_t owner, const std::string& where, const std::string& name, hid_t file_type,
                     hid_t memory_type, const void* data) const {
    const H5Handle space(H5Screate(H5S_SCALAR), H5Sclose);
    const H5Handle created(H5Acreate2(owner, name.c_str(), file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
    if (!created.valid() || H5Awrite(created.get(), memory_type, data) < 0) fail(where);
  }

  void attribute(hid_t owner, const std::string& where, const std::string& name, const std::string& value) const {
    const H5Handle type = string_type();
    const char* text = value.c_str();
    raw_attribute(owner, where, name, type.get(), type.get(), &text);
  }

  template <class T>
  void attribute(hid_t owner, const std::string& where, const std::string& name, T value) const {
    raw_attribute(owner, where, name, H5Stored<T>::file_type(), H5Stored<T>::memory_type(), &value);
  }

  H5Handle dataset(hid_t group, const std::string& where, const std::string& name, hid_t file_type, hid_t memory_type,
                std::size_t rows, const void* data) const {
    const hsize_t extent = rows;
    const H5Handle space(H5Screate_simple(1, &extent, nullptr), H5Sclose);
    H5Handle created(H5Dcreate2(group, name.c_str(), file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                  H5Dclose);
    // HDF5 refuses a null buffer even for zero rows, and an empty vector may give one.
    if (!created.valid() || (rows > 0 && H5Dwrite(created.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0))
      fail(where);
    return created;
  }

  void write_column(hid_t group, const std::string& where, const H5Column& column,
                    const std::vector<std::string>& values, std::size_t rows) const {
    std::vector<const char*> texts;
    texts.reserve(values.size());
    for (const std::string& value : values) texts.push_back(value.c_str());
    const H5Handle type = string_type();
    dataset(group, where, column.name, type.get(), type.get(), rows, texts.data());
  }

  template <class T>
  void write_column(hid_t group, const std::string& where, const H5Column& column, const std::vector<T>& values,
                    std::size_t rows) const {
    const H5Handle created =
        dataset(group, where, column.name, H5Stored<T>::file_type(), H5Stored<T>::memory_type(), rows, values.data());
    attribute(created.get(), where + " attribute units", "units", column.units);
  }

  hid_t file_;
  std::string path_;
};

// Reads back what TableAppender wrote: scalar attributes and one-dimensional columns.
class TableReader {
 public:
  TableReader(std::string path, std::string group_path) : path_(std::move(path)), group_path_(std::move(group_path)) {}

  H5Table read(hid_t file) const {
    const H5Handle group(H5Gopen2(file, group_path_.c_str(), H5P_DEFAULT), H5Gclose);
    if (!group.valid()) fail("no such table");
    H5Table table{group_path_, {}, {}};
    H5O_info_t info{};
    if (H5Oget_info(group.get(), &info) < 0) fail("cannot read its attributes");
    for (hsize_t i = 0; i < info.num_attrs; ++i) table.attributes.push_back(attribute(group.get(), i));
    hsize_t links = 0;
    H5G_info_t group_info{};
    if (H5Gget_info(group.get(), &group_info) < 0) fail("cannot list its columns");
    links = group_info.nlinks;
    for (hsize_t i = 0; i < links; ++i) {
      const std::string name = link_name(group.get(), i);
      H5O_info_t member{};
      if (H5Oget_info_by_name(group.get(), name.c_str(), &member, H5P_DEFAULT) < 0) fail(name + ": cannot be read");
      if (member.type == H5O_TYPE_DATASET) table.columns.push_back(column(group.get(), name));
    }
    return table;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const { throw InputError(path_ + ": " + group_path_ + ": " + what); }

  std::string link_name(hid_t group, hsize_t i) const {
    const ssize_t length = H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
    if (length < 0) fail("cannot list its columns");
    std::string name(static_cast<std::size_t>(length) + 1, '\0');
    H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(), name.size(), H5P_DEFAULT);
    name.resize(static_cast<std::size_t>(length));
    return name;
  }

  std::pair<std::string, std::variant<std::string, double, std::int32_t>> attribute(hid_t owner, hsize_t i) const {
    const H5Handle opened(H5Aopen_by_idx(owner, ".", H5_INDEX_NAME, H5_ITER_INC, i, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
    if (!opened.valid()) fail("cannot read its attributes");
    const ssize_t length = H5Aget_name(opened.get(), 0, nullptr);
    std::string name(static_cast<std::size_t>(std::max<ssize_t>(length, 0)) + 1, '\0');
    H5Aget_name(opened.get(), name.size(), name.data());
    name.resize(name.size() - 1);
    const H5Handle type(H5Aget_type(opened.get()), H5Tclose);
    const H5T_class_t type_class = H5Tget_class(type.get());
    if (type_class == H5T_STRING && H5Tis_variable_str(type.get()) > 0) {
      char* text = nullptr;
      if (H5Aread(opened.get(), type.get(), &text) < 0) fail("attribute " + name + ": cannot be read");
      std::string value = text != nullptr ? text : "";
      H5free_memory(text);
      return {name, value};
    }
    if (type_class == H5T_FLOAT) {
      double value = 0;
      if (H5Aread(opened.get(), H5T_NATIVE_DOUBLE, &value) < 0) fail("attribute " + name + ": cannot be read");
      return {name, value};
    }
    if (type_class == H5T_INTEGER) {
      std::int32_t value = 0;
      if (H5Aread(opened.get(), H5T_NATIVE_INT32, &value) < 0) fail("attribute " + name + ": cannot be read");
      return {name, value};
    }
    fail("attribute " + name + ": expected a string or a number");
  }

  template <class T>
  std::vector<T> numbers(hid_t dataset, const std::string& name, std::size_t rows) const {
    std::vector<T> values(rows);
    if (rows > 0 && H5Dread(dataset, H5Stored<T>::memory_type(), H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0)
      fail(name + ": cannot read its values");
    return values;
  }

  H5Column column(hid_t group, const std::string& name) const {
    const H5Handle dataset(H5Dopen2(group, name.c_str(), H5P_DEFAULT), H5Dclose);
    const H5Handle type(H5Dget_type(dataset.get()), H5Tclose);
    const H5Handle space(H5Dget_space(dataset.get()), H5Sclose);
    hsize_t rows = 0;
    if (!dataset.valid() || H5Sget_simple_extent_ndims(space.get()) != 1 ||
        H5Sget_simple_extent_dims(space.get(), &rows, nullptr) < 0)
      fail(name + ": expected a one-dimensional column");
    H5Column column{name, units(dataset.get()), {}};
    const H5T_class_t type_class = H5Tget_class(type.get());
    if (type_class == H5T_STRING && H5Tis_variable_str(type.get()) > 0) {
      std::vector<char*> raw(rows, nullptr);
      if (rows > 0 && H5Dread(dataset.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, raw.data()) < 0)
        fail(name + ": cannot read its strings");
      std::vector<std::string> values;
      for (char* text : raw) {
        values.emplace_back(text != nullptr ? text : "");
        H5free_memory(text);
      }
      column.values = std::move(values);
    } else if (type_class == H5T_FLOAT) {
      column.values = numbers<double>(dataset.get(), name, rows);
    } else if (type_class == H5T_INTEGER && H5Tget_size(type.get()) == 1) {
      column.values = numbers<std::uint8_t>(dataset.get(), name, rows);
    } else if (type_class == H5T_INTEGER) {
      column.values = numbers<std::int32_t>(dataset.get(), name, rows);
    } else {
      fail(name + ": expected a column of numbers or strings");
    }
    return column;
  }

  static std::string units(hid_t dataset) {
    if (H5Aexists(dataset, "units") <= 0) return {};
    const H5Handle opened(H5Aopen(dataset, "units", H5P_DEFAULT), H5Aclose);
    const H5Handle type(H5Aget_type(opened.get()), H5Tclose);
    char* text = nullptr;
    if (H5Tis_variable_str(type.get()) <= 0 || H5Aread(opened.get(), type.get(), &text) < 0) return {};
    std::string value = text != nullptr ? text : "";
    H5free_memory(text);
    return value;
  }

  std::string path_;
  std::string group_path_;
};

H5Handle open_for_reading(const std::string& path) {
  H5Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!file.valid()) throw InputError(path + ": cannot open as an HDF5 file");
  return file;
}

}  // namespace

H5Table read_table_h5(const std::string& path, const std::string& group_path) {
  const SilentHdf5Errors quiet;
  const H5Handle file = open_for_reading(path);
  return TableReader(path, group_path).read(file.get());
}

bool has_table_h5(const std::string& path, const std::string& group_path) {
  const SilentHdf5Errors quiet;
  const H5Handle file = open_for_reading(path);
  return H5Lexists(file.get(), group_path.c_str(), H5P_DEFAULT) > 0;
}

void write_table_file_h5(const std::string& path, std::span<const std::pair<std::string, std::string>> root_attributes,
                         std::span<const H5Table> tables) {
  const SilentHdf5Errors quiet;
  // Room for the seal (file_integrity.h), written once the file is closed.
  const H5Handle creation(H5Pcreate(H5P_FILE_CREATE), H5Pclose);
  H5Pset_userblock(creation.get(), h5_seal_bytes);
  H5Handle file(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, creation.get(), H5P_DEFAULT), H5Fclose);
  if (!file.valid()) throw std::runtime_error(path + ": cannot create; is its directory there and writable?");
  const TableAppender appender(file.get(), path);
  for (const auto& [name, value] : root_attributes) appender.root_attribute(name, value);
  for (const H5Table& table : tables) appender.append(table);
  if (!file.close()) throw std::runtime_error(path + ": could not write the file to disk");
  seal_h5_file(path);
}

void write_results_with_tables_h5(const ResultSet& results, std::span<const H5Table> tables, const std::string& path,
                                  bool overwrite) {
  namespace fs = std::filesystem;
  if (!overwrite && fs::exists(path)) throw InputError(path + ": exists; pass --force to overwrite it");
  write_atomically(path, [&](const std::string& partial) {
    write_results_h5(results, partial, true);
    const SilentHdf5Errors quiet;
    H5Handle file(H5Fopen(partial.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose);
    if (!file.valid()) throw std::runtime_error(path + ": could not reopen " + partial);
    const TableAppender appender(file.get(), path);
    for (const H5Table& table : tables) appender.append(table);
    if (!file.close()) throw std::runtime_error(path + ": could not write the file to disk");
    seal_h5_file(partial);  // the tables changed the bytes the results' seal covered
  });
}

}  // namespace fxbench
