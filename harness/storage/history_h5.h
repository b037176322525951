// The nightly history file: one row per gating metric per night (layout in
// harness/RESULTS_FORMAT.md, "The nightly history file"): a root attribute `schema` =
// fx2d-bench.history/1 and a /history group of equal-length column datasets, sealed in its user
// block like a result file (file_integrity.h).
//
// Invariant: the file at `path` is always a complete history, the old one or the new one. An
// append never opens the existing file for writing: it reads it, writes the old rows and the new
// ones to `path.tmp.<pid>` beside it, seals it (so the seal covers the bytes that are renamed),
// fsyncs it, renames it over `path` (atomic within one file system) and fsyncs the directory, so the rename itself survives a power cut. A process
// killed at any moment leaves at most its own `.tmp.<pid>`, which later appends ignore.
#pragma once

#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "common/history_row.h"

namespace fxbench {

// Every row, oldest first. A sealed file is verified against its seal before libhdf5 opens it; an
// unsealed one (written before history files were sealed) is still read. Throws InputError (one
// line) for a missing, non-HDF5, truncated, corrupt or foreign file, or a /history whose columns
// are missing, mistyped or of different lengths.
std::vector<HistoryRow> read_history_h5(const std::string& path);

// The moments of an append, in order, for a caller that watches it (interruption, tests):
// "read" (the old file is read; nothing written yet), "written" (the temporary file is complete
// and sealed), "synced" (it is on disk; next comes the rename), "renamed" (the new history is in
// place). The hook may throw to stop the append; before "renamed" the temporary file is then
// removed and `path` is untouched.
using AppendStageHook = std::function<void(std::string_view stage)>;

// Appends `rows` to the history at `path`, creating it when absent. Throws InputError when the
// existing file is not a history, std::runtime_error when writing fails; either way `path` is as
// it was.
void append_history_h5(const std::string& path, std::span<const HistoryRow> rows, const AppendStageHook& at_stage = {});

}  // namespace fxbench
