// Appends column tables to a freshly written result file; invariants in h5_tables.h.
#include "storage/h5_tables.h"

#include <hdf5.h>

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

}  // namespace

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
