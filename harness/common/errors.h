// Errors the harness reports to a user. Each is printed as one line at the CLI boundary and
// mapped to an exit code there; nothing below main() prints or exits.
#pragma once

#include <stdexcept>
#include <string>

namespace fxbench {

// Exit codes, stable for scripts and CI.
enum ExitCode : int {
  exit_ok = 0,
  exit_regression = 1,   // compare: a regression beyond tolerance
  exit_bad_input = 2,    // bad file, bad option, bad scene
  exit_inconclusive = 3, // compare: too noisy to decide
  exit_internal = 4,     // a bug in fx2d-bench or an engine failure
};

// Bad input from the user: a scene file, a result file, an option. The message is complete and
// fit to print as is, e.g. "scenes/pile.json:12:7: /generators/0/count: expected an integer >= 0, got "a"".
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace fxbench
