// Tests of the noise-free counts behind `fx2d-bench run --counter instructions`: callgrind's output
// is parsed exactly; the counting child, run twice on one scene, gives the same positive count
// (the determinism that lets CI gate on it without statistics); the count covers the step loop
// alone, so doubling the steps of a scene that does the same work every step doubles it; the
// refusals (valgrind missing, the child outside valgrind, an unknown engine) are one line and
// exit 2; and `run --counter instructions --out` stores the count in the result file.
//
// Valgrind cannot run a program built with AddressSanitizer, so the tests that start it are
// skipped in FX2D_SANITIZE builds, and where valgrind is not installed.
#include "measure/instruction_counter.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "tests/support/bench_process.h"
#include "common/errors.h"
#include "scene/scene_loader.h"
#include "storage/results_h5.h"

namespace fxbench {
namespace {

namespace fs = std::filesystem;

// --- callgrind's output format --------------------------------------------------------------------

std::uint64_t parse(const std::string& text) {
  std::istringstream output(text);
  return callgrind_total_instructions(output, "callgrind.out");
}

TEST(CallgrindOutput, TotalsLineGivesTheCount) {
  EXPECT_EQ(parse("version: 1\ncreator: callgrind-3.19.0\nevents: Ir\nsummary: 0\n\nfn=(1) main\n0 9016\n"
                  "totals: 18018\n"),
            18018u);
}

TEST(CallgrindOutput, SummaryLineServesWhenThereIsNoTotalsLine) {
  EXPECT_EQ(parse("events: Ir\nsummary: 9016\n"), 9016u);
}

TEST(CallgrindOutput, FirstEventMustBeInstructions) {
  EXPECT_THROW(parse("events: Dr Ir\ntotals: 5 7\n"), std::runtime_error);
  EXPECT_THROW(parse("totals: 5\n"), std::runtime_error);
}

TEST(CallgrindOutput, MissingOrMalformedTotalIsAnError) {
  EXPECT_THROW(parse("events: Ir\n"), std::runtime_error);
  EXPECT_THROW(parse("events: Ir\ntotals: many\n"), std::runtime_error);
  EXPECT_THROW(parse("events: Ir\ntotals: 12x\n"), std::runtime_error);
}

// --- the counting child -----------------------------------------------------------------------------

// A stack of 10 boxes at rest with sleeping off: every step finds the same contacts and runs the
// same solver iterations, so each step costs about the same number of instructions and the count
// grows in proportion to the steps.
SceneSpec resting_stack(int steps, const std::string& engine) {
  SceneOverrides overrides;
  overrides.bodies = 10;
  overrides.steps = steps;
  const std::string sleeping = engine == "ode" ? "auto_disable" : "sleeping";
  overrides.sets = {{"/solver/" + engine + "/" + sleeping, "false"}};
  return load_scene_text(*embedded_scene_text("stacks"), "<embedded:stacks>", overrides);
}

class InstructionCounting : public ::testing::Test {
 protected:
  void SetUp() override {
    if (built_with_address_sanitizer) GTEST_SKIP() << "valgrind cannot run an AddressSanitizer build (FX2D_SANITIZE)";
    try {
      counter_.emplace(FX2D_BENCH_EXE);
    } catch (const InputError& error) {
      GTEST_SKIP() << error.what();
    }
    directory_ = fs::temp_directory_path() / ("fx2d_instruction_counter_test_" + std::to_string(getpid()));
    fs::create_directories(directory_);
  }
  void TearDown() override {
    if (!directory_.empty()) fs::remove_all(directory_);
  }

  InstructionCount count(const SceneSpec& scene, const std::string& engine) const {
    const std::optional<InstructionCount> counted = counter_->count(scene, engine);
    if (!counted) throw std::logic_error("the count was interrupted");
    return *counted;
  }

  std::optional<InstructionCounter> counter_;
  fs::path directory_;
};

// Box2D 2.4.1 times its own step (b2Timer, gettimeofday), and b2Timer::GetMilliseconds takes an
// extra branch, about 11 instructions, when a timed span crosses a wall-clock second: its count
// moves by that much now and then (1669140, 1669151 and 1669162 seen for this scene). Fx2D and
// ODE read no clock in their step, so theirs repeat exactly.
std::uint64_t clock_dependent_instructions(const std::string& engine, std::uint64_t count) {
  return engine == "box2d" ? count / 10000 : 0;
}

TEST_F(InstructionCounting, TwoSeparateRunsGiveTheSamePositiveCountOnEveryEngine) {
  for (const std::string engine : {"fx2d", "box2d", "ode"}) {
    const SceneSpec scene = resting_stack(20, engine);
    const InstructionCount first = count(scene, engine);
    const InstructionCount second = count(scene, engine);
    EXPECT_GT(first.instructions, 0u) << engine;
    const std::uint64_t difference = std::max(first.instructions, second.instructions) -
                                     std::min(first.instructions, second.instructions);
    EXPECT_LE(difference, clock_dependent_instructions(engine, first.instructions))
        << engine << ": " << first.instructions << " then " << second.instructions;
    EXPECT_EQ(first.steps, 20) << engine;
    EXPECT_EQ(first.tool, "callgrind");
    EXPECT_TRUE(first.tool_version.starts_with("valgrind-")) << first.tool_version;
  }
}

TEST_F(InstructionCounting, DoublingTheStepsRoughlyDoublesTheCount) {
  // Everything outside the loop (start-up, loading and building the scene) costs about 21
  // million instructions here, six times the 20 steps' 3.5 million: were any of it counted, the
  // ratio would fall towards 1 (1.14 with all of it).
  const double twenty = static_cast<double>(count(resting_stack(20, "fx2d"), "fx2d").instructions);
  const double forty = static_cast<double>(count(resting_stack(40, "fx2d"), "fx2d").instructions);
  EXPECT_GT(forty / twenty, 1.7);
  EXPECT_LT(forty / twenty, 2.3);
}

TEST_F(InstructionCounting, UnknownEngineIsBadInputNamingIt) {
  try {
    count(resting_stack(5, "fx2d"), "bullet");
    FAIL() << "an unknown engine was counted";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("bullet"), std::string::npos) << error.what();
  }
}

TEST_F(InstructionCounting, ChildRefusesToRunOutsideValgrind) {
  const bench_test::Ending ending =
      bench_test::run_bench({"count-instructions", "--engine", "fx2d", "stacks", "--steps", "5"}, directory_);
  EXPECT_EQ(ending.exit_code, exit_bad_input) << ending.err;
  EXPECT_NE(ending.err.find("valgrind"), std::string::npos) << ending.err;
  EXPECT_EQ(std::count(ending.err.begin(), ending.err.end(), '\n'), 1) << ending.err;
}

TEST_F(InstructionCounting, RunStoresTheCountOfEachRunInTheResultFile) {
  const std::string out = (directory_ / "counted.h5").string();
  const bench_test::Ending ending =
      bench_test::run_bench({"run", "stacks", "--bodies", "10", "--steps", "10", "--repeats", "1", "--engine",
                             "fx2d,box2d", "--counter", "instructions", "--out", out},
                            directory_);
  ASSERT_EQ(ending.exit_code, exit_ok) << ending.err;
  const ResultSet results = read_results_h5(out);
  ASSERT_EQ(results.runs.size(), 2u);
  for (const RunRecord& run : results.runs) {
    ASSERT_TRUE(run.instruction_count.has_value()) << run.engine;
    EXPECT_EQ(run.instruction_count->steps, 10) << run.engine;
    EXPECT_GT(run.instruction_count->instructions, 0u) << run.engine;
    EXPECT_EQ(run.instruction_count->tool_version, counter_->valgrind_version());
  }
  // The same scene as the counting child's, counted directly: the child stepped the run's scene.
  const SceneSpec scene = load_scene_text(*embedded_scene_text("stacks"), "<embedded:stacks>", {10, 10, {}});
  EXPECT_EQ(results.runs[0].instruction_count->instructions, count(scene, "fx2d").instructions);
}

TEST_F(InstructionCounting, RunSummaryShowsInstructionsPerStep) {
  const bench_test::Ending ending = bench_test::run_bench(
      {"run", "stacks", "--bodies", "10", "--steps", "10", "--repeats", "1", "--engine", "fx2d", "--counter",
       "instructions", "--json"},
      directory_);
  ASSERT_EQ(ending.exit_code, exit_ok) << ending.err;
  const auto summary = nlohmann::json::parse(ending.out);
  const SceneSpec scene = load_scene_text(*embedded_scene_text("stacks"), "<embedded:stacks>", {10, 10, {}});
  EXPECT_EQ(summary["runs"][0]["instructions_per_step"].get<double>(), count(scene, "fx2d").per_step());

  const bench_test::Ending table = bench_test::run_bench(
      {"run", "stacks", "--bodies", "10", "--steps", "10", "--repeats", "1", "--engine", "fx2d", "--counter",
       "instructions"},
      directory_);
  ASSERT_EQ(table.exit_code, exit_ok) << table.err;
  EXPECT_NE(table.out.find("instr/step"), std::string::npos) << table.out;
}

// With no valgrind on PATH, counting is refused before anything runs: one line, exit 2.
class WithoutValgrind : public ::testing::Test {
 protected:
  void SetUp() override {
    if (const char* path = std::getenv("PATH")) saved_path_ = path;
    directory_ = fs::temp_directory_path() / ("fx2d_no_valgrind_" + std::to_string(getpid()));
    fs::create_directories(directory_ / "empty");
    setenv("PATH", (directory_ / "empty").c_str(), 1);
  }
  void TearDown() override {
    setenv("PATH", saved_path_.c_str(), 1);
    fs::remove_all(directory_);
  }

  std::string saved_path_;
  fs::path directory_;
};

TEST_F(WithoutValgrind, CounterIsRefusedAsBadInput) {
  EXPECT_THROW(InstructionCounter{FX2D_BENCH_EXE}, InputError);
}

TEST_F(WithoutValgrind, RunWithCounterExitsTwoWithOneLine) {
  const std::string out = (directory_ / "never.h5").string();
  const bench_test::Ending ending = bench_test::run_bench(
      {"run", "stacks", "--bodies", "10", "--steps", "5", "--counter", "instructions", "--out", out}, directory_);
  EXPECT_EQ(ending.exit_code, exit_bad_input) << ending.err;
  EXPECT_EQ(std::count(ending.err.begin(), ending.err.end(), '\n'), 1) << ending.err;
  EXPECT_NE(ending.err.find("valgrind"), std::string::npos) << ending.err;
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace fxbench
