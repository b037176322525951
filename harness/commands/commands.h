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
// `fx2d-bench count-instructions` (count_instructions.cpp), hidden: the child that `run --counter
// instructions` starts under callgrind.
void register_count_instructions(CLI::App& app);
// `fx2d-bench ab` (ab.cpp): two builds of Fx2D timed in alternating rounds in one process, with
// compare's verdict, which lands in exit_status as for compare.
void register_ab(CLI::App& app, const std::string& command_line, int& exit_status);
// `fx2d-bench gate` (gate.cpp): a comparison judged by the committed gating policy (ci/gating.json);
// its verdict, like compare's, lands in exit_status.
void register_gate(CLI::App& app, int& exit_status);
// `fx2d-bench history` (history.cpp): append a night to the nightly history file, or show it.
void register_history(CLI::App& app);
// `fx2d-bench merge` (merge.cpp): one sweep or stability file from the files of its shards.
void register_merge(CLI::App& app);

}  // namespace fxbench
