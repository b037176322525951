// A sweep's points and fronts (analysis/sweep_grid.h) as text and a table: a terminal table with
// where each default stands on its front, one JSON object (schema fx2d-bench.sweep/1), and the
// /sweep table of a result file (harness/RESULTS_FORMAT.md).
#pragma once

#include <nlohmann/json.hpp>
#include <span>
#include <string>

#include "analysis/sweep_grid.h"
#include "common/column_tables.h"

namespace fxbench {

inline constexpr const char* sweep_schema = "fx2d-bench.sweep/1";

std::string sweep_table(const Sweep& sweep);

nlohmann::ordered_json sweep_json(const Sweep& sweep);

// One row per point, with a column per knob axis (-1 where the point's engine has no such knob).
H5Table sweep_table_h5(const Sweep& sweep, std::span<const KnobAxis> axes, int repeats);

}  // namespace fxbench
