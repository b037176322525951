// End-to-end test of `fx2d-bench sweep`: a 2-point grid on the smallest contact scene, checked
// through --json (schema, the default added to the grid and marked, fronts consistent with the
// points' flags, each point's cost against the default's worked out again from the stored steps)
// and through the /sweep table of the --out file.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

namespace fxbench {
namespace {

namespace fs = std::filesystem;

struct Outcome {
  int exit_code = -1;
  std::string out;
};

Outcome run_bench(const std::string& arguments) {
  const std::string command = std::string(FX2D_BENCH_EXE) + " " + arguments + " 2>/dev/null";
  FILE* pipe = popen(command.c_str(), "r");
  Outcome outcome;
  if (pipe == nullptr) return outcome;
  char buffer[4096];
  std::size_t read = 0;
  while ((read = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) outcome.out.append(buffer, read);
  const int status = pclose(pipe);
  outcome.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return outcome;
}

long rows_of(hid_t file, const char* dataset_path) {
  const hid_t dataset = H5Dopen2(file, dataset_path, H5P_DEFAULT);
  if (dataset < 0) return -1;
  const hid_t space = H5Dget_space(dataset);
  const long rows = H5Sget_simple_extent_npoints(space);
  H5Sclose(space);
  H5Dclose(dataset);
  return rows;
}

// A one-dimensional dataset read as T, which `memory_type` (H5T_NATIVE_INT, H5T_NATIVE_DOUBLE) names.
template <class T>
std::vector<T> column_of(hid_t file, const char* dataset_path, hid_t memory_type) {
  std::vector<T> values(static_cast<std::size_t>(rows_of(file, dataset_path)));
  const hid_t dataset = H5Dopen2(file, dataset_path, H5P_DEFAULT);
  H5Dread(dataset, memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
  H5Dclose(dataset);
  return values;
}

std::vector<double> double_column(hid_t file, const char* dataset_path) {
  return column_of<double>(file, dataset_path, H5T_NATIVE_DOUBLE);
}

std::vector<int> int_column(hid_t file, const char* dataset_path) {
  return column_of<int>(file, dataset_path, H5T_NATIVE_INT);
}

TEST(SweepCommand, TwoPointGridGetsTheDefaultAddedAndConsistentFronts) {
  const fs::path out = fs::temp_directory_path() / ("sweep_test_" + std::to_string(getpid()) + ".h5");
  const std::string scene = std::string(FX2D_SOURCE_DIR) + "/scenes/tests/single_box_on_ground.json";
  const Outcome outcome = run_bench("sweep " + scene + " --engine fx2d --fx2d-substeps 2,4 --fx2d-passes 1 --repeats 2 --json --out " +
                                    out.string() + " --force");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.out;
  const auto json = nlohmann::json::parse(outcome.out);
  EXPECT_EQ(json["schema"], "fx2d-bench.sweep/1");

  // substeps 2 and 4 at 1 pass, then the scene's own 8 x 1, which the grid lacks.
  const auto& points = json["points"];
  ASSERT_EQ(points.size(), 3u);
  EXPECT_EQ(points[0]["settings"]["substeps"], 2);
  EXPECT_EQ(points[1]["settings"]["substeps"], 4);
  EXPECT_EQ(points[2]["settings"]["substeps"], 8);
  EXPECT_EQ(points[2]["settings"]["velocity_passes"], 1);
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_EQ(points[i]["default"], i == 2);
    EXPECT_EQ(points[i]["primary_metric"], "displacement");
    EXPECT_EQ(points[i]["primary_error"], points[i]["accuracy"]["max_displacement"]);
    const auto& ms = points[i]["ms_per_step"];
    EXPECT_LE(ms["ci_low"].get<double>(), ms["median"].get<double>());
    EXPECT_LE(ms["median"].get<double>(), ms["ci_high"].get<double>());
    // A point is on the front exactly when nothing dominates it.
    EXPECT_EQ(points[i]["on_front"].get<bool>(), points[i]["dominated_by"].is_null());
  }

  // One front for the one engine; its members are exactly the points flagged on_front, fastest
  // first, and each is more accurate than the one before.
  ASSERT_EQ(json["fronts"].size(), 1u);
  const auto& front = json["fronts"][0]["points"];
  std::size_t flagged = 0;
  for (const auto& point : points) flagged += point["on_front"].get<bool>() ? 1 : 0;
  ASSERT_EQ(front.size(), flagged);
  for (std::size_t k = 1; k < front.size(); ++k) {
    const auto& before = points[front[k - 1].get<std::size_t>()];
    const auto& after = points[front[k].get<std::size_t>()];
    EXPECT_LE(before["ms_per_simulated_s"].get<double>(), after["ms_per_simulated_s"].get<double>());
    EXPECT_GT(before["primary_error"].get<double>(), after["primary_error"].get<double>());
  }

  const hid_t file = H5Fopen(out.string().c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  EXPECT_EQ(rows_of(file, "/sweep/ms_per_step"), 3);
  EXPECT_EQ(rows_of(file, "/sweep/fx2d_substeps"), 3);
  EXPECT_EQ(rows_of(file, "/runs/2/wall_ms"), 2 * 60);  // repeats x steps of the default's run
  EXPECT_GT(H5Aexists(file, "schema"), 0);

  // Each point's cost against the default's, from the steps the file keeps: per round, the mean
  // step time over dt; per point, the median of its two rounds' ratios to the default's, their mean.
  const std::vector<double> ratios = double_column(file, "/sweep/cost_vs_default");
  ASSERT_EQ(ratios.size(), 3u);
  const auto round_costs = [&](std::size_t point) {
    const std::vector<double> steps =
        double_column(file, ("/runs/" + std::to_string(point) + "/wall_ms").c_str());
    const double dt = points[point]["dt"].get<double>();
    double first = 0.0, second = 0.0;
    for (std::size_t step = 0; step < 60; ++step) first += steps[step], second += steps[60 + step];
    return std::pair{first / 60.0 / dt, second / 60.0 / dt};
  };
  const auto [default_first, default_second] = round_costs(2);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto [first, second] = round_costs(i);
    const double expected = (first / default_first + second / default_second) / 2.0;
    const auto& versus = points[i]["cost_vs_default"];
    EXPECT_NEAR(versus["ratio"].get<double>(), expected, 1e-9 * expected) << "point " << i;
    EXPECT_NEAR(ratios[i], expected, 1e-9 * expected) << "point " << i;
    EXPECT_LE(versus["ci_low"].get<double>(), versus["ratio"].get<double>());
    EXPECT_LE(versus["ratio"].get<double>(), versus["ci_high"].get<double>());
  }
  EXPECT_EQ(points[2]["cost_vs_default"]["ratio"], 1.0);
  H5Fclose(file);
  fs::remove(out);
}

// relax_passes is an optional key that scenes leave out. Swept, the point at Fx2D's default is the
// scene's own: marked default, no extra point, and the same scene hash as a sweep that leaves the
// knob alone. Three boxes sunk into each other: two relaxation passes leave more of the soft
// spring's velocity than four, so the knob visibly reaches the engine.
TEST(SweepCommand, SweepsRelaxationPassesWhenAskedAndKeepsTheSceneItselfAsTheDefault) {
  const fs::path directory = fs::temp_directory_path() / ("sweep_test_relax_" + std::to_string(getpid()));
  fs::create_directories(directory);
  const fs::path scene = directory / "overlapping_boxes.json";
  std::FILE* file = std::fopen(scene.string().c_str(), "w");
  // The shallow schedule off: this short, slow column would take one rigid pass whatever the grid says.
  std::fputs(R"({"schema": "fx2d.scene/1", "steps": 120, "primary_metric": "displacement",
    "solver": {"fx2d": {"shallow_schedule": false}},
    "generators": [{"type": "ground", "top": 0, "half_width": 5}],
    "bodies": [{"shape": {"box": [0.5, 0.5]}, "position": [0, 0.2]},
               {"shape": {"box": [0.5, 0.5]}, "position": [0, 0.9]},
               {"shape": {"box": [0.5, 0.5]}, "position": [0, 1.6]}]})",
             file);
  std::fclose(file);
  const fs::path out = directory / "sweep.h5";
  const std::string grid =
      "sweep " + scene.string() + " --engine fx2d --fx2d-substeps 8 --fx2d-passes 1 --repeats 1 --json";
  const Outcome relaxed = run_bench(grid + " --fx2d-relax 3,4 --out " + out.string());
  const Outcome plain = run_bench(grid);
  ASSERT_EQ(relaxed.exit_code, 0) << relaxed.out;
  ASSERT_EQ(plain.exit_code, 0) << plain.out;

  const auto points = nlohmann::json::parse(relaxed.out)["points"];
  ASSERT_EQ(points.size(), 2u);
  EXPECT_EQ(points[0]["settings"]["relax_passes"], 3);
  EXPECT_EQ(points[1]["settings"]["relax_passes"], 4);
  // The engine's own three relaxation passes are the default point, and the scene without the key is it.
  EXPECT_TRUE(points[0]["default"].get<bool>());
  EXPECT_FALSE(points[1]["default"].get<bool>());
  const auto plain_default = nlohmann::json::parse(plain.out)["points"][0];
  EXPECT_FALSE(plain_default["settings"].contains("relax_passes"));
  EXPECT_EQ(points[0]["scene_hash"], plain_default["scene_hash"]);
  EXPECT_NE(points[1]["scene_hash"], plain_default["scene_hash"]);
  EXPECT_EQ(points[0]["primary_error"], plain_default["primary_error"]);
  EXPECT_NE(points[0]["primary_error"].get<double>(), points[1]["primary_error"].get<double>());

  const hid_t h5 = H5Fopen(out.string().c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(h5, 0);
  EXPECT_EQ(int_column(h5, "/sweep/fx2d_relax_passes"), (std::vector<int>{3, 4}));
  H5Fclose(h5);
  fs::remove_all(directory);
}

TEST(SweepCommand, NamingOneKnobOfAnEngineHoldsItsOthersAtTheScenesValues) {
  // A scaling sweep: only the workers vary, Fx2D's substeps and passes stay the scene's own; Box2D,
  // none of whose knobs is named, keeps its default grid (6 x 3 points, the scene's own among them).
  const std::string scene = std::string(FX2D_SOURCE_DIR) + "/scenes/tests/single_box_on_ground.json";
  const Outcome outcome = run_bench(
      "sweep " + scene + " --engine fx2d,box2d --axis fx2d.workers=1,2 --steps 20 --repeats 1 --json");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.out;
  const auto points = nlohmann::json::parse(outcome.out)["points"];
  std::vector<nlohmann::json> fx2d_settings;
  int box2d_points = 0;
  for (const auto& point : points) {
    if (point["engine"] == "fx2d") fx2d_settings.push_back(point["settings"]);
    box2d_points += point["engine"] == "box2d" ? 1 : 0;
  }
  ASSERT_EQ(fx2d_settings.size(), 2u);
  EXPECT_EQ(fx2d_settings[0], (nlohmann::json{{"workers", 1}}));
  EXPECT_EQ(fx2d_settings[1], (nlohmann::json{{"workers", 2}}));
  EXPECT_EQ(box2d_points, 18);
  // Timings of threads move with how fast the cores hand a cache line over: the sweep records it,
  // where there are two cores to hand it between.
  const auto machine = nlohmann::json::parse(outcome.out)["machine"];
  const bool two_cores = std::thread::hardware_concurrency() >= 2;
  EXPECT_EQ(machine["core_round_trip_ns_start"].get<double>() > 0.0, two_cores) << machine;
  EXPECT_EQ(machine["core_round_trip_ns_end"].get<double>() > 0.0, two_cores) << machine;

  // A short form names its knob as --axis does: the passes alone, at the scene's 8 substeps.
  const Outcome passes =
      run_bench("sweep " + scene + " --engine fx2d --fx2d-passes 2,4 --steps 20 --repeats 1 --json");
  ASSERT_EQ(passes.exit_code, 0) << passes.out;
  const auto pass_points = nlohmann::json::parse(passes.out)["points"];
  ASSERT_EQ(pass_points.size(), 3u);  // 2 and 4, then the scene's own 1
  EXPECT_EQ(pass_points[0]["settings"], (nlohmann::json{{"velocity_passes", 2}}));
  EXPECT_EQ(pass_points[1]["settings"], (nlohmann::json{{"velocity_passes", 4}}));
  EXPECT_EQ(pass_points[2]["settings"], (nlohmann::json{{"velocity_passes", 1}}));
  EXPECT_TRUE(pass_points[2]["default"].get<bool>());
}

TEST(SweepCommand, RefusesAnExistingOutWithoutForce) {
  const fs::path out = fs::temp_directory_path() / ("sweep_test_exists_" + std::to_string(getpid()) + ".h5");
  { std::FILE* file = std::fopen(out.string().c_str(), "w"); std::fclose(file); }
  const Outcome outcome = run_bench("sweep stacks --bodies 10 --engine fx2d --fx2d-substeps 1 --fx2d-passes 1 --out " + out.string());
  EXPECT_EQ(outcome.exit_code, 2);
  EXPECT_EQ(fs::file_size(out), 0u);
  fs::remove(out);
}

TEST(SweepCommand, AThreadSweepSaysHowFastTheCoresHandedALineOverAndNoOtherDoes) {
  if (std::thread::hardware_concurrency() < 2) GTEST_SKIP() << "one hardware thread: nothing to hand over";
  const std::string scene = std::string(FX2D_SOURCE_DIR) + "/scenes/tests/single_box_on_ground.json";
  const std::string line = "the machine: a cache line went from one core to another and back in ";
  const Outcome threads =
      run_bench("sweep " + scene + " --engine fx2d --axis fx2d.workers=1,2 --steps 20 --repeats 1");
  ASSERT_EQ(threads.exit_code, 0) << threads.out;
  EXPECT_NE(threads.out.find(line), std::string::npos) << threads.out;
  const Outcome substeps =
      run_bench("sweep " + scene + " --engine fx2d --axis fx2d.substeps=4,8 --steps 20 --repeats 1");
  ASSERT_EQ(substeps.exit_code, 0) << substeps.out;
  EXPECT_EQ(substeps.out.find(line), std::string::npos) << substeps.out;
}

}  // namespace
}  // namespace fxbench
