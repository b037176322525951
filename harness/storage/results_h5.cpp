// The HDF5 result file, through the HDF5 C API. Layout: harness/RESULTS_FORMAT.md.
//
// Invariants: every attribute and dataset is named once, in the tables below, which both the
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

namespace fxbench {
namespace {

static_assert(std::is_same_v<int, std::int32_t>, "the records' int fields are stored as int32");

template <class Record, class Field>
struct Member {
  const char* name;
  Field Record::*field;
};

constexpr Member<Provenance, std::string> provenance_strings[] = {
    {"fx2d_version", &Provenance::fx2d_version},
    {"fx2d_git_revision", &Provenance::fx2d_git_revision},
    {"build_type", &Provenance::build_type},
    {"build_flags", &Provenance::build_flags},
    {"compiler", &Provenance::compiler},
    {"cpu_model", &Provenance::cpu_model},
    {"kernel", &Provenance::kernel},
    {"hostname", &Provenance::hostname},
    {"date_utc", &Provenance::date_utc},
    {"command_line", &Provenance::command_line},
    {"counter_kind", &Provenance::counter_kind},
};
constexpr Member<Provenance, double> provenance_numbers[] = {{"tsc_ghz", &Provenance::tsc_ghz}};
constexpr const char* partial_attribute = "partial";

constexpr Member<SceneRecord, std::string> scene_strings[] = {
    {"name", &SceneRecord::name},
    {"hash", &SceneRecord::hash},
    {"source_path", &SceneRecord::source_path},
    {"primary_metric", &SceneRecord::primary_metric},
};

constexpr Member<RunRecord, std::string> run_strings[] = {
    {"engine", &RunRecord::engine},
    {"engine_version", &RunRecord::engine_version},
    {"engine_settings", &RunRecord::engine_settings},
    {"scene", &RunRecord::scene},
    {"scene_hash", &RunRecord::scene_hash},
    {"final_state_hash", &RunRecord::final_state_hash},
};
constexpr Member<RunRecord, int> run_integers[] = {
    {"bodies", &RunRecord::bodies},
    {"body_count", &RunRecord::body_count},
    {"steps", &RunRecord::steps},
    {"repeats", &RunRecord::repeats},
    {"warmup_steps", &RunRecord::warmup_steps},
    {"hash_every", &RunRecord::hash_every},
};

// The per-step series, shaped [repeats x steps].
struct TimedSeries {
  const char* name;
  std::vector<double> RunRecord::*field;
  const char* units;
};
constexpr TimedSeries run_times[] = {{"wall_ms", &RunRecord::wall_ms, "ms"},
                                     {"cpu_ms", &RunRecord::cpu_ms, "ms"}};
constexpr const char* cycles_units = "cycles";

// A run counted with --counter instructions has one scalar dataset more, with its provenance.
constexpr const char* instructions_dataset = "instructions";
constexpr const char* instructions_units = "instructions";
constexpr const char* instructions_steps_attribute = "steps";
constexpr Member<InstructionCount, std::string> instruction_count_strings[] = {
    {"tool", &InstructionCount::tool},
    {"tool_version", &InstructionCount::tool_version},
};
constexpr const char* contacts_units = "manifolds";
constexpr const char* phase_units = "ms";

struct AccuracyField {
  const char* name;
  std::size_t offset;
  bool is_integer;
  const char* units;
};
const AccuracyField accuracy_fields[] = {
    {"step", offsetof(AccuracySample, step), true, "step"},
    {"max_penetration", offsetof(AccuracySample, max_penetration), false, "m"},
    {"mean_penetration", offsetof(AccuracySample, mean_penetration), false, "m"},
    {"max_displacement", offsetof(AccuracySample, max_displacement), false, "m"},
    {"max_lateral_drift", offsetof(AccuracySample, max_lateral_drift), false, "m"},
    {"kinetic_energy", offsetof(AccuracySample, kinetic_energy), false, "J"},
    {"escaped", offsetof(AccuracySample, escaped), true, "bodies"},
    {"nan", offsetof(AccuracySample, nan), true, "bodies"},
};

// AccuracySample as HDF5 sees it: in memory at the struct's own offsets, in the file packed
// little-endian.
H5Handle accuracy_type(bool in_memory) {
  H5Handle type(H5Tcreate(H5T_COMPOUND, sizeof(AccuracySample)), H5Tclose);
  std::size_t packed_offset = 0;
  for (const AccuracyField& field : accuracy_fields) {
    const hid_t member =
        field.is_integer
            ? (in_memory ? H5Stored<std::int32_t>::memory_type() : H5Stored<std::int32_t>::file_type())
            : (in_memory ? H5Stored<double>::memory_type() : H5Stored<double>::file_type());
    H5Tinsert(type.get(), field.name, in_memory ? field.offset : packed_offset, member);
    packed_offset += H5Tget_size(member);
  }
  if (!in_memory) H5Tset_size(type.get(), packed_offset);
  return type;
}

H5Handle utf8_string_type() {
  H5Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type.get(), H5T_VARIABLE);
  H5Tset_cset(type.get(), H5T_CSET_UTF8);
  return type;
}

// An empty shape is a scalar.
H5Handle space_of(const std::vector<hsize_t>& shape) {
  if (shape.empty()) return H5Handle(H5Screate(H5S_SCALAR), H5Sclose);
  return H5Handle(H5Screate_simple(static_cast<int>(shape.size()), shape.data(), nullptr), H5Sclose);
}

std::size_t element_count(const std::vector<hsize_t>& shape) {
  std::size_t count = 1;
  for (hsize_t extent : shape) count *= extent;
  return count;
}

std::string shape_text(const std::vector<hsize_t>& shape) {
  std::string text = "[";
  for (std::size_t i = 0; i < shape.size(); ++i) text += (i > 0 ? " x " : "") + std::to_string(shape[i]);
  return text + "]";
}

std::vector<const char*> c_strings(const std::vector<std::string>& strings) {
  std::vector<const char*> pointers;
  for (const std::string& text : strings) pointers.push_back(text.c_str());
  return pointers;
}

class ResultsWriter {
 public:
  explicit ResultsWriter(std::string path) : path_(std::move(path)) {}

  void write(const ResultSet& results, const std::string& file_path) const {
    // Room for the seal (file_integrity.h), written once the file is closed.
    const H5Handle creation(H5Pcreate(H5P_FILE_CREATE), H5Pclose);
    H5Pset_userblock(creation.get(), h5_seal_bytes);
    H5Handle file(H5Fcreate(file_path.c_str(), H5F_ACC_TRUNC, creation.get(), H5P_DEFAULT), H5Fclose);
    if (!file.valid())
      throw InputError(path_ + ": cannot create " + file_path + "; is its directory there and writable?");
    write_provenance(file.get(), results.provenance);
    // Only a partial file carries the attribute, so complete files keep the layout they always had.
    if (results.partial) number_attribute<std::uint8_t>(file.get(), "/", partial_attribute, 1);
    write_scenes(file.get(), results.scenes);
    write_runs(file.get(), results.runs, results.provenance.counter_kind);
    if (!file.close()) fail("the file to disk");
    seal_h5_file(file_path);
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error(path_ + ": could not write " + what);
  }

  H5Handle create_group(hid_t parent, const std::string& where, const std::string& name) const {
    H5Handle group(H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    if (!group.valid()) fail(where + "/" + name);
    return group;
  }

  void attribute(hid_t owner, const std::string& where, const char* name, hid_t file_type, hid_t memory_type,
                 const std::vector<hsize_t>& shape, const void* data) const {
    const H5Handle space = space_of(shape);
    const H5Handle created(H5Acreate2(owner, name, file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
    if (!created.valid() || H5Awrite(created.get(), memory_type, data) < 0)
      fail(where + " attribute " + name);
  }

  void string_attribute(hid_t owner, const std::string& where, const char* name,
                        const std::string& value) const {
    const H5Handle type = utf8_string_type();
    const char* text = value.c_str();
    attribute(owner, where, name, type.get(), type.get(), {}, &text);
  }

  void string_array_attribute(hid_t owner, const std::string& where, const char* name,
                              const std::vector<std::string>& values) const {
    const H5Handle type = utf8_string_type();
    attribute(owner, where, name, type.get(), type.get(), {values.size()}, c_strings(values).data());
  }

  template <class T>
  void number_attribute(hid_t owner, const std::string& where, const char* name, T value) const {
    attribute(owner, where, name, H5Stored<T>::file_type(), H5Stored<T>::memory_type(), {}, &value);
  }

  H5Handle dataset(hid_t group, const std::string& where, const char* name, hid_t file_type, hid_t memory_type,
                 const std::vector<hsize_t>& shape, const void* data) const {
    const H5Handle space = space_of(shape);
    H5Handle created(H5Dcreate2(group, name, file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                   H5Dclose);
    // HDF5 refuses a null buffer even for zero elements, and an empty vector may give one.
    const bool has_data = element_count(shape) > 0;
    if (!created.valid() ||
        (has_data && H5Dwrite(created.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)) {
      fail(where + "/" + name);
    }
    return created;
  }

  template <class T>
  H5Handle numeric_dataset(hid_t group, const std::string& where, const char* name,
                         const std::vector<hsize_t>& shape, const std::vector<T>& values,
                         const char* units) const {
    if (values.size() != element_count(shape)) {
      fail(where + "/" + name + ": " + std::to_string(values.size()) + " values do not fill " +
           shape_text(shape));
    }
    H5Handle created =
        dataset(group, where, name, H5Stored<T>::file_type(), H5Stored<T>::memory_type(), shape, values.data());
    string_attribute(created.get(), where + "/" + name, "units", units);
    return created;
  }

  void write_provenance(hid_t root, const Provenance& provenance) const {
    string_attribute(root, "/", "schema", results_schema);
    for (const auto& member : provenance_strings)
      string_attribute(root, "/", member.name, provenance.*member.field);
    for (const auto& member : provenance_numbers)
      number_attribute(root, "/", member.name, provenance.*member.field);
  }

  void write_scenes(hid_t root, const std::vector<SceneRecord>& scenes) const {
    const H5Handle group = create_group(root, "", "scenes");
    for (std::size_t k = 0; k < scenes.size(); ++k) {
      const std::string where = "/scenes/" + std::to_string(k);
      const H5Handle scene = create_group(group.get(), "/scenes", std::to_string(k));
      for (const auto& member : scene_strings)
        string_attribute(scene.get(), where, member.name, scenes[k].*member.field);
      const H5Handle type = utf8_string_type();
      const char* json = scenes[k].resolved_json.c_str();
      dataset(scene.get(), where, "resolved_json", type.get(), type.get(), {}, &json);
    }
  }

  void write_runs(hid_t root, const std::vector<RunRecord>& runs, const std::string& counter_kind) const {
    const H5Handle group = create_group(root, "", "runs");
    for (std::size_t k = 0; k < runs.size(); ++k) {
      const H5Handle run = create_group(group.get(), "/runs", std::to_string(k));
      write_run(run.get(), "/runs/" + std::to_string(k), runs[k], counter_kind);
    }
  }

  void write_run(hid_t run, const std::string& where, const RunRecord& record,
                 const std::string& counter_kind) const {
    for (const auto& member : run_strings) string_attribute(run, where, member.name, record.*member.field);
    for (const auto& member : run_integers) number_attribute(run, where, member.name, record.*member.field);
    number_attribute<std::uint8_t>(run, where, "deterministic", record.deterministic ? 1 : 0);

    const std::vector<hsize_t> per_step{static_cast<hsize_t>(record.repeats),
                                        static_cast<hsize_t>(record.steps)};
    for (const TimedSeries& series : run_times) {
      numeric_dataset(run, where, series.name, per_step, record.*series.field, series.units);
    }
    const H5Handle cycles = numeric_dataset(run, where, "cycles", per_step, record.cycles, cycles_units);
    string_attribute(cycles.get(), where + "/cycles", "counter", counter_kind);
    numeric_dataset(run, where, "contacts", per_step, record.contacts, contacts_units);
    write_phases(run, where, per_step, record);
    write_accuracy(run, where, record.accuracy);

    const H5Handle type = utf8_string_type();
    dataset(run, where, "state_hashes", type.get(), type.get(), {record.state_hashes.size()},
            c_strings(record.state_hashes).data());
    if (record.instruction_count) write_instruction_count(run, where, *record.instruction_count);
  }

  void write_instruction_count(hid_t run, const std::string& where, const InstructionCount& count) const {
    const std::string counted = where + "/" + instructions_dataset;
    const H5Handle instructions = numeric_dataset(run, where, instructions_dataset, {},
                                                  std::vector<std::uint64_t>{count.instructions}, instructions_units);
    number_attribute(instructions.get(), counted, instructions_steps_attribute, count.steps);
    for (const auto& member : instruction_count_strings)
      string_attribute(instructions.get(), counted, member.name, count.*member.field);
  }

  // An engine without a phase split has no phase_ms dataset at all.
  void write_phases(hid_t run, const std::string& where, const std::vector<hsize_t>& per_step,
                    const RunRecord& record) const {
    if (record.phase_names.empty()) {
      if (!record.phase_ms.empty()) fail(where + "/phase_ms: values without phase_names");
      return;
    }
    const std::vector<hsize_t> shape{per_step[0], per_step[1], record.phase_names.size()};
    const H5Handle phases = numeric_dataset(run, where, "phase_ms", shape, record.phase_ms, phase_units);
    string_array_attribute(phases.get(), where + "/phase_ms", "phase_names", record.phase_names);
  }

  void write_accuracy(hid_t run, const std::string& where,
                      const std::vector<AccuracySample>& accuracy) const {
    const H5Handle in_file = accuracy_type(false);
    const H5Handle in_memory = accuracy_type(true);
    const H5Handle created =
        dataset(run, where, "accuracy", in_file.get(), in_memory.get(), {accuracy.size()}, accuracy.data());
    std::vector<std::string> units;
    for (const AccuracyField& field : accuracy_fields) units.push_back(field.units);
    string_array_attribute(created.get(), where + "/accuracy", "units", units);
  }

  std::string path_;
};

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

void write_results_h5(const ResultSet& results, const std::string& path, bool overwrite) {
  std::error_code ignored;
  if (!overwrite && std::filesystem::exists(path, ignored)) {
    throw InputError(path + ": exists; pass --force to overwrite");
  }
  const SilentHdf5Errors quiet;
  write_atomically(path, [&](const std::string& temporary) { ResultsWriter(path).write(results, temporary); });
}

ResultSet read_results_h5(const std::string& path) {
  const SilentHdf5Errors quiet;
  return ResultsReader(path).read();
}

}  // namespace fxbench
