// Tests of `fx2d-bench report`: the refusals it makes before anything is drawn, and a report of a
// small real run, sweep and comparison opened in headless Chromium, which must load every chart
// and show every section. Each test process renders its own copy in a scratch directory (ctest runs
// the tests as separate, possibly parallel, processes); the screenshot test alone writes the
// artefacts, that report and Chromium's screenshot of it, to <build>/harness/tests/report_test_artefacts/,
// and prints the screenshot's path.
//
// The Chromium tests skip, saying so, only when /usr/bin/chromium is not installed (Debian's
// `chromium` package; ci/install-deps installs it).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "storage/file_integrity.h"
#include "storage/results_h5.h"

namespace {

namespace fs = std::filesystem;

constexpr const char* chromium = "/usr/bin/chromium";

struct Outcome {
  int exit_code = -1;
  std::string out;
  std::string err;
};

std::string read_text(const fs::path& path) {
  std::ifstream stream(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(stream), {}};
}

// Runs a shell command line; stderr goes through a file so that stdout and stderr stay apart.
Outcome shell(const std::string& command, const fs::path& scratch) {
  const fs::path err = scratch / "stderr.txt";
  Outcome outcome;
  FILE* pipe = popen((command + " 2>" + err.string()).c_str(), "r");
  if (pipe == nullptr) return outcome;
  char buffer[4096];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) outcome.out.append(buffer, n);
  const int status = pclose(pipe);
  outcome.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  outcome.err = read_text(err);
  return outcome;
}

std::string bench(const std::string& arguments) { return std::string(FX2D_BENCH_EXE) + " " + arguments; }

// Chromium headless with nothing that reaches the network or a shared profile.
std::string chromium_command(const fs::path& profile, const std::string& action, const fs::path& page) {
  return std::string(chromium) +
         " --headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking"
         " --disable-component-update --disable-sync --user-data-dir=" +
         profile.string() + " --window-size=1280,2000 --virtual-time-budget=5000 " + action + " file://" +
         page.string();
}

// The `src` of every <img> of a page, in order.
std::vector<std::string> image_sources(const std::string& html) {
  const std::regex img(R"(<img[^>]*\ssrc="([^"]+)\")");
  std::vector<std::string> sources;
  for (auto it = std::sregex_iterator(html.begin(), html.end(), img); it != std::sregex_iterator(); ++it)
    sources.push_back((*it)[1]);
  return sources;
}

std::string body_data(const std::string& dom, const std::string& name) {
  const std::regex attribute("<body[^>]*\\sdata-" + name + "=\"([^\"]*)\"");
  std::smatch match;
  return std::regex_search(dom, match, attribute) ? match[1].str() : std::string("(absent)");
}

// Exit code 2 and exactly one line on stderr, prefixed with the program's name.
void expect_one_line_input_error(const Outcome& outcome, const std::string& mentions) {
  EXPECT_EQ(outcome.exit_code, 2);
  EXPECT_TRUE(outcome.err.starts_with("fx2d-bench: ")) << outcome.err;
  EXPECT_EQ(std::count(outcome.err.begin(), outcome.err.end(), '\n'), 1) << outcome.err;
  EXPECT_NE(outcome.err.find(mentions), std::string::npos) << outcome.err;
}

// One small run of every engine, a small sweep and the compare golden, rendered once for all tests.
class ReportOfSmallRun : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    fs::create_directories(scratch());
    const fs::path run = scratch() / "run.h5";
    const fs::path sweep = scratch() / "sweep.h5";
    setup_ = shell(bench("run pile --bodies 36 --steps 30 --repeats 2 --out " + run.string()), scratch());
    if (setup_.exit_code != 0) return;
    setup_ = shell(bench("sweep pile --bodies 36 --steps 30 --repeats 1 --fx2d-substeps 2,14 --fx2d-passes 1,4"
                         " --box2d-velocity 2,8 --box2d-position 3 --ode-iterations 5,20 --out " +
                         sweep.string()),
                   scratch());
    if (setup_.exit_code != 0) return;
    report_ = shell(bench("report " + run.string() + " " + sweep.string() + " --compare-json " + compare_golden() +
                          " -o " + page_dir().string()),
                    scratch());
  }

  static void TearDownTestSuite() { fs::remove_all(scratch()); }

  void SetUp() override {
    ASSERT_EQ(setup_.exit_code, 0) << "could not make the inputs: " << setup_.err;
    ASSERT_EQ(report_.exit_code, 0) << report_.err;
  }

  static fs::path scratch() { return fs::temp_directory_path() / ("fx2d_report_test_" + std::to_string(getpid())); }
  static fs::path artefacts() { return REPORT_TEST_ARTEFACTS; }
  static fs::path page_dir() { return scratch() / "report"; }
  static fs::path index() { return page_dir() / "index.html"; }
  static std::string compare_golden() { return std::string(FX2D_SOURCE_DIR) + "/goldens/compare_ab.json"; }

  static void skip_without_chromium() {
    if (access(chromium, X_OK) != 0) GTEST_SKIP() << chromium << " is not installed (apt-get install chromium)";
  }

  // The page as Chromium has it after load, when the inline check has run.
  static const std::string& rendered_dom() {
    static const std::string dom = [] {
      return shell(chromium_command(scratch() / "chromium-profile", "--dump-dom", index()), scratch()).out;
    }();
    return dom;
  }

  static Outcome setup_;
  static Outcome report_;
};

Outcome ReportOfSmallRun::setup_;
Outcome ReportOfSmallRun::report_;

TEST_F(ReportOfSmallRun, PrintsThePathOfItsIndexPage) {
  EXPECT_EQ(report_.out, index().string() + "\n");
  EXPECT_TRUE(fs::is_regular_file(index()));
}

// Phase split (the run), speed against accuracy (the sweep's one scene), A/B (the compare golden).
TEST_F(ReportOfSmallRun, DrawsOneChartPerInputKindAsPngAndSvg) {
  const std::vector<std::string> sources = image_sources(read_text(index()));
  const std::set<std::string> expected{"phase_split.png", "speed_accuracy_pile_36.png", "ab_0.png"};
  EXPECT_EQ(std::set<std::string>(sources.begin(), sources.end()), expected);
  for (const std::string& source : sources) {
    EXPECT_EQ(read_text(page_dir() / source).substr(0, 8), "\x89PNG\r\n\x1a\n") << source;
    const fs::path svg = page_dir() / fs::path(source).replace_extension(".svg");
    EXPECT_NE(read_text(svg).find("<svg"), std::string::npos) << svg;
  }
}

// Viewable offline: nothing is fetched from elsewhere, every image is a relative path.
TEST_F(ReportOfSmallRun, PageReferencesNothingOutsideItsDirectory) {
  const std::string html = read_text(index());
  EXPECT_EQ(html.find("src=\"http"), std::string::npos);
  EXPECT_EQ(html.find("href=\"http"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
  EXPECT_EQ(html.find("@import"), std::string::npos);
  for (const std::string& source : image_sources(html)) EXPECT_TRUE(fs::path(source).is_relative()) << source;
}

TEST_F(ReportOfSmallRun, EveryChartLoadsInHeadlessChromium) {
  skip_without_chromium();
  const std::string& dom = rendered_dom();
  ASSERT_FALSE(dom.empty()) << "chromium --dump-dom printed nothing";
  EXPECT_EQ(body_data(dom, "images-total"), "3");
  EXPECT_EQ(body_data(dom, "images-loaded"), "3") << "broken: " << body_data(dom, "images-broken");
}

TEST_F(ReportOfSmallRun, ChromiumShowsEverySectionAndSaysWhatIsMissing) {
  skip_without_chromium();
  const std::string& dom = rendered_dom();
  for (const char* heading : {"Runs", "Phase split", "Speed against accuracy", "Scaling with workers",
                              "A/B comparison", "Stability", "Nightly history", "Provenance"})
    EXPECT_NE(dom.find(std::string("<h2>") + heading + "</h2>"), std::string::npos) << heading;
  EXPECT_NE(dom.find("No sweep over an engine's thread count among the inputs"), std::string::npos);
  EXPECT_NE(dom.find("No stability file among the inputs"), std::string::npos);
  EXPECT_NE(dom.find("No nightly history file among the inputs"), std::string::npos);
  // One summary row per engine of the run: each engine's chip appears in the runs table.
  for (const char* engine : {"fx2d", "box2d", "ode"})
    EXPECT_NE(dom.find(std::string(">") + engine + "</span>"), std::string::npos) << engine;
}

TEST_F(ReportOfSmallRun, ScreenshotIsKeptAsArtefact) {
  skip_without_chromium();
  fs::remove_all(artefacts());
  fs::create_directories(artefacts());
  fs::copy(page_dir(), artefacts() / "report", fs::copy_options::recursive);
  const fs::path screenshot = artefacts() / "screenshot.png";
  shell(chromium_command(scratch() / "chromium-profile", "--screenshot=" + screenshot.string(),
                         artefacts() / "report" / "index.html"),
        scratch());
  const std::string png = read_text(screenshot);
  ASSERT_GE(png.size(), 24u) << screenshot;
  ASSERT_EQ(png.substr(0, 8), "\x89PNG\r\n\x1a\n");
  // IHDR's width, big-endian at byte 16: the window is 1280 pixels wide.
  const auto byte = [&](std::size_t i) { return static_cast<unsigned>(static_cast<unsigned char>(png[i])); };
  EXPECT_EQ((byte(16) << 24) | (byte(17) << 16) | (byte(18) << 8) | byte(19), 1280u);
  std::cout << "report screenshot: " << screenshot.string() << '\n';
}

TEST_F(ReportOfSmallRun, RefusesAnExistingReportWithoutForceAndReplacesItWithForce) {
  const std::string again = "report " + (scratch() / "run.h5").string() + " -o " + page_dir().string();
  expect_one_line_input_error(shell(bench(again), scratch()), "pass --force");
  EXPECT_TRUE(fs::exists(page_dir() / "ab_0.png")) << "a refused report leaves the old one as it was";
  const Outcome forced = shell(bench(again + " --force"), scratch());
  ASSERT_EQ(forced.exit_code, 0) << forced.err;
  EXPECT_EQ(image_sources(read_text(index())), std::vector<std::string>{"phase_split.png"});
  EXPECT_FALSE(fs::exists(page_dir() / "ab_0.png")) << "a replaced report keeps none of the old one's files";
}

// A nightly history of three nights written by `fx2d-bench history append`: fx2d steady, then 10%
// slower (a step the gate detects), then accepted as the new baseline. The report draws its trend.
class ReportOfHistory : public ::testing::Test {
 protected:
  void SetUp() override {
    scratch_ = fs::temp_directory_path() / ("fx2d_report_history_" + std::to_string(getpid()));
    fs::create_directories(scratch_);
    const std::string policy = std::string(FX2D_SOURCE_DIR) + "/ci/gating.json";
    const struct {
      const char* date;
      double ratio;
      const char* extra;
    } nights[] = {{"2026-11-01T02:00:00Z", 1.0, ""}, {"2026-11-02T02:00:00Z", 1.1, ""},
                  {"2026-11-03T02:00:00Z", 1.1, " --accepted"}};
    for (const auto& night : nights) {
      std::ofstream(scratch_ / "compare.json") << compare_json(night.ratio);
      const Outcome appended =
          shell(bench("history append " + history().string() + " --compare " + (scratch_ / "compare.json").string() +
                      " --candidate c --baseline b --policy " + policy + " --date " + night.date + night.extra),
                scratch_);
      ASSERT_EQ(appended.exit_code, 0) << appended.err;
    }
    report_ = shell(bench("report " + history().string() + " -o " + (scratch_ / "report").string()), scratch_);
  }
  void TearDown() override { fs::remove_all(scratch_); }

  // One significant fx2d row at `ratio` and a steady Box2D control.
  static std::string compare_json(double ratio) {
    const auto row = [](const char* engine, double r, double p) {
      return std::string("{\"engine\": \"") + engine + "\", \"scene\": \"pile\", \"bodies\": 600, \"metric\": " +
             "\"ms_per_step\", \"a\": 1.0, \"b\": " + std::to_string(r) + ", \"ratio\": " + std::to_string(r) +
             ", \"ci_low\": " + std::to_string(r - 0.01) + ", \"ci_high\": " + std::to_string(r + 0.01) +
             ", \"p_value\": " + std::to_string(p) + ", \"verdict\": \"\"}";
    };
    return "{\"schema\": \"fx2d-bench.compare/1\", \"mode\": \"ab\", \"rows\": [" + row("fx2d", ratio, 0.001) + ", " +
           row("box2d", 1.0, 0.9) + "]}";
  }

  fs::path history() const { return scratch_ / "history.h5"; }

  fs::path scratch_;
  Outcome report_;
};

TEST_F(ReportOfHistory, HistoryFileProducesTheTrendChartAndTheLastNight) {
  ASSERT_EQ(report_.exit_code, 0) << report_.err;
  const fs::path page = scratch_ / "report" / "index.html";
  const std::vector<std::string> sources = image_sources(read_text(page));
  ASSERT_EQ(sources, std::vector<std::string>{"history_history_h5_ms_per_step.png"});
  EXPECT_EQ(read_text(scratch_ / "report" / sources[0]).substr(0, 8), "\x89PNG\r\n\x1a\n");
  const std::string html = read_text(page);
  EXPECT_EQ(html.find("No nightly history file among the inputs"), std::string::npos);
  EXPECT_NE(html.find("Last night (2026-11-03T02:00:00Z)"), std::string::npos);
  // The second and third nights were 10% slower beyond the band: the gate saw a step each night.
  EXPECT_NE(html.find("<td>step</td><td>yes</td>"), std::string::npos) << "the accepted night's fx2d row";
}

TEST_F(ReportOfHistory, SealedHistoryIsVerifiedAndADamagedOneRefusedBeforeAnythingIsDrawn) {
  ASSERT_TRUE(fxbench::carries_h5_seal(history().string())) << "history append seals the file it writes";
  std::string bytes = read_text(history());
  bytes[(fxbench::h5_seal_bytes + bytes.size()) / 2] ^= 0x20;
  const fs::path damaged = scratch_ / "damaged.h5";
  std::ofstream(damaged, std::ios::binary) << bytes;
  expect_one_line_input_error(shell(bench("report " + damaged.string() + " -o " + (scratch_ / "out").string()), scratch_),
                              damaged.string() + ": corrupt or truncated (checksum mismatch)");
  EXPECT_FALSE(fs::exists(scratch_ / "out"));
}

TEST_F(ReportOfHistory, UnsealedHistoryOfAnOlderBenchIsStillReported) {
  // The HDF5 file proper without its user block, as fx2d-bench wrote history files before sealing them.
  const fs::path old = scratch_ / "old.h5";
  std::ofstream(old, std::ios::binary) << read_text(history()).substr(fxbench::h5_seal_bytes);
  ASSERT_FALSE(fxbench::carries_h5_seal(old.string()));
  const Outcome reported = shell(bench("report " + old.string() + " -o " + (scratch_ / "out").string()), scratch_);
  ASSERT_EQ(reported.exit_code, 0) << reported.err;
  EXPECT_EQ(image_sources(read_text(scratch_ / "out" / "index.html")),
            std::vector<std::string>{"history_old_h5_ms_per_step.png"});
}

class ReportRefusals : public ::testing::Test {
 protected:
  void SetUp() override {
    scratch_ = fs::temp_directory_path() / ("fx2d_report_refusals_" + std::to_string(getpid()));
    fs::create_directories(scratch_);
  }
  void TearDown() override { fs::remove_all(scratch_); }

  fs::path write(const std::string& name, const std::string& text) const {
    std::ofstream(scratch_ / name) << text;
    return scratch_ / name;
  }

  fs::path scratch_;
};

TEST_F(ReportRefusals, FileThatIsNotHdf5IsNamedInOneLine) {
  const fs::path text = write("notes.h5", "not HDF5");
  expect_one_line_input_error(shell(bench("report " + text.string() + " -o " + (scratch_ / "out").string()), scratch_),
                              text.string() + ": not an HDF5 file");
  EXPECT_FALSE(fs::exists(scratch_ / "out"));
}

TEST_F(ReportRefusals, MissingFileIsNamedInOneLine) {
  const fs::path missing = scratch_ / "absent.h5";
  expect_one_line_input_error(shell(bench("report " + missing.string() + " -o " + (scratch_ / "out").string()), scratch_),
                              missing.string() + ": no such file");
}

TEST_F(ReportRefusals, CompareJsonOfAnotherSchemaIsRefused) {
  const fs::path json = write("summary.json", R"({"schema": "fx2d-bench.summary/1", "runs": []})");
  expect_one_line_input_error(
      shell(bench("report --compare-json " + json.string() + " -o " + (scratch_ / "out").string()), scratch_),
      "fx2d-bench.compare/1");
}

TEST_F(ReportRefusals, DirectoryThatIsNotAReportIsNeverReplacedEvenWithForce) {
  fs::create_directories(scratch_ / "mine");
  write("mine/thesis.tex", "precious");
  const std::string golden = std::string(FX2D_SOURCE_DIR) + "/goldens/compare_ab.json";
  expect_one_line_input_error(
      shell(bench("report --compare-json " + golden + " -o " + (scratch_ / "mine").string() + " --force"), scratch_),
      "not a previous report");
  EXPECT_EQ(read_text(scratch_ / "mine" / "thesis.tex"), "precious");
}

// The renderer's own check: a module that cannot be imported is reported with the Debian packages
// that provide it. A stand-in h5py beside a copy of the script shadows the real one.
TEST_F(ReportRefusals, MissingPythonModuleNamesTheDebianPackages) {
  fs::create_directories(scratch_ / "reports");
  fs::copy_file(fs::path(FX2D_SOURCE_DIR) / "reports" / "render_report.py", scratch_ / "reports" / "render_report.py");
  write("reports/h5py.py", "raise ImportError('simulated for report_test', name='h5py')\n");
  const std::string golden = std::string(FX2D_SOURCE_DIR) + "/goldens/compare_ab.json";
  const Outcome outcome = shell("FX2D_REPORTS_DIR=" + (scratch_ / "reports").string() + " " +
                                    bench("report --compare-json " + golden + " -o " + (scratch_ / "out").string()),
                                scratch_);
  expect_one_line_input_error(outcome, "python3-h5py");
  EXPECT_NE(outcome.err.find("'h5py'"), std::string::npos) << outcome.err;
  EXPECT_FALSE(fs::exists(scratch_ / "out"));
}

}  // namespace

// Only the scratch directory of the refusals: a report of a stability search of its own.
using ReportOfStability = ReportRefusals;

// The stability section says, for each engine and test that failed, which criterion failed first
// and at which step, as `stability --json` records them.
TEST_F(ReportOfStability, SaysWhichCriterionFailedFirstAndAtWhichStep) {
  const fs::path file = scratch_ / "stability.h5";
  const Outcome searched =
      shell(bench("stability --quick --engine fx2d,box2d --test chain_load --json --out " + file.string()), scratch_);
  ASSERT_EQ(searched.exit_code, 0) << searched.err;
  const Outcome reported = shell(bench("report " + file.string() + " -o " + (scratch_ / "out").string()), scratch_);
  ASSERT_EQ(reported.exit_code, 0) << reported.err;
  const std::string html = read_text(scratch_ / "out" / "index.html");
  const nlohmann::json results = nlohmann::json::parse(searched.out).at("results");
  int failures = 0;
  for (const nlohmann::json& result : results) {
    if (result.at("failed_step").is_null()) continue;
    ++failures;
    const std::string row_end = "<td>" + result.at("failed_criterion").get<std::string>() + "</td><td>" +
                                std::to_string(result.at("failed_step").get<int>()) + "</td><td>" +
                                result.at("failure").get<std::string>() + "</td></tr>";
    EXPECT_NE(html.find(row_end), std::string::npos) << result.at("engine") << ": " << row_end;
  }
  EXPECT_GT(failures, 0) << "chain_load's quick search failed nowhere: the test checks nothing";
}

// Only the scratch directory of the refusals: a report of a sweep over Fx2D's worker count.
using ReportOfWorkerSweep = ReportRefusals;

namespace {

// The page `report FILE -o SCRATCH/out` writes; a failed report fails the test.
std::string reported_page(const fs::path& file, const fs::path& scratch) {
  const Outcome reported = shell(bench("report " + file.string() + " -o " + (scratch / "out").string()), scratch);
  EXPECT_EQ(reported.exit_code, 0) << reported.err;
  return read_text(scratch / "out" / "index.html");
}

// "%.Ng" as the report writes numbers (Python's format "g" and C's agree).
std::string g_format(double value, int digits) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*g", digits, value);
  return text;
}

}  // namespace

// A sweep that varies only fx2d.workers gives the speedup chart, and each point's row in the phase
// split table carries its workers, its ms/step and its speedup with an interval: the median over
// the rounds of the 1-worker point's round time over this point's (the two ran each round in the
// same pass), worked out again here from the steps the file keeps.
TEST_F(ReportOfWorkerSweep, DrawsSpeedupAgainstWorkersFromPairedRounds) {
  const fs::path file = scratch_ / "workers.h5";
  const Outcome swept =
      shell(bench("sweep pile --bodies 36 --steps 30 --repeats 3 --engine fx2d"
                  " --fx2d-substeps 2 --fx2d-passes 1 --axis fx2d.workers=1,2,3 --json --out " +
                  file.string()),
            scratch_);
  ASSERT_EQ(swept.exit_code, 0) << swept.err;
  const std::string html = reported_page(file, scratch_);
  const std::vector<std::string> sources = image_sources(html);
  EXPECT_NE(std::find(sources.begin(), sources.end(), "speedup_workers.png"), sources.end());
  EXPECT_EQ(read_text(scratch_ / "out" / "speedup_workers.png").substr(0, 8), "\x89PNG\r\n\x1a\n");
  // Per worker count: the point's ms/step and each round's mean step time (point i is /runs/i).
  std::map<int, std::pair<double, std::vector<double>>> by_workers;
  const nlohmann::json points = nlohmann::json::parse(swept.out).at("points");
  const fxbench::ResultSet runs = fxbench::read_results_h5(file.string());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const nlohmann::json& settings = points[i].at("settings");
    if (settings.at("substeps") != 2) continue;
    const fxbench::RunRecord& run = runs.runs.at(i);
    std::vector<double> rounds(static_cast<std::size_t>(run.repeats), 0.0);
    for (std::size_t k = 0; k < run.wall_ms.size(); ++k)
      rounds[k / static_cast<std::size_t>(run.steps)] += run.wall_ms[k];
    for (double& round : rounds) round /= run.steps;
    by_workers[settings.at("workers").get<int>()] = {points[i].at("ms_per_step").at("median").get<double>(),
                                                     rounds};
  }
  ASSERT_EQ(by_workers.size(), 3u);
  // Beside the speedups, how fast the cores handed a cache line over as the sweep began and ended.
  const nlohmann::json machine = nlohmann::json::parse(swept.out).at("machine");
  if (std::thread::hardware_concurrency() >= 2) {
    char round_trips[128];
    std::snprintf(round_trips, sizeof round_trips, "back in %.0f ns as the sweep began, %.0f ns as it ended",
                  machine.at("core_round_trip_ns_start").get<double>(),
                  machine.at("core_round_trip_ns_end").get<double>());
    EXPECT_NE(html.find(round_trips), std::string::npos) << round_trips;
  }
  EXPECT_NE(html.find("\">pile · 36 bodies · substeps 2, velocity_passes 1</td>"), std::string::npos)
      << "one series: the swept setting (the default point, alone at its workers, is none)";
  const std::vector<double>& one_worker = by_workers.at(1).second;
  for (const auto& [workers, figures] : by_workers) {
    const auto& [ms, rounds] = figures;
    std::vector<double> ratios;
    for (std::size_t k = 0; k < rounds.size(); ++k) ratios.push_back(one_worker[k] / rounds[k]);
    std::sort(ratios.begin(), ratios.end());
    const std::string row = "<tr><td>" + std::to_string(workers) + "</td><td>" + g_format(ms, 4) +
                            "</td><td>" + g_format(ratios[1], 3) + "</td><td>";
    const std::size_t found = html.find(row);
    ASSERT_NE(found, std::string::npos) << row;
    // The interval, a bootstrap of medians of these three ratios, lies within them.
    const std::size_t start = found + row.size();
    const std::string interval = html.substr(start, html.find("</td>", start) - start);
    const std::size_t dash = interval.find("\u2013");
    ASSERT_NE(dash, std::string::npos) << interval;
    EXPECT_GE(std::stod(interval.substr(0, dash)), std::stod(g_format(ratios[0], 3)) - 1e-12) << interval;
    EXPECT_LE(std::stod(interval.substr(dash + 3)), std::stod(g_format(ratios[2], 3)) + 1e-12) << interval;
  }
}

// A merged sweep's points may come from shards that ran apart, whose rounds pair nothing: there
// the speedup is the ratio of the points' medians, and its interval cell says there is none.
TEST_F(ReportOfWorkerSweep, AMergedSweepsSpeedupIsTheRatioOfTheMediansWithNoInterval) {
  const std::string sweep =
      "sweep pile --bodies 36 --steps 30 --repeats 3 --engine fx2d --fx2d-substeps 2"
      " --fx2d-passes 1 --axis fx2d.workers=1,2,3 --json --out ";
  std::map<int, double> ms_by_workers;
  for (const char* shard : {"1/2", "2/2"}) {
    const fs::path part = scratch_ / (std::string("part") + shard[0] + ".h5");
    const Outcome swept = shell(bench(sweep + part.string() + " --shard " + shard), scratch_);
    ASSERT_EQ(swept.exit_code, 0) << swept.err;
    const nlohmann::json printed = nlohmann::json::parse(swept.out);
    for (const nlohmann::json& point : printed.at("points")) {
      const nlohmann::json& settings = point.at("settings");
      if (settings.at("substeps") == 2)
        ms_by_workers[settings.at("workers").get<int>()] = point.at("ms_per_step").at("median").get<double>();
    }
  }
  ASSERT_EQ(ms_by_workers.size(), 3u);
  const fs::path merged = scratch_ / "merged.h5";
  const Outcome merging = shell(bench("merge " + merged.string() + " " + (scratch_ / "part1.h5").string() +
                                      " " + (scratch_ / "part2.h5").string()),
                                scratch_);
  ASSERT_EQ(merging.exit_code, 0) << merging.err;
  const std::string html = reported_page(merged, scratch_);
  for (const auto& [workers, ms] : ms_by_workers) {
    const std::string row = "<tr><td>" + std::to_string(workers) + "</td><td>" + g_format(ms, 4) +
                            "</td><td>" + g_format(ms_by_workers.at(1) / ms, 3) + "</td><td>\u2013</td>";
    EXPECT_NE(html.find(row), std::string::npos) << row;
  }
}
