// Reading an HDF5 result file back into a ResultSet, through the HDF5 C API; the writer is
// results_h5_writer.cpp, the names both walk are in results_layout.h. Layout: harness/RESULTS_FORMAT.md.
//
// Invariants: every attribute and dataset is named once, in results_layout.h, which both the
// writer and the reader walk, so the two cannot disagree; every HDF5 identifier is owned by a
// H5Handle and closed on every path; HDF5's automatic error printing is off for the whole of a
// read or write, so failures reach the user only as our own one-line messages.
#include "storage/results_h5.h"

#include <hdf5.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <system_error>
#include <type_traits>
#include <utility>
#include <vector>

#include "common/errors.h"
#include "storage/atomic_file.h"
#include "storage/file_integrity.h"
#include "storage/h5_types.h"
#include "storage/results_layout.h"

namespace fxbench {
namespace {

using namespace results_layout;

class ResultsReader {
 public:
  explicit ResultsReader(std::string path) : path_(std::move(path)) {}

  ResultSet read() const {
    std::error_code ignored;
    if (!std::filesystem::exists(path_, ignored)) throw InputError(path_ + ": no such file");
    const std::string expected =
        std::string("; expected an fx2d-bench result file (schema ") + results_schema + ")";
    // Before libhdf5 sees a byte: it trusts its input, and crashes on some corrupt files.
    verify_h5_seal(path_);
    if (H5Fis_hdf5(path_.c_str()) <= 0) throw InputError(path_ + ": not an HDF5 file" + expected);
    const H5Handle file(H5Fopen(path_.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    if (!file.valid()) throw InputError(path_ + ": cannot open: the HDF5 file is truncated or damaged");
    if (H5Aexists(file.get(), "schema") <= 0)
      throw InputError(path_ + ": no root attribute 'schema'" + expected);
    ResultSet results;
    results.provenance.schema = string_attribute(file.get(), "/", "schema");
    if (results.provenance.schema != results_schema) {
      throw InputError(path_ + ": schema '" + results.provenance.schema + "' is not supported; expected " +
                       results_schema);
    }
    for (const auto& member : provenance_strings) {
      results.provenance.*member.field = string_attribute(file.get(), "/", member.name);
    }
    for (const auto& member : provenance_numbers) {
      results.provenance.*member.field = number_attribute<double>(file.get(), "/", member.name);
    }
    for (const auto& member : optional_provenance_numbers) {
      if (H5Aexists(file.get(), member.name) > 0)
        results.provenance.*member.field = number_attribute<double>(file.get(), "/", member.name);
    }
    results.partial = H5Aexists(file.get(), partial_attribute) > 0 &&
                      number_attribute<std::uint8_t>(file.get(), "/", partial_attribute) != 0;
    for_each_numbered_group(file.get(), "scenes", [&](hid_t group, const std::string& where) {
      results.scenes.push_back(read_scene(group, where));
    });
    for_each_numbered_group(file.get(), "runs", [&](hid_t group, const std::string& where) {
      results.runs.push_back(read_run(group, where));
    });
    return results;
  }

 private:
  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw InputError(path_ + ": " + where + ": " + what);
  }

  H5Handle open_group(hid_t parent, const std::string& where, const std::string& name) const {
    if (H5Lexists(parent, name.c_str(), H5P_DEFAULT) <= 0) fail(where, "missing group '" + name + "'");
    H5Handle group(H5Gopen2(parent, name.c_str(), H5P_DEFAULT), H5Gclose);
    if (!group.valid()) fail(where, "'" + name + "' is not a group");
    return group;
  }

  // Calls visit(group, "/<collection>/<k>") for k = 0, 1, ... over every member of /<collection>.
  template <class Visit>
  void for_each_numbered_group(hid_t root, const std::string& collection, Visit visit) const {
    const H5Handle group = open_group(root, "/", collection);
    H5G_info_t info{};
    if (H5Gget_info(group.get(), &info) < 0) fail("/" + collection, "cannot list its members");
    for (hsize_t k = 0; k < info.nlinks; ++k) {
      const std::string name = std::to_string(k);
      const H5Handle member = open_group(group.get(), "/" + collection, name);
      visit(member.get(), "/" + collection + "/" + name);
    }
  }

  H5Handle open_attribute(hid_t owner, const std::string& where, const char* name, H5T_class_t type_class,
                        const char* expected) const {
    if (H5Aexists(owner, name) <= 0) fail(where, std::string("missing attribute '") + name + "'");
    H5Handle attribute(H5Aopen(owner, name, H5P_DEFAULT), H5Aclose);
    const H5Handle type(H5Aget_type(attribute.get()), H5Tclose);
    if (H5Tget_class(type.get()) != type_class ||
        (type_class == H5T_STRING && H5Tis_variable_str(type.get()) <= 0)) {
      fail(where, std::string("attribute '") + name + "': expected " + expected);
    }
    return attribute;
  }

  // Reads `count` variable-length strings through read_into(type, buffer), an H5Aread or H5Dread
  // call, and frees HDF5's copies. The file's own string type is the memory type, so no
  // character-set conversion is asked of HDF5.
  template <class Read>
  std::optional<std::vector<std::string>> read_strings(hid_t type, std::size_t count, Read read_into) const {
    std::vector<char*> raw(count, nullptr);
    if (count > 0 && read_into(type, raw.data()) < 0) return std::nullopt;
    std::vector<std::string> strings;
    for (char* text : raw) {
      strings.emplace_back(text != nullptr ? text : "");
      H5free_memory(text);
    }
    return strings;
  }

  std::vector<std::string> string_array_attribute(hid_t owner, const std::string& where,
                                                  const char* name) const {
    const H5Handle attribute = open_attribute(owner, where, name, H5T_STRING, "variable-length strings");
    const H5Handle type(H5Aget_type(attribute.get()), H5Tclose);
    const H5Handle space(H5Aget_space(attribute.get()), H5Sclose);
    const auto count = static_cast<std::size_t>(H5Sget_simple_extent_npoints(space.get()));
    const auto strings = read_strings(type.get(), count, [&](hid_t memory_type, char** buffer) {
      return H5Aread(attribute.get(), memory_type, buffer);
    });
    if (!strings) fail(where, std::string("cannot read attribute '") + name + "'");
    return *strings;
  }

  std::string string_attribute(hid_t owner, const std::string& where, const char* name) const {
    std::vector<std::string> strings = string_array_attribute(owner, where, name);
    if (strings.size() != 1) fail(where, std::string("attribute '") + name + "': expected a single string");
    return strings.front();
  }

  template <class T>
  T number_attribute(hid_t owner, const std::string& where, const char* name) const {
    const bool is_float = H5Stored<T>::type_class == H5T_FLOAT;
    const H5Handle attribute =
        open_attribute(owner, where, name, H5Stored<T>::type_class, is_float ? "a number" : "an integer");
    const H5Handle space(H5Aget_space(attribute.get()), H5Sclose);
    T value{};
    if (H5Sget_simple_extent_npoints(space.get()) != 1 ||
        H5Aread(attribute.get(), H5Stored<T>::memory_type(), &value) < 0) {
      fail(where, std::string("attribute '") + name + "': expected a single value");
    }
    return value;
  }

  H5Handle open_dataset(hid_t group, const std::string& where, const char* name, H5T_class_t type_class,
                      const char* expected) const {
    if (H5Lexists(group, name, H5P_DEFAULT) <= 0) fail(where, std::string("missing dataset '") + name + "'");
    H5Handle dataset(H5Dopen2(group, name, H5P_DEFAULT), H5Dclose);
    if (!dataset.valid()) fail(where, std::string("'") + name + "' is not a dataset");
    const H5Handle type(H5Dget_type(dataset.get()), H5Tclose);
    if (H5Tget_class(type.get()) != type_class ||
        (type_class == H5T_STRING && H5Tis_variable_str(type.get()) <= 0)) {
      fail(where + "/" + name, std::string("expected ") + expected);
    }
    return dataset;
  }

  std::vector<hsize_t> shape_of(hid_t dataset) const {
    const H5Handle space(H5Dget_space(dataset), H5Sclose);
    std::vector<hsize_t> shape(
        static_cast<std::size_t>(std::max(H5Sget_simple_extent_ndims(space.get()), 0)));
    H5Sget_simple_extent_dims(space.get(), shape.data(), nullptr);
    return shape;
  }

  // Opens `name` and checks its shape; an empty `expected` accepts any one-dimensional length.
  H5Handle open_shaped(hid_t group, const std::string& where, const char* name, H5T_class_t type_class,
                     const char* expected_type, const std::vector<hsize_t>& expected) const {
    H5Handle dataset = open_dataset(group, where, name, type_class, expected_type);
    const std::vector<hsize_t> shape = shape_of(dataset.get());
    if (expected.empty() ? shape.size() != 1 : shape != expected) {
      fail(where + "/" + name, "expected shape " +
                                   (expected.empty() ? std::string("[n]") : shape_text(expected)) +
                                   ", found " + shape_text(shape));
    }
    return dataset;
  }

  template <class T>
  std::vector<T> numbers(hid_t group, const std::string& where, const char* name,
                         const std::vector<hsize_t>& expected) const {
    const char* kind = H5Stored<T>::type_class == H5T_FLOAT ? "floating-point numbers" : "integers";
    const H5Handle dataset = open_shaped(group, where, name, H5Stored<T>::type_class, kind, expected);
    std::vector<T> values(element_count(expected));
    if (!values.empty() &&
        H5Dread(dataset.get(), H5Stored<T>::memory_type(), H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0) {
      fail(where + "/" + name, "cannot read its values");
    }
    return values;
  }

  // A one-dimensional string dataset, or a scalar one when `scalar`.
  std::vector<std::string> strings(hid_t group, const std::string& where, const char* name,
                                   bool scalar) const {
    const H5Handle dataset = open_dataset(group, where, name, H5T_STRING, "variable-length strings");
    const std::vector<hsize_t> shape = shape_of(dataset.get());
    if (shape.size() != (scalar ? 0u : 1u)) {
      fail(where + "/" + name, std::string("expected ") + (scalar ? "a single string" : "a list of strings") +
                                   ", found shape " + shape_text(shape));
    }
    const H5Handle type(H5Dget_type(dataset.get()), H5Tclose);
    const auto values = read_strings(type.get(), element_count(shape), [&](hid_t memory_type, char** buffer) {
      return H5Dread(dataset.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer);
    });
    if (!values) fail(where + "/" + name, "cannot read its strings");
    return *values;
  }

  std::vector<AccuracySample> accuracy(hid_t group, const std::string& where) const {
    const H5Handle dataset =
        open_shaped(group, where, "accuracy", H5T_COMPOUND, "a table of accuracy samples", {});
    std::vector<AccuracySample> samples(element_count(shape_of(dataset.get())));
    const H5Handle in_memory = accuracy_type(true);
    if (!samples.empty() &&
        H5Dread(dataset.get(), in_memory.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, samples.data()) < 0) {
      std::string fields;
      for (const AccuracyField& field : accuracy_fields)
        fields += std::string(fields.empty() ? "" : ", ") + field.name;
      fail(where + "/accuracy", "expected the fields " + fields);
    }
    return samples;
  }

  SceneRecord read_scene(hid_t scene, const std::string& where) const {
    SceneRecord record;
    for (const auto& member : scene_strings)
      record.*member.field = string_attribute(scene, where, member.name);
    record.resolved_json = strings(scene, where, "resolved_json", true).front();
    return record;
  }

  RunRecord read_run(hid_t run, const std::string& where) const {
    RunRecord record;
    for (const auto& member : run_strings) record.*member.field = string_attribute(run, where, member.name);
    for (const auto& member : run_integers)
      record.*member.field = number_attribute<int>(run, where, member.name);
    record.deterministic = number_attribute<std::uint8_t>(run, where, "deterministic") != 0;
    if (record.repeats < 0 || record.steps < 0) fail(where, "expected repeats >= 0 and steps >= 0");

    const std::vector<hsize_t> per_step{static_cast<hsize_t>(record.repeats),
                                        static_cast<hsize_t>(record.steps)};
    for (const TimedSeries& series : run_times)
      record.*series.field = numbers<double>(run, where, series.name, per_step);
    record.cycles = numbers<std::uint64_t>(run, where, "cycles", per_step);
    record.contacts = numbers<std::int32_t>(run, where, "contacts", per_step);
    if (H5Lexists(run, "phase_ms", H5P_DEFAULT) > 0) {
      record.phase_names = string_array_attribute(
          open_dataset(run, where, "phase_ms", H5T_FLOAT, "floating-point numbers").get(),
          where + "/phase_ms", "phase_names");
      record.phase_ms =
          numbers<double>(run, where, "phase_ms", {per_step[0], per_step[1], record.phase_names.size()});
    }
    record.accuracy = accuracy(run, where);
    record.state_hashes = strings(run, where, "state_hashes", false);
    if (H5Lexists(run, instructions_dataset, H5P_DEFAULT) > 0) record.instruction_count = instruction_count(run, where);
    return record;
  }

  InstructionCount instruction_count(hid_t run, const std::string& where) const {
    const std::string counted = where + "/" + instructions_dataset;
    const H5Handle dataset = open_dataset(run, where, instructions_dataset, H5T_INTEGER, "an integer");
    InstructionCount count;
    if (!shape_of(dataset.get()).empty() ||
        H5Dread(dataset.get(), H5Stored<std::uint64_t>::memory_type(), H5S_ALL, H5S_ALL, H5P_DEFAULT,
                &count.instructions) < 0) {
      fail(counted, "expected a single unsigned integer");
    }
    count.steps = number_attribute<int>(dataset.get(), counted, instructions_steps_attribute);
    for (const auto& member : instruction_count_strings)
      count.*member.field = string_attribute(dataset.get(), counted, member.name);
    return count;
  }

  std::string path_;
};

}  // namespace

ResultSet read_results_h5(const std::string& path) {
  const SilentHdf5Errors quiet;
  return ResultsReader(path).read();
}

std::string h5_root_schema(const std::string& path) {
  const SilentHdf5Errors quiet;
  if (H5Fis_hdf5(path.c_str()) <= 0) throw InputError(path + ": not an HDF5 file");
  const H5Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (file.get() < 0) throw InputError(path + ": cannot open: the HDF5 file is truncated or damaged");
  if (H5Aexists(file.get(), "schema") <= 0) return {};
  const H5Handle attribute(H5Aopen(file.get(), "schema", H5P_DEFAULT), H5Aclose);
  const H5Handle stored_type(H5Aget_type(attribute.get()), H5Tclose);
  if (H5Tget_class(stored_type.get()) != H5T_STRING || H5Tis_variable_str(stored_type.get()) <= 0) return {};
  const H5Handle text_type = results_layout::utf8_string_type();
  char* text = nullptr;
  if (H5Aread(attribute.get(), text_type.get(), static_cast<void*>(&text)) < 0 || text == nullptr) return {};
  std::string schema(text);
  H5free_memory(text);
  return schema;
}

}  // namespace fxbench
