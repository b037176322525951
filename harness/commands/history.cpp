// `fx2d-bench history append HISTORY.h5 --compare C.json... --candidate REV --baseline REV
// [--policy P] [--accepted]` adds one night to the nightly history: every gating row of the
// comparison as the gate judges it (gate_policy.h), with the date, both revisions, whether the gate
// detected a change and whether the candidate was accepted as the new baseline.
// `fx2d-bench history show HISTORY.h5 [--last N] [--json]` prints it.
//
// Reads top to bottom: the options, turning a judgement into rows, the append (crash-safe by
// history_h5.h; a SIGINT before the new file is in place leaves the old one and exits 130), then
// the show (its renderers are format/history_format.h) and the command line.
#include <signal.h>

#include <chrono>
#include <cstdlib>
#include <ctime>
#include <iostream>
#include <limits>
#include <memory>
#include <regex>

#include "analysis/gate_policy.h"
#include "commands/commands.h"
#include "common/errors.h"
#include "format/history_format.h"
#include "measure/interrupt.h"
#include "storage/history_h5.h"

namespace fxbench {
namespace {

// Test hook: the append stops itself (SIGSTOP) at the named stage of history_h5.h ("read",
// "written", "synced", "renamed"), so a test can kill or interrupt it at exactly that moment.
constexpr const char* stop_at_variable = "FX2D_HISTORY_TEST_STOP_AT";

struct AppendOptions {
  std::string history;
  std::vector<std::string> compare;
  std::string policy;
  std::string candidate;
  std::string baseline;
  std::string date;
  bool accepted = false;
};

struct ShowOptions {
  std::string history;
  int last = 0;
  bool json = false;
};

struct Interrupted {};

std::string utc_now() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm parts{};
  gmtime_r(&now, &parts);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &parts);
  return text;
}

// --date: a calendar date, or a UTC time on it, as ISO 8601 writes them (2026-11-25,
// 2026-11-25T02:17:00Z). Both sort as text in time order, which the history's nights rely on, and
// each field is checked, so that no impossible date (month 13, 30 February) enters the history.
CLI::Validator iso8601_utc_date() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        static const std::regex shape(R"((\d{4})-(\d{2})-(\d{2})(T(\d{2}):(\d{2}):(\d{2})Z)?)");
        std::smatch parts;
        const auto field = [&parts](int index) { return std::stoi(parts[index].str()); };
        const bool valid =
            std::regex_match(text, parts, shape) &&
            std::chrono::year_month_day(std::chrono::year(field(1)), std::chrono::month(static_cast<unsigned>(field(2))),
                                        std::chrono::day(static_cast<unsigned>(field(3))))
                .ok() &&
            (!parts[4].matched || (field(5) < 24 && field(6) < 60 && field(7) < 60));
        if (valid) return {};
        return "expected an ISO 8601 UTC date, YYYY-MM-DD or YYYY-MM-DDTHH:MM:SSZ, got '" + text + "'";
      },
      "ISO8601");
}

// --- one night's rows -----------------------------------------------------------------------------

std::vector<HistoryRow> night_rows(const GateReport& report, const AppendOptions& options) {
  const std::string date = options.date.empty() ? utc_now() : options.date;
  std::vector<HistoryRow> rows;
  for (const GateRow& row : report.rows) {
    rows.push_back({date, options.candidate, options.baseline, row.engine, row.scene, row.bodies, row.metric, row.a,
                    row.b, row.ratio, row.ci_low, row.ci_high,
                    row.p_value.value_or(std::numeric_limits<double>::quiet_NaN()), row.verdict, row.step_detected,
                    options.accepted});
  }
  return rows;
}

// --- append ---------------------------------------------------------------------------------------

void watch_stage(std::string_view stage) {
  const char* stop_at = std::getenv(stop_at_variable);
  if (stop_at != nullptr && stage == stop_at) raise(SIGSTOP);
  // Once the new file is in place the append is done; before, stopping costs nothing.
  if (interrupt_requested() && stage != "renamed") throw Interrupted{};
}

void append_command(const AppendOptions& options) {
  const Policy policy = options.policy.empty() ? Policy{} : read_policy(options.policy);
  const std::vector<HistoryRow> rows = night_rows(judge_files(options.compare, policy), options);
  const ScopedInterruptHandler interrupts;
  try {
    append_history_h5(options.history, rows, watch_stage);
  } catch (const Interrupted&) {
    exit_after_interrupt("interrupted; " + options.history + " is unchanged");
  }
  std::cout << options.history << ": " << rows.size() << " rows appended (" << options.candidate << " against "
            << options.baseline << (options.accepted ? ", accepted as the new baseline" : "") << ")\n";
}

// --- show -----------------------------------------------------------------------------------------

// The last `nights` distinct dates, or every row.
std::span<const HistoryRow> last_nights(const std::vector<HistoryRow>& rows, int nights) {
  std::size_t first = rows.size();
  for (int seen = 0; first > 0 && (nights <= 0 || seen < nights);) {
    --first;
    if (first == 0 || rows[first - 1].date_utc != rows[first].date_utc) ++seen;
  }
  return std::span(rows).subspan(first);
}

void show_command(const ShowOptions& options) {
  const std::vector<HistoryRow> rows = read_history_h5(options.history);
  const std::span<const HistoryRow> shown = last_nights(rows, options.last);
  if (options.json)
    std::cout << history_json(shown).dump(2) << "\n";
  else
    std::cout << history_table(shown);
}

}  // namespace

void register_history(CLI::App& app) {
  CLI::App* history = app.add_subcommand("history", "The nightly history file: append a night, show the trend");
  history->require_subcommand(1);

  auto append = std::make_shared<AppendOptions>();
  CLI::App* add = history->add_subcommand("append", "Append one night's gated comparison (crash-safe)");
  add->add_option("HISTORY", append->history, "History file (fx2d-bench.history/1); created when absent")->required();
  add->add_option("--compare", append->compare, "JSON of `fx2d-bench compare --json` for this night (repeatable, or several)")
      ->required();
  add->add_option("--candidate", append->candidate, "Revision judged (B)")->required();
  add->add_option("--baseline", append->baseline, "Accepted baseline revision (A)")->required();
  add->add_option("--policy", append->policy, "Gating policy the night was judged by (default: built-in thresholds)");
  add->add_option("--date", append->date, "Date of the night, ISO 8601 UTC (default: now)")->check(iso8601_utc_date());
  add->add_flag("--accepted", append->accepted, "The candidate became the new baseline this night");
  add->callback([append] { append_command(*append); });

  auto show = std::make_shared<ShowOptions>();
  CLI::App* print = history->add_subcommand("show", "Print the history, oldest night first");
  print->add_option("HISTORY", show->history, "History file (fx2d-bench.history/1)")->required();
  print->add_option("--last", show->last, "Only the last N nights")->check(CLI::PositiveNumber);
  print->add_flag("--json", show->json, "Print one JSON object (fx2d-bench.history/1 rows)");
  print->callback([show] { show_command(*show); });
}

}  // namespace fxbench
