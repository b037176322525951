// Collects provenance. The git revision is the one built, read on every build into a generated
// header; the other build facts come from compile definitions set by harness/CMakeLists.txt at
// configure time; machine facts from /proc/cpuinfo and uname.
#include "measure/provenance.h"

#include <sys/utsname.h>

#include <ctime>
#include <fstream>

#include "fx2d/Version.h"
#include "fx2d_bench_git_revision.h"  // generated in the build tree (harness/git_revision.cmake)
#include "measure/clocks.h"
#include "measure/core_latency.h"

#ifndef FX2D_BENCH_BUILD_TYPE
#error "harness/CMakeLists.txt defines the FX2D_BENCH_* build facts"
#endif

namespace fxbench {
namespace {

std::string cpu_model() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line)) {
    if (!line.starts_with("model name")) continue;
    const auto colon = line.find(':');
    if (colon != std::string::npos) return line.substr(line.find_first_not_of(' ', colon + 1));
  }
  return "unknown";
}

std::string utc_now_iso8601() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

}  // namespace

Provenance collect_provenance(const std::string& command_line, double counter_ghz) {
  Provenance provenance;
  provenance.fx2d_version = std::string(fx2d::fx_version());
  provenance.fx2d_git_revision = FX2D_BENCH_GIT_REVISION;
  provenance.build_type = FX2D_BENCH_BUILD_TYPE;
  provenance.build_flags = FX2D_BENCH_BUILD_FLAGS;
  provenance.compiler = FX2D_BENCH_COMPILER;
  provenance.cpu_model = cpu_model();
  utsname system{};
  if (uname(&system) == 0) {
    provenance.kernel = std::string(system.sysname) + " " + system.release;
    provenance.hostname = system.nodename;
  }
  provenance.date_utc = utc_now_iso8601();
  provenance.command_line = command_line;
  provenance.counter_kind = counter_kind();
  provenance.tsc_ghz = counter_ghz;
  provenance.core_round_trip_ns_start = measure_core_round_trip_ns();
  return provenance;
}

void finish_provenance(Provenance& provenance) {
  provenance.core_round_trip_ns_end = measure_core_round_trip_ns();
}

std::string build_description() {
  return "fx2d " + std::string(fx2d::fx_version()) + ", git " + FX2D_BENCH_GIT_REVISION + ", " + FX2D_BENCH_BUILD_TYPE +
         ", " + FX2D_BENCH_COMPILER;
}

std::string join_command_line(int argc, const char* const* argv) {
  std::string line;
  for (int i = 0; i < argc; ++i) {
    const std::string argument = argv[i];
    if (i > 0) line += ' ';
    if (argument.find_first_of(" \t'\"") == std::string::npos) {
      line += argument;
      continue;
    }
    line += '\'';
    for (const char c : argument) line += c == '\'' ? std::string("'\\''") : std::string(1, c);
    line += '\'';
  }
  return line;
}

}  // namespace fxbench
