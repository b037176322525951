// Writing a ResultSet to an HDF5 result file (results_h5.h), through the HDF5 C API: each
// record walked through the tables of results_layout.h, every HDF5 identifier owned by an
// H5Handle and closed on every path, the file written beside its final name and renamed in place.
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
    for (const auto& member : optional_provenance_numbers)
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

}  // namespace

void write_results_h5(const ResultSet& results, const std::string& path, bool overwrite) {
  std::error_code ignored;
  if (!overwrite && std::filesystem::exists(path, ignored)) {
    throw InputError(path + ": exists; pass --force to overwrite");
  }
  const SilentHdf5Errors quiet;
  write_atomically(path, [&](const std::string& temporary) { ResultsWriter(path).write(results, temporary); });
}

}  // namespace fxbench
