// Tables of named columns appended to a result file: how `fx2d-bench sweep` and `stability` store
// their own groups (/sweep, /stability) beside the provenance, /scenes and /runs of an
// fx2d-bench.results/1 file, so that one reader serves every file the harness writes.
//
// Invariants: the file is complete or absent, as write_results_h5 promises (everything is
// written beside the final name and renamed into place); every column of a table has the same
// length, one row per entry; numbers are stored little-endian with a `units` attribute, strings
// as variable-length UTF-8, exactly as harness/RESULTS_FORMAT.md describes for run files.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "common/column_tables.h"
#include "common/results.h"

namespace fxbench {

// Writes `results` as write_results_h5 does, then every table in order. Throws InputError if
// `path` exists and `overwrite` is false, std::runtime_error if the columns of a table differ in
// length or HDF5 fails; on failure nothing is left behind and an existing `path` is untouched.
void write_results_with_tables_h5(const ResultSet& results, std::span<const H5Table> tables, const std::string& path,
                                  bool overwrite);

// A file of tables alone (the nightly history, history_h5.h): created or truncated at `path`,
// string attributes on its root, then every table in order, then sealed (file_integrity.h) as a
// result file is. Not renamed into place: the caller writes a temporary name and makes the
// replacement atomic. Throws std::runtime_error.
void write_table_file_h5(const std::string& path, std::span<const std::pair<std::string, std::string>> root_attributes,
                         std::span<const H5Table> tables);

// The table at `group_path` (e.g. "/sweep") of a result file written by
// write_results_with_tables_h5: its attributes and its columns, in the order of their names (the
// order HDF5 lists them in); groups inside it are tables of their own and are left out. Throws
// InputError (one line naming the file and the table) when the file, the group or a column
// cannot be read as written.
H5Table read_table_h5(const std::string& path, const std::string& group_path);

// Whether the file at `path` holds a group `group_path`. Throws InputError when it cannot be opened.
bool has_table_h5(const std::string& path, const std::string& group_path);

}  // namespace fxbench
