// fx2d-bench: the command-line entry point. Registers the subcommands and is the one place that
// turns what they throw into a message and an exit code: bad input (InputError, a CLI11 parse
// error) prints one line and exits 2; anything else is a bug or an engine failure, one line and
// exit 4. Never a stack trace, never more than one line.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <string>

#include "commands/commands.h"
#include "common/errors.h"
#include "measure/provenance.h"

namespace {

int fail(const std::string& message, fxbench::ExitCode code) {
  // One line, whatever the message holds (a file name, a system error, a command-line argument): a
  // line break becomes a space, any other control character, which a terminal would act on, a '?'.
  std::string line = message;
  for (char& c : line) {
    if (c == '\n' || c == '\r' || c == '\t')
      c = ' ';
    else if (static_cast<unsigned char>(c) < 0x20 || c == '\x7f')
      c = '?';
  }
  std::fprintf(stderr, "fx2d-bench: %s\n", line.c_str());
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Times 2D physics engines (Fx2D, Box2D, ODE, Chipmunk2D, plugins) on the same scenes and measures their accuracy", "fx2d-bench"};
  app.set_version_flag("--version", [] { return "fx2d-bench (" + fxbench::build_description() + ")"; });
  app.require_subcommand(1);
  fxbench::register_run(app, fxbench::join_command_line(argc, argv));
  fxbench::register_engines(app);
  int status = fxbench::exit_ok;  // a subcommand with a verdict (compare) sets it
  fxbench::register_compare(app, status);
  fxbench::register_sweep(app, fxbench::join_command_line(argc, argv));
  fxbench::register_stability(app, fxbench::join_command_line(argc, argv));
  fxbench::register_report(app);
  fxbench::register_count_instructions(app);
  fxbench::register_ab(app, fxbench::join_command_line(argc, argv), status);
  fxbench::register_gate(app, status);
  fxbench::register_history(app);
  fxbench::register_merge(app);
  try {
    app.parse(argc, argv);
    return status;
  } catch (const CLI::ParseError& error) {
    if (error.get_exit_code() == 0) return app.exit(error);  // --help, --version
    return fail(error.what(), fxbench::exit_bad_input);
  } catch (const fxbench::InputError& error) {
    return fail(error.what(), fxbench::exit_bad_input);
  } catch (const std::exception& error) {
    return fail(error.what(), fxbench::exit_internal);
  } catch (...) {
    return fail("unknown internal error", fxbench::exit_internal);
  }
}
