// Where and how a run's numbers were taken: the build (its git revision read on every build, the
// rest recorded by CMake at configure time), the machine and the moment, for the provenance
// attributes of a result file.
#pragma once

#include <string>

#include "common/results.h"

namespace fxbench {

// Fills every Provenance field. `command_line` is stored as given; `counter_ghz` is the measured
// rate of the step counter (clocks.h).
Provenance collect_provenance(const std::string& command_line, double counter_ghz);

// Records what the machine was like as the measurement ended: the cross-core round trip.
void finish_provenance(Provenance& provenance);

// One line naming the build: Fx2D's version, git revision, build type and compiler.
std::string build_description();

// argv joined by spaces, an argument holding a space or quote wrapped in single quotes, so the
// line can be pasted back into a shell.
std::string join_command_line(int argc, const char* const* argv);

}  // namespace fxbench
