// Hostile and broken input through the real binary: result files handed to `compare` and
// `report`, and scenes that ask for absurd sizes or values. Each must be refused with exit code 2
// and one line on stderr naming what was wrong, quickly and without allocating in proportion to
// what was asked for.
//
// Memory bound: the binary's own high-water resident set is about 13 MiB (libraries, HDF5, the
// embedded scenes). Anything allocated per body or per byte of a large file shows as hundreds of
// MiB or more (a billion bodies at even 100 B each is 100 GB), so 64 MiB separates "refused before
// allocating" from "allocated, then failed" with a wide margin either side.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "tests/support/bench_process.h"
#include "storage/file_integrity.h"

namespace fxbench {
namespace {

namespace fs = std::filesystem;
using bench_test::Ending;
using bench_test::run_bench;

// Peak memory of a refused run: the program's own baseline and no more. AddressSanitizer's shadow
// memory and allocator add about 60 MiB to every process, so a sanitized build gets that on top.
// Either way a billion bodies, or a parsed 5 MB nesting, would need gigabytes.
#if defined(__SANITIZE_ADDRESS__)
constexpr long refusal_rss_limit_kib = (64 + 96) * 1024;
#else
constexpr long refusal_rss_limit_kib = 64 * 1024;
#endif

// Exit code 2, and exactly one line on stderr, prefixed with the program's name, mentioning `what`.
void expect_one_line_refusal(const Ending& ending, const std::string& what) {
  EXPECT_EQ(ending.signal, 0) << ending.err;
  EXPECT_EQ(ending.exit_code, 2) << ending.err;
  EXPECT_TRUE(ending.err.starts_with("fx2d-bench: ")) << ending.err;
  EXPECT_EQ(std::count(ending.err.begin(), ending.err.end(), '\n'), 1) << ending.err;
  EXPECT_NE(ending.err.find(what), std::string::npos) << "expected '" << what << "' in: " << ending.err;
}

constexpr const char* no_header = "not an fx2d-bench result file (no fx2d-bench header)";
constexpr const char* corrupt = "corrupt or truncated";

void expect_refused_before_allocating(const Ending& ending, const std::string& what) {
  expect_one_line_refusal(ending, what);
  EXPECT_LT(ending.peak_rss_kib, refusal_rss_limit_kib);
}

class HostileInputTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    directory_ = fs::temp_directory_path() / ("fx2d_hostile_input_test_" + std::to_string(getpid()));
    fs::create_directories(directory_);
    const Ending made = run_bench({"run", "stacks", "--engine", "box2d", "--steps", "5", "--repeats", "1", "--out",
                                   good_file().string()},
                                  directory_);
    ASSERT_EQ(made.exit_code, 0) << made.err;
  }
  static void TearDownTestSuite() { fs::remove_all(directory_); }

  static fs::path good_file() { return directory_ / "good.h5"; }

  static std::string good_bytes() {
    std::ifstream file(good_file(), std::ios::binary);
    return {std::istreambuf_iterator<char>(file), {}};
  }

  static fs::path write_file(const std::string& name, const std::string& bytes) {
    const fs::path path = directory_ / name;
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }

  // Both readers of result files, through the binary, on `bad`: one refusal line naming the file.
  static void expect_result_readers_refuse(const fs::path& bad, const std::string& what) {
    SCOPED_TRACE(bad.filename().string());
    const Ending compared = run_bench({"compare", bad.string(), good_file().string()}, directory_);
    expect_refused_before_allocating(compared, bad.string());
    expect_one_line_refusal(compared, what);
    const Ending reported = run_bench({"report", bad.string(), "-o", (directory_ / "report").string()}, directory_);
    expect_refused_before_allocating(reported, bad.string());
    EXPECT_FALSE(fs::exists(directory_ / "report")) << "nothing is drawn from a bad file";
  }

  static Ending run_scene(const std::vector<std::string>& options) {
    std::vector<std::string> arguments{"run", "pile", "--engine", "fx2d", "--repeats", "1", "--steps", "1"};
    arguments.insert(arguments.end(), options.begin(), options.end());
    return run_bench(arguments, directory_);
  }

  static inline fs::path directory_;
};

TEST_F(HostileInputTest, ZeroLengthResultFileIsRefused) {
  expect_result_readers_refuse(write_file("empty.h5", ""), no_header);
}

TEST_F(HostileInputTest, TruncatedResultFileIsRefused) {
  const std::string bytes = good_bytes();
  for (const std::size_t length : {std::size_t{100}, bytes.size() / 2, bytes.size() - 1}) {
    expect_result_readers_refuse(write_file("truncated_" + std::to_string(length) + ".h5", bytes.substr(0, length)),
                                 corrupt);
  }
}

TEST_F(HostileInputTest, ResultFileWithOneByteFlippedIsRefused) {
  const std::string bytes = good_bytes();
  // The first byte libhdf5 would read, one in the middle, the last.
  for (const std::size_t at : {h5_seal_bytes, (h5_seal_bytes + bytes.size()) / 2, bytes.size() - 1}) {
    std::string flipped = bytes;
    flipped[at] = static_cast<char>(flipped[at] ^ 0x20);
    expect_result_readers_refuse(write_file("flipped_" + std::to_string(at) + ".h5", flipped),
                                 "corrupt or truncated (checksum mismatch)");
  }
}

TEST_F(HostileInputTest, ValidHdf5FileWithoutTheSealIsRefused) {
  // The HDF5 file proper with its user block cut off: libhdf5 and h5py open it, fx2d-bench does not.
  expect_result_readers_refuse(write_file("unsealed.h5", good_bytes().substr(h5_seal_bytes)), no_header);
}

TEST_F(HostileInputTest, ResultFileOfAnotherSchemaVersionIsRefused) {
  std::string bytes = good_bytes();
  // The schema string is stored once, verbatim; the same length keeps every offset in the file valid.
  const std::string schema = "fx2d-bench.results/1";
  const std::size_t at = bytes.find(schema);
  ASSERT_NE(at, std::string::npos);
  bytes.replace(at, schema.size(), "fx2d-bench.results/9");
  const fs::path future = write_file("future.h5", bytes);
  seal_h5_file(future.string());  // as a future fx2d-bench would have written it
  expect_result_readers_refuse(future, "fx2d-bench.results/9");
}

TEST_F(HostileInputTest, FileThatIsNotHdf5IsRefused) {
  expect_result_readers_refuse(write_file("text.h5", "engine,ms\nfx2d,1.0\n"), no_header);
}

TEST_F(HostileInputTest, SparseFourGibibyteFileIsRefusedWithoutBeingRead) {
  const fs::path huge = directory_ / "huge.h5";
  const int descriptor = open(huge.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  ASSERT_GE(descriptor, 0);
  // A hole: 4 GiB of zeros that occupy no disk and would take seconds and gigabytes to read whole.
  ASSERT_EQ(ftruncate(descriptor, off_t{4} << 30), 0);
  close(descriptor);
  const Ending compared = run_bench({"compare", huge.string(), good_file().string()}, directory_);
  expect_refused_before_allocating(compared, no_header);
  // Reading 4 GiB of zeros, even from the page cache, takes well over a second on this machine.
  EXPECT_LT(compared.seconds, 1.0);
}

TEST_F(HostileInputTest, BillionBodiesAreRefusedBeforeAnyAllocation) {
  expect_refused_before_allocating(run_scene({"--bodies", "1000000000"}), "--bodies");
}

TEST_F(HostileInputTest, OdeRefusesMoreBodiesThanItsHashSpaceCanHoldBeforeBuilding) {
  // 70,000 circles: ODE's hash space would clear a 612 MB bit table every step (engines/ode.cpp).
  // Named, ODE is refused before Fx2D and Box2D, listed first, are measured: nothing is lost at the
  // end. (With `all` it would be left out of the run, cli_misuse_test.py.)
  const Ending ending = run_bench(
      {"run", "pile", "--engine", "fx2d,box2d,ode", "--bodies", "70000", "--repeats", "1", "--steps", "1"}, directory_);
  expect_refused_before_allocating(ending, "engine ode cannot build more than 65536 bodies");
}

TEST_F(HostileInputTest, NegativeBodyCountIsRefused) {
  expect_refused_before_allocating(run_scene({"--bodies", "-5"}), "--bodies");
}

TEST_F(HostileInputTest, SceneFileAskingForABillionBodiesIsRefusedBeforeAnyAllocation) {
  const fs::path scene = write_file("billion.json", R"({"schema": "fx2d.scene/1", "size": 1000000000,
      "generators": [{"type": "ground"}, {"type": "pile"}]})");
  expect_refused_before_allocating(run_bench({"run", scene.string()}, directory_), "/size");
}

TEST_F(HostileInputTest, GravityBeyondDoubleRangeIsRefused) {
  expect_refused_before_allocating(run_scene({"--set", "/gravity=[1e400,0]"}), "/gravity");
}

TEST_F(HostileInputTest, NanGravityIsRefused) {
  expect_refused_before_allocating(run_scene({"--set", R"(/gravity=["NaN",0])"}), "/gravity/0");
}

TEST_F(HostileInputTest, FiftyMegabytesOfGarbageAreRefusedWithoutBeingRead) {
  std::string garbage(50'000'000, '\0');
  std::mt19937 random(7);
  std::ranges::generate(garbage, [&] { return static_cast<char>(random()); });
  const fs::path scene = write_file("garbage.json", garbage);
  const Ending ending = run_bench({"run", scene.string()}, directory_);
  // Refused by its size before a byte is parsed.
  expect_refused_before_allocating(ending, "at most 16 MiB");
  EXPECT_LT(ending.seconds, 5.0);
}

TEST_F(HostileInputTest, DeeplyNestedSceneIsRefusedBeforeParsing) {
  // Five million '[' once cost nlohmann's parser 43 s and 3.8 GB; the depth check reads it once.
  const fs::path scene = write_file("deep.json", std::string(5'000'000, '['));
  const Ending ending = run_bench({"run", scene.string()}, directory_);
  expect_refused_before_allocating(ending, "nesting deeper than 64 levels");
  EXPECT_LT(ending.seconds, 5.0);
}

TEST_F(HostileInputTest, DeeplyNestedGatingPolicyIsRefusedBeforeParsing) {
  // The policy shares the scenes' parser and its depth check: eight million levels, balanced, once
  // cost 616 MB before the root was found not to be an object.
  const fs::path policy =
      write_file("deep_policy.json", std::string(8'000'000, '[') + std::string(8'000'000, ']'));
  const Ending ending = run_bench({"gate", "--policy", policy.string(), "--print-suite", "full"}, directory_);
  expect_refused_before_allocating(ending, "deep_policy.json:1:65: nesting deeper than 64 levels");
  EXPECT_LT(ending.seconds, 5.0);
}

TEST_F(HostileInputTest, AbsurdRepeatsTimesStepsAreRefusedBeforeMeasuring) {
  const Ending ending = run_bench({"run", "pile", "--engine", "fx2d", "--repeats", "100000", "--steps", "10000000"}, directory_);
  expect_refused_before_allocating(ending, "--repeats x --steps");
}

}  // namespace
}  // namespace fxbench
