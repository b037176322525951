// What one `fx2d-bench run` measured, in memory: the form the HDF5 writer stores, the reader
// returns, and the summary and compare read. Layout on disk: harness/RESULTS_FORMAT.md.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace fxbench {

// Accuracy figures computed by the harness from poses and shapes alone (accuracy.h).
struct AccuracySample {
  int step = 0;                    // step index after which the sample was taken (1-based)
  double max_penetration = 0;      // metres, deepest overlap between any two shapes
  double mean_penetration = 0;     // metres, mean over overlapping pairs (0 when none)
  double max_displacement = 0;     // metres, largest distance of a dynamic body from its start
  double max_lateral_drift = 0;    // metres, largest |x - x0| of a dynamic body
  double kinetic_energy = 0;       // joules, translational + rotational, dynamic bodies
  int escaped = 0;                 // dynamic bodies outside the scene bounds
  int nan = 0;                     // bodies with a non-finite pose or velocity

  // Field by field, exact: what a round trip through a result file must preserve.
  friend bool operator==(const AccuracySample&, const AccuracySample&) = default;
};

// The instructions one step loop executed, counted under valgrind (instruction_counter.h): exact
// and the same on every run of one binary on one scene, so compared without statistics.
struct InstructionCount {
  std::uint64_t instructions = 0;  // executed by the whole loop, callgrind's Ir
  int steps = 0;                   // steps the loop took, from a freshly built instance (building not counted)
  std::string tool;                // how they were counted: "callgrind"
  std::string tool_version;        // e.g. "valgrind-3.19.0"

  double per_step() const { return steps > 0 ? static_cast<double>(instructions) / steps : 0.0; }

  friend bool operator==(const InstructionCount&, const InstructionCount&) = default;
};

// One engine on one scene: `repeats` timed repeats of `steps` steps each.
struct RunRecord {
  std::string engine;
  std::string engine_version;
  std::string engine_settings;     // e.g. "substeps=14 velocity_passes=4 sleeping=1"
  std::string scene;               // scene name
  std::string scene_hash;
  int bodies = 0;                  // the scene's size parameter N
  int body_count = 0;              // bodies actually built, static ones included
  int steps = 0;
  int repeats = 0;
  int warmup_steps = 0;

  // Per-step samples, repeat-major: index = repeat * steps + step.
  std::vector<double> wall_ms;
  std::vector<double> cpu_ms;      // thread CPU time
  std::vector<std::uint64_t> cycles;  // reference cycles from the time-stamp counter
  std::vector<std::int32_t> contacts;
  std::vector<std::string> phase_names;  // the engine's own phase split (may be empty)
  std::vector<double> phase_ms;    // repeat-major, then step, then phase: index = (r * steps + s) * P + p

  // Accuracy, from the first repeat (every repeat is the same deterministic trajectory).
  std::vector<AccuracySample> accuracy;
  std::vector<std::string> state_hashes;  // poses hashed every `hash_every` steps, then at the end
  int hash_every = 0;
  std::string final_state_hash;
  bool deterministic = true;       // every repeat ended with the same final state hash

  // Only when `run --counter instructions` asked for it.
  std::optional<InstructionCount> instruction_count;

  friend bool operator==(const RunRecord&, const RunRecord&) = default;
};

// Where and how the numbers were taken.
struct Provenance {
  std::string schema = "fx2d-bench.results/1";
  std::string fx2d_version;
  std::string fx2d_git_revision;
  std::string build_type;
  std::string build_flags;
  std::string compiler;
  std::string cpu_model;
  std::string kernel;
  std::string hostname;
  std::string date_utc;            // ISO 8601
  std::string command_line;
  std::string counter_kind = "tsc-reference-cycles";
  double tsc_ghz = 0;              // measured reference-cycle rate
  // The cross-core round trip (measure/core_latency.h) as the measurement began and as it ended,
  // ns; 0 when not measured (one hardware thread, or a file written before it was recorded).
  double core_round_trip_ns_start = 0;
  double core_round_trip_ns_end = 0;

  friend bool operator==(const Provenance&, const Provenance&) = default;
};

struct SceneRecord {
  std::string name;
  std::string hash;
  std::string resolved_json;
  std::string source_path;
  std::string primary_metric;      // "penetration" or "displacement"

  friend bool operator==(const SceneRecord&, const SceneRecord&) = default;
};

struct ResultSet {
  Provenance provenance;
  std::vector<SceneRecord> scenes;
  std::vector<RunRecord> runs;
  bool partial = false;            // a SIGINT stopped the run: some runs or repeats are missing

  friend bool operator==(const ResultSet&, const ResultSet&) = default;
};

}  // namespace fxbench
