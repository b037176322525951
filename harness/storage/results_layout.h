// What a result file holds and how HDF5 sees it: every attribute and dataset is named once, in
// the tables below, which both the writer and the reader walk, so the two cannot disagree.
// Layout: harness/RESULTS_FORMAT.md. Private to storage/.
#pragma once

#include <hdf5.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "common/results.h"
#include "storage/h5_types.h"

namespace fxbench::results_layout {

static_assert(std::is_same_v<int, std::int32_t>, "the records' int fields are stored as int32");

template <class Record, class Field>
struct Member {
  const char* name;
  Field Record::*field;
};

inline constexpr Member<Provenance, std::string> provenance_strings[] = {
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
inline constexpr Member<Provenance, double> provenance_numbers[] = {{"tsc_ghz", &Provenance::tsc_ghz}};
// Written always; read as 0 when absent, so that files written before them still read.
inline constexpr Member<Provenance, double> optional_provenance_numbers[] = {
    {"core_round_trip_ns_start", &Provenance::core_round_trip_ns_start},
    {"core_round_trip_ns_end", &Provenance::core_round_trip_ns_end},
};
inline constexpr const char* partial_attribute = "partial";

inline constexpr Member<SceneRecord, std::string> scene_strings[] = {
    {"name", &SceneRecord::name},
    {"hash", &SceneRecord::hash},
    {"source_path", &SceneRecord::source_path},
    {"primary_metric", &SceneRecord::primary_metric},
};

inline constexpr Member<RunRecord, std::string> run_strings[] = {
    {"engine", &RunRecord::engine},
    {"engine_version", &RunRecord::engine_version},
    {"engine_settings", &RunRecord::engine_settings},
    {"scene", &RunRecord::scene},
    {"scene_hash", &RunRecord::scene_hash},
    {"final_state_hash", &RunRecord::final_state_hash},
};
inline constexpr Member<RunRecord, int> run_integers[] = {
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
inline constexpr TimedSeries run_times[] = {{"wall_ms", &RunRecord::wall_ms, "ms"},
                                            {"cpu_ms", &RunRecord::cpu_ms, "ms"}};
inline constexpr const char* cycles_units = "cycles";

// A run counted with --counter instructions has one scalar dataset more, with its provenance.
inline constexpr const char* instructions_dataset = "instructions";
inline constexpr const char* instructions_units = "instructions";
inline constexpr const char* instructions_steps_attribute = "steps";
inline constexpr Member<InstructionCount, std::string> instruction_count_strings[] = {
    {"tool", &InstructionCount::tool},
    {"tool_version", &InstructionCount::tool_version},
};
inline constexpr const char* contacts_units = "manifolds";
inline constexpr const char* phase_units = "ms";

struct AccuracyField {
  const char* name;
  std::size_t offset;
  bool is_integer;
  const char* units;
};
inline const AccuracyField accuracy_fields[] = {
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
H5Handle accuracy_type(bool in_memory);

H5Handle utf8_string_type();

// An empty shape is a scalar.
H5Handle space_of(const std::vector<hsize_t>& shape);

std::size_t element_count(const std::vector<hsize_t>& shape);

std::string shape_text(const std::vector<hsize_t>& shape);

std::vector<const char*> c_strings(const std::vector<std::string>& strings);

}  // namespace fxbench::results_layout
