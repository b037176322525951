// A compare report (analysis/compare.h) as text: the terminal table, Markdown for a pull-request
// comment, and the JSON object of schema fx2d-bench.compare/1 that `gate` and `report` read.
// JSON layout: harness/README.md, compare.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "analysis/compare.h"
#include "common/errors.h"

namespace fxbench {

nlohmann::ordered_json compare_json(const CompareReport& report);
std::string compare_markdown(const CompareReport& report);
std::string compare_table(const CompareReport& report);

// How a command that ends in a verdict (`compare`, `ab`) prints it: the terminal table unless
// one of these is set (the commands let at most one be).
struct CompareOutput {
  bool json = false;
  bool markdown = false;
};

// The report's warnings on stderr, the report on stdout in the chosen format; returns the
// report's exit code, which is the command's.
ExitCode print_compare_report(const CompareReport& report, const CompareOutput& output);

}  // namespace fxbench
