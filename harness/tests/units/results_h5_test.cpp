// Tests of the HDF5 result file: exact round trip, atomic and non-clobbering writes, one-line
// errors for every file the reader cannot take, the on-disk layout against a golden dump, and
// that h5py (the reader most users will reach for) understands it.
//
// The layout golden is goldens/results_layout.txt. Regenerate it, after a deliberate layout
// change, only with:
//   FX2D_UPDATE_GOLDENS=1 <build>/harness/tests/results_h5_test --gtest_filter='*Golden*'
#include "storage/results_h5.h"

#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "common/errors.h"
#include "storage/file_integrity.h"

namespace fxbench {
namespace {

namespace fs = std::filesystem;

RunRecord sample_run(const std::string& engine, int repeats, int steps, std::vector<std::string> phases) {
  RunRecord run;
  run.engine = engine;
  run.engine_version = engine == "fx2d" ? "0.1.0" : "2.4.1";
  run.engine_settings = "substeps=14 velocity_passes=4 sleeping=1";
  run.scene = "pile";
  run.scene_hash = "0123456789abcdef";
  run.bodies = 300;
  run.body_count = 303;
  run.steps = steps;
  run.repeats = repeats;
  run.warmup_steps = 10;
  run.hash_every = 50;
  const int samples = repeats * steps;
  for (int i = 0; i < samples; ++i) {
    // Thirds and sevenths have no finite binary expansion: any rounding on the way shows.
    run.wall_ms.push_back(1.0 / (i + 3));
    run.cpu_ms.push_back(1.0 / (i + 7));
    run.cycles.push_back(std::numeric_limits<std::uint64_t>::max() - static_cast<std::uint64_t>(i));
    run.contacts.push_back(i == 0 ? std::numeric_limits<std::int32_t>::max() : 7 * i);
    for (std::size_t p = 0; p < phases.size(); ++p)
      run.phase_ms.push_back(0.1 * static_cast<double>(p + 1) / (i + 1));
  }
  run.phase_names = std::move(phases);
  return run;
}

ResultSet sample_results() {
  ResultSet results;
  Provenance& provenance = results.provenance;
  provenance.fx2d_version = "0.1.0";
  provenance.fx2d_git_revision = "21f8336";
  provenance.build_type = "Release";
  provenance.build_flags = "-O2 -ffp-contract=off";
  provenance.compiler = "GNU 12.2.0";
  provenance.cpu_model = "Intel(R) Xeon(R) CPU @ 2.20GHz";
  provenance.kernel = "6.1.0-18-amd64";
  provenance.hostname = "bench-01";
  provenance.date_utc = "2024-05-01T12:00:00Z";
  provenance.command_line = "fx2d-bench run --scene pile --set '/name=\"Größe µ\"' -o out.h5";
  provenance.tsc_ghz = 2.2000000000000002;
  provenance.core_round_trip_ns_start = 152.25;
  provenance.core_round_trip_ns_end = 410.0000000000001;

  results.scenes.push_back({"pile", "0123456789abcdef",
                            "{\n  \"name\": \"pile\",\n  \"note\": \"Größe µ\"\n}\n", "scenes/pile.json",
                            "penetration"});
  results.scenes.push_back({"stacks", "fedcba9876543210", "{}", "", "displacement"});

  RunRecord with_phases = sample_run("fx2d", 2, 3, {"collide", "solve", "integrate"});
  with_phases.accuracy.push_back({1, 0.0125, -0.0, 1e-300, 4.9e-324, 1.0 / 3.0, 0, 0});
  with_phases.accuracy.push_back({3, 0.02, 0.01, 0.5, 0.25, 1e300, 2, 1});
  with_phases.state_hashes = {"00000000deadbeef", "0123456789abcdef"};
  with_phases.final_state_hash = "0123456789abcdef";
  results.runs.push_back(with_phases);

  // No phase split, no accuracy samples, no hashes: the empty cases.
  RunRecord without_phases = sample_run("box2d", 1, 4, {});
  without_phases.deterministic = false;
  results.runs.push_back(without_phases);
  return results;
}

std::string file_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

class ResultsFile : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string test = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    directory_ =
        fs::temp_directory_path() / ("fx2d_results_h5_test." + std::to_string(::getpid()) + "." + test);
    fs::remove_all(directory_);
    fs::create_directories(directory_);
    path_ = (directory_ / "results.h5").string();
  }
  void TearDown() override { fs::remove_all(directory_); }

  std::vector<std::string> directory_entries() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(directory_))
      names.push_back(entry.path().filename().string());
    return names;
  }

  // The InputError message reading `path` gives, checking that nothing reached stderr.
  static std::string read_error(const std::string& path) {
    ::testing::internal::CaptureStderr();
    std::string message = "(no InputError)";
    try {
      read_results_h5(path);
    } catch (const InputError& error) {
      message = error.what();
    }
    EXPECT_EQ(::testing::internal::GetCapturedStderr(), "") << path;
    return message;
  }

  fs::path directory_;
  std::string path_;
};

constexpr const char* no_header = "not an fx2d-bench result file (no fx2d-bench header)";
constexpr const char* corrupt = "corrupt or truncated";

void expect_one_line_naming(const std::string& message, const std::string& path,
                            const std::string& expected) {
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
  EXPECT_NE(message.find(expected), std::string::npos) << message;
}

TEST_F(ResultsFile, RoundTripKeepsEveryFieldExactly) {
  const ResultSet written = sample_results();
  write_results_h5(written, path_, false);
  const ResultSet read = read_results_h5(path_);
  EXPECT_EQ(read.provenance, written.provenance);
  ASSERT_EQ(read.scenes.size(), 2u);
  EXPECT_EQ(read.scenes[0], written.scenes[0]);
  EXPECT_EQ(read.scenes[1], written.scenes[1]);
  ASSERT_EQ(read.runs.size(), 2u);
  EXPECT_EQ(read.runs[0], written.runs[0]);
  EXPECT_EQ(read.runs[1], written.runs[1]);
  // operator== calls -0.0 and 0.0 equal; the bits must survive too.
  EXPECT_TRUE(std::signbit(read.runs[0].accuracy[0].mean_penetration));
  EXPECT_TRUE(read == written);
}

TEST_F(ResultsFile, WriteLeavesOnlyTheFinalFile) {
  write_results_h5(sample_results(), path_, false);
  EXPECT_EQ(directory_entries(), std::vector<std::string>{"results.h5"});
}

TEST_F(ResultsFile, ExistingFileIsReplacedOnlyWithOverwrite) {
  write_results_h5(sample_results(), path_, false);
  const std::string before = file_text(path_);
  ResultSet other = sample_results();
  other.provenance.hostname = "bench-02";
  try {
    write_results_h5(other, path_, false);
    ADD_FAILURE() << "wrote over an existing file";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()), path_ + ": exists; pass --force to overwrite");
  }
  EXPECT_EQ(file_text(path_), before);

  write_results_h5(other, path_, true);
  EXPECT_EQ(read_results_h5(path_).provenance.hostname, "bench-02");
  EXPECT_EQ(directory_entries(), std::vector<std::string>{"results.h5"});
}

TEST_F(ResultsFile, FailedWriteLeavesNoTemporaryAndKeepsTheOldFile) {
  write_results_h5(sample_results(), path_, false);
  const std::string before = file_text(path_);
  // The second run is inconsistent, so the failure comes after the temporary file has been
  // created and partly written.
  ResultSet broken = sample_results();
  broken.runs[1].wall_ms.pop_back();
  EXPECT_THROW(write_results_h5(broken, path_, true), std::runtime_error);
  EXPECT_EQ(directory_entries(), std::vector<std::string>{"results.h5"});
  EXPECT_EQ(file_text(path_), before);
}

TEST_F(ResultsFile, UncreatableFileIsAnInputErrorNamingIt) {
  const std::string nowhere = (directory_ / "missing" / "results.h5").string();
  ::testing::internal::CaptureStderr();
  try {
    write_results_h5(sample_results(), nowhere, false);
    ADD_FAILURE() << "wrote into a missing directory";
  } catch (const InputError& error) {
    expect_one_line_naming(error.what(), nowhere, "cannot create");
  }
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  EXPECT_TRUE(directory_entries().empty());
}

TEST_F(ResultsFile, UnreadableFilesGiveOneLineInputErrors) {
  write_results_h5(sample_results(), path_, false);
  const std::string whole = file_text(path_);

  const std::string missing = (directory_ / "absent.h5").string();
  expect_one_line_naming(read_error(missing), missing, "no such file");

  const std::string empty = (directory_ / "empty.h5").string();
  write_text(empty, "");
  expect_one_line_naming(read_error(empty), empty, no_header);

  const std::string text = (directory_ / "text.h5").string();
  write_text(text, "wall_ms,cpu_ms\n0.1,0.1\n");
  expect_one_line_naming(read_error(text), text, no_header);

  const std::string truncated = (directory_ / "truncated.h5").string();
  write_text(truncated, whole.substr(0, whole.size() / 2));
  expect_one_line_naming(read_error(truncated), truncated, corrupt);

  // A valid HDF5 file, but not one fx2d-bench sealed: libhdf5 is never asked to open it.
  const std::string bare = (directory_ / "bare.h5").string();
  H5Fclose(H5Fcreate(bare.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT));
  expect_one_line_naming(read_error(bare), bare, no_header);

  // The same seal on a file without schema: past the seal, the reader's own checks still hold.
  const std::string sealed_bare = (directory_ / "sealed_bare.h5").string();
  const hid_t creation = H5Pcreate(H5P_FILE_CREATE);
  H5Pset_userblock(creation, h5_seal_bytes);
  H5Fclose(H5Fcreate(sealed_bare.c_str(), H5F_ACC_TRUNC, creation, H5P_DEFAULT));
  H5Pclose(creation);
  seal_h5_file(sealed_bare);
  expect_one_line_naming(read_error(sealed_bare), sealed_bare, "no root attribute 'schema'");
}

TEST_F(ResultsFile, BytesFlippedAfterTheSealAreRefused) {
  write_results_h5(sample_results(), path_, false);
  const std::string whole = file_text(path_);
  const std::string damaged = (directory_ / "damaged.h5").string();
  // FNV-1a guarantees that any single-byte change shows (file_integrity.h); this samples it: all
  // of the superblock libhdf5 reads first, then every 61st byte (a prime, so the samples fall at
  // every offset within HDF5's 8-byte fields) to the last. Writing the file for every byte would
  // take a minute of disk traffic.
  std::vector<std::size_t> offsets;
  for (std::size_t at = h5_seal_bytes; at < h5_seal_bytes + 96; ++at) offsets.push_back(at);
  for (std::size_t at = h5_seal_bytes + 96; at < whole.size(); at += 61) offsets.push_back(at);
  offsets.push_back(whole.size() - 1);
  for (const std::size_t at : offsets) {
    std::string bytes = whole;
    bytes[at] = static_cast<char>(bytes[at] ^ 0x01);
    write_text(damaged, bytes);
    const std::string message = read_error(damaged);
    if (message != damaged + ": corrupt or truncated (checksum mismatch)") {
      ADD_FAILURE() << "byte " << at << " of " << whole.size() << " flipped: " << message;
      break;
    }
  }
}

TEST_F(ResultsFile, TruncatedFilesAreRefusedAtEveryLength) {
  write_results_h5(sample_results(), path_, false);
  const std::string whole = file_text(path_);
  const std::string cut = (directory_ / "cut.h5").string();
  // Shorter than the first line of the seal, there is no seal to speak of; from there on the
  // header, its length or its checksum disagrees with what is left.
  for (const std::size_t length : {std::size_t{0}, std::size_t{10}}) {
    write_text(cut, whole.substr(0, length));
    expect_one_line_naming(read_error(cut), cut, no_header);
  }
  for (const std::size_t length : {std::size_t{40}, h5_seal_bytes - 1, h5_seal_bytes, h5_seal_bytes + 8,
                                   whole.size() / 2, whole.size() - 1}) {
    SCOPED_TRACE(length);
    write_text(cut, whole.substr(0, length));
    expect_one_line_naming(read_error(cut), cut, corrupt);
  }
  write_text(cut, whole + std::string(1, '\0'));
  expect_one_line_naming(read_error(cut), cut, corrupt);
}

// libhdf5 crashed, hung or overran its buffers inside H5Fopen, H5Gopen or H5Aread on these
// (found by harness/fuzz/results_reader_fuzz.cpp); none carries a seal, so none reaches it now.
TEST_F(ResultsFile, PastLibhdf5CrashReproducersAreRefusedBeforeLibhdf5) {
  const fs::path crashes = fs::path(FX2D_SOURCE_DIR) / "harness" / "fuzz" / "crashes" / "results_reader";
  int replayed = 0;
  for (const auto& entry : fs::directory_iterator(crashes)) {
    expect_one_line_naming(read_error(entry.path().string()), entry.path().string(), no_header);
    ++replayed;
  }
  EXPECT_GE(replayed, 4);
}

TEST_F(ResultsFile, SealStatesTheLengthInPlainText) {
  write_results_h5(sample_results(), path_, false);
  const std::string whole = file_text(path_);
  const std::string header = whole.substr(0, whole.find('\0'));
  char length[21];
  std::snprintf(length, sizeof length, "%020zu", whole.size());
  EXPECT_EQ(header.rfind("fx2d-bench sealed HDF5 file\nformat 1\nlength " + std::string(length) +
                             "\nchecksum fnv1a64 ",
                         0),
            0u)
      << header;
  EXPECT_EQ(whole.substr(h5_seal_bytes, 4), "\x89HDF");
}

TEST_F(ResultsFile, UnknownSchemaIsRefused) {
  write_results_h5(sample_results(), path_, false);
  const hid_t file = H5Fopen(path_.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  H5Adelete(file, "schema");
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, H5T_VARIABLE);
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t attribute = H5Acreate2(file, "schema", type, space, H5P_DEFAULT, H5P_DEFAULT);
  const char* future = "fx2d-bench.results/2";
  H5Awrite(attribute, type, &future);
  H5Aclose(attribute);
  H5Sclose(space);
  H5Tclose(type);
  H5Fclose(file);
  seal_h5_file(path_);  // as if written so: the check after the seal is the one under test
  expect_one_line_naming(read_error(path_), path_, "schema 'fx2d-bench.results/2' is not supported");
}

TEST_F(ResultsFile, AFileWrittenBeforeTheCoreRoundTripWasRecordedReadsItAsNotMeasured) {
  ResultSet written = sample_results();
  write_results_h5(written, path_, false);
  const hid_t file = H5Fopen(path_.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(H5Adelete(file, "core_round_trip_ns_start"), 0);
  ASSERT_GE(H5Adelete(file, "core_round_trip_ns_end"), 0);
  H5Fclose(file);
  seal_h5_file(path_);
  const ResultSet read = read_results_h5(path_);
  EXPECT_EQ(read.provenance.core_round_trip_ns_start, 0.0);
  EXPECT_EQ(read.provenance.core_round_trip_ns_end, 0.0);
  written.provenance.core_round_trip_ns_start = written.provenance.core_round_trip_ns_end = 0.0;
  EXPECT_TRUE(read == written);
}

TEST_F(ResultsFile, MissingDatasetIsNamed) {
  write_results_h5(sample_results(), path_, false);
  const hid_t file = H5Fopen(path_.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  H5Ldelete(file, "/runs/1/cpu_ms", H5P_DEFAULT);
  H5Fclose(file);
  seal_h5_file(path_);
  expect_one_line_naming(read_error(path_), path_, "/runs/1: missing dataset 'cpu_ms'");
}

// The layout dump: one line per group, dataset and attribute, in name order, with types,
// shapes and attribute values, but no dataset contents.
std::string type_text(hid_t type) {
  const auto bits = std::to_string(8 * H5Tget_size(type));
  const std::string order = H5Tget_order(type) == H5T_ORDER_LE ? "le" : "be";
  switch (H5Tget_class(type)) {
    case H5T_INTEGER:
      return (H5Tget_sign(type) == H5T_SGN_NONE ? "uint" : "int") + bits + order;
    case H5T_FLOAT:
      return "float" + bits + order;
    case H5T_STRING:
      return std::string(H5Tis_variable_str(type) > 0 ? "vlen-string" : "fixed-string") +
             (H5Tget_cset(type) == H5T_CSET_UTF8 ? "(utf-8)" : "(ascii)");
    case H5T_COMPOUND: {
      std::string text = "compound{";
      for (int i = 0; i < H5Tget_nmembers(type); ++i) {
        char* name = H5Tget_member_name(type, static_cast<unsigned>(i));
        const hid_t member = H5Tget_member_type(type, static_cast<unsigned>(i));
        text += (i > 0 ? ", " : "") + std::string(name) + ":" + type_text(member);
        H5Tclose(member);
        H5free_memory(name);
      }
      return text + "}";
    }
    default:
      return "other";
  }
}

std::string space_text(hid_t space) {
  if (H5Sget_simple_extent_type(space) == H5S_SCALAR) return "scalar";
  std::vector<hsize_t> shape(static_cast<std::size_t>(H5Sget_simple_extent_ndims(space)));
  H5Sget_simple_extent_dims(space, shape.data(), nullptr);
  std::string text = "[";
  for (std::size_t i = 0; i < shape.size(); ++i) text += (i > 0 ? " x " : "") + std::to_string(shape[i]);
  return text + "]";
}

std::string attribute_values(hid_t attribute, hid_t type, hid_t space) {
  const auto count = static_cast<std::size_t>(H5Sget_simple_extent_npoints(space));
  std::ostringstream text;
  text.precision(17);
  const auto list = [&](const auto& values) {
    for (std::size_t i = 0; i < values.size(); ++i) text << (i > 0 ? ", " : "") << values[i];
  };
  switch (H5Tget_class(type)) {
    case H5T_STRING: {
      std::vector<char*> values(count);
      H5Aread(attribute, type, values.data());
      std::vector<std::string> quoted;
      for (char* value : values) quoted.push_back('"' + std::string(value) + '"');
      list(quoted);
      for (char* value : values) H5free_memory(value);
      break;
    }
    case H5T_FLOAT: {
      std::vector<double> values(count);
      H5Aread(attribute, H5T_NATIVE_DOUBLE, values.data());
      list(values);
      break;
    }
    default: {
      std::vector<long long> values(count);
      H5Aread(attribute, H5T_NATIVE_LLONG, values.data());
      list(values);
    }
  }
  return text.str();
}

herr_t collect_name(hid_t, const char* name, const H5A_info_t*, void* names) {
  static_cast<std::vector<std::string>*>(names)->push_back(name);
  return 0;
}

void dump_attributes(hid_t object, const std::string& path, std::string& dump) {
  std::vector<std::string> names;
  H5Aiterate2(object, H5_INDEX_NAME, H5_ITER_INC, nullptr, collect_name, &names);
  for (const std::string& name : names) {
    const hid_t attribute = H5Aopen(object, name.c_str(), H5P_DEFAULT);
    const hid_t type = H5Aget_type(attribute);
    const hid_t space = H5Aget_space(attribute);
    dump += path + "@" + name + " " + type_text(type) + " " + space_text(space) + " = " +
            attribute_values(attribute, type, space) + "\n";
    H5Sclose(space);
    H5Tclose(type);
    H5Aclose(attribute);
  }
}

void dump_object(hid_t object, const std::string& path, std::string& dump) {
  if (H5Iget_type(object) == H5I_DATASET) {
    const hid_t type = H5Dget_type(object);
    const hid_t space = H5Dget_space(object);
    dump += path + " dataset " + type_text(type) + " " + space_text(space) + "\n";
    H5Sclose(space);
    H5Tclose(type);
    dump_attributes(object, path, dump);
    return;
  }
  dump += path + " group\n";
  dump_attributes(object, path, dump);
  H5G_info_t info{};
  H5Gget_info(object, &info);
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    char name[256];
    H5Lget_name_by_idx(object, ".", H5_INDEX_NAME, H5_ITER_INC, i, name, sizeof name, H5P_DEFAULT);
    const hid_t member = H5Oopen(object, name, H5P_DEFAULT);
    dump_object(member, (path == "/" ? "/" : path + "/") + name, dump);
    H5Oclose(member);
  }
}

std::string layout_of(const std::string& path) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  std::string dump;
  dump_object(file, "/", dump);
  H5Fclose(file);
  return dump;
}

TEST_F(ResultsFile, LayoutMatchesGolden) {
  write_results_h5(sample_results(), path_, false);
  const std::string layout = layout_of(path_);
  const fs::path golden = fs::path(FX2D_SOURCE_DIR) / "goldens" / "results_layout.txt";
  const char* update = std::getenv("FX2D_UPDATE_GOLDENS");
  if (update != nullptr && std::string(update) == "1") {
    write_text(golden, layout);
    GTEST_SKIP() << "regenerated " << golden;
  }
  ASSERT_TRUE(fs::exists(golden)) << golden << " is missing; regenerate it as this file's header says";
  EXPECT_EQ(layout, file_text(golden))
      << "the result-file layout changed; if deliberately, regenerate " << golden
      << " as this file's header says and update RESULTS_FORMAT.md";
}

// A run counted with --counter instructions; the count is near the top of uint64, where a
// round trip through a double would lose its last digits.
ResultSet counted_results() {
  ResultSet results = sample_results();
  results.runs[0].instruction_count =
      InstructionCount{std::numeric_limits<std::uint64_t>::max() - 12345, 3, "callgrind", "valgrind-3.19.0"};
  return results;
}

TEST_F(ResultsFile, InstructionCountRoundTripsExactlyAndIsAbsentWhereNotCounted) {
  const ResultSet written = counted_results();
  write_results_h5(written, path_, false);
  const ResultSet read = read_results_h5(path_);
  ASSERT_TRUE(read.runs[0].instruction_count.has_value());
  EXPECT_EQ(*read.runs[0].instruction_count, *written.runs[0].instruction_count);
  EXPECT_FALSE(read.runs[1].instruction_count.has_value());
  EXPECT_TRUE(read == written);
}

TEST_F(ResultsFile, InstructionCountIsOneScalarDatasetWithItsProvenance) {
  write_results_h5(counted_results(), path_, false);
  const std::string layout = layout_of(path_);
  const std::string counted =
      "/runs/0/instructions dataset uint64le scalar\n"
      "/runs/0/instructions@steps int32le scalar = 3\n"
      "/runs/0/instructions@tool vlen-string(utf-8) scalar = \"callgrind\"\n"
      "/runs/0/instructions@tool_version vlen-string(utf-8) scalar = \"valgrind-3.19.0\"\n"
      "/runs/0/instructions@units vlen-string(utf-8) scalar = \"instructions\"\n";
  EXPECT_NE(layout.find(counted), std::string::npos) << layout;
  EXPECT_EQ(layout.find("/runs/1/instructions"), std::string::npos) << layout;
}

TEST_F(ResultsFile, MalformedInstructionCountIsNamed) {
  write_results_h5(counted_results(), path_, false);
  const hid_t file = H5Fopen(path_.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  H5Adelete_by_name(file, "/runs/0/instructions", "steps", H5P_DEFAULT);
  H5Fclose(file);
  seal_h5_file(path_);
  expect_one_line_naming(read_error(path_), path_, "/runs/0/instructions: missing attribute 'steps'");
}

TEST_F(ResultsFile, H5pyReadsTheFile) {
  if (std::system("/usr/bin/python3 -c 'import h5py' >/dev/null 2>&1") != 0) {
    GTEST_SKIP() << "/usr/bin/python3 with h5py is not installed";
  }
  const ResultSet results = sample_results();
  write_results_h5(results, path_, false);
  std::ostringstream script;
  script.precision(17);
  script << "import sys, h5py\n"
         << "f = h5py.File(sys.argv[1], 'r')\n"
         << "assert f.attrs['schema'] == 'fx2d-bench.results/1', f.attrs['schema']\n"
         << "wall = f['runs/0/wall_ms']\n"
         << "assert wall.shape == (2, 3), wall.shape\n"
         << "assert wall.attrs['units'] == 'ms'\n"
         << "assert wall[1, 2] == " << results.runs[0].wall_ms[5] << ", wall[1, 2]\n"
         << "assert f['runs/0/phase_ms'].shape == (2, 3, 3)\n"
         << "assert list(f['runs/0/phase_ms'].attrs['phase_names']) == ['collide', 'solve', 'integrate']\n"
         << "assert f['runs/0/accuracy']['kinetic_energy'][1] == 1e300\n"
         << "assert f['runs/0/state_hashes'].asstr()[1] == '0123456789abcdef'\n"
         << "assert 'phase_ms' not in f['runs/1']\n";
  const fs::path script_path = directory_ / "check.py";
  write_text(script_path, script.str());
  EXPECT_EQ(std::system(("/usr/bin/python3 " + script_path.string() + " " + path_).c_str()), 0);
}

}  // namespace
}  // namespace fxbench
