// A ResultSet on disk: one HDF5 file per `fx2d-bench run`, layout in harness/RESULTS_FORMAT.md.
//
// Invariants: a result file is either complete or absent (it is written beside its final name
// and renamed into place); read(write(x)) == x field by field; a file the reader cannot take
// produces one InputError line naming the file and what was expected, never HDF5's own error
// stack on stderr.
#pragma once

#include <string>

#include "common/results.h"

namespace fxbench {

// The layout this code writes and reads, stored in the root attribute `schema`.
inline constexpr const char* results_schema = "fx2d-bench.results/1";

// Writes `results` to `path`. The root `schema` attribute is always results_schema, whatever
// results.provenance.schema holds. Throws InputError if `path` exists and `overwrite` is false,
// or if the file cannot be created or renamed into place; std::runtime_error if a run's sample
// arrays do not match its repeats x steps (x phases) or HDF5 fails mid-write. On any failure
// no file is left behind and an existing `path` is untouched.
void write_results_h5(const ResultSet& results, const std::string& path, bool overwrite);

// Reads a file written by write_results_h5. Throws InputError.
ResultSet read_results_h5(const std::string& path);

// The root attribute `schema` of any HDF5 file the harness writes (result or history file), or ""
// when it has none that is a string: what lets a reader choose how to read a file. Throws
// InputError when the file is not HDF5 or cannot be opened.
std::string h5_root_schema(const std::string& path);

}  // namespace fxbench
