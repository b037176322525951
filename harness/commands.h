// The subcommands of fx2d-bench, one file each; main.cpp registers them and is the only place
// that catches what they throw (errors.h says what maps to which exit code).
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace fxbench {

// `fx2d-bench run` (run.cpp). `command_line` is recorded in result files' provenance.
void register_run(CLI::App& app, const std::string& command_line);
// `fx2d-bench engines` (engines_command.cpp).
void register_engines(CLI::App& app);
// `fx2d-bench compare` (compare.cpp); its verdict, exit_ok/exit_regression/exit_inconclusive, lands in exit_status.
void register_compare(CLI::App& app, int& exit_status);

// `fx2d-bench sweep` (sweep.cpp): speed against accuracy over solver settings, Pareto fronts.
void register_sweep(CLI::App& app, const std::string& command_line);
// `fx2d-bench stability` (stability.cpp): where each engine's solver breaks, by bracketing search.
void register_stability(CLI::App& app, const std::string& command_line);
// `fx2d-bench report` (report.cpp): an HTML page of charts from any of the files above.
void register_report(CLI::App& app);

}  // namespace fxbench
