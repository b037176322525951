// The nightly history (common/history_row.h) as text: a terminal table, oldest night first, or one
// JSON object (schema fx2d-bench.history/1), for `fx2d-bench history show`.
#pragma once

#include <nlohmann/json.hpp>
#include <span>
#include <string>

#include "common/history_row.h"

namespace fxbench {

std::string history_table(std::span<const HistoryRow> rows);

nlohmann::ordered_json history_json(std::span<const HistoryRow> rows);

}  // namespace fxbench
