// Tests of the stability suite (stability_tests.h): each pass criterion on hand-built poses, on
// both sides of its limit; the bracket-and-bisect search on synthetic monotone predicates with a
// known threshold; and one real search on fx2d, small enough to run in a few seconds.
#include "analysis/stability_tests.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

namespace fxbench {
namespace {

BodySpec box_at(double x, double y, BodyType type = BodyType::dynamic) {
  BodySpec body;
  body.type = type;
  body.position = {x, y};
  return body;
}

std::vector<BodyState> start_of(const SceneSpec& scene) {
  std::vector<BodyState> states;
  for (const BodySpec& body : scene.bodies) states.push_back({body.position, body.angle, {}, 0.0});
  return states;
}

// The scene's start at t = 0, then `later` at t = `duration`.
Trajectory from_start_to(const SceneSpec& scene, std::vector<BodyState> later, double duration = 1.0) {
  return {{0.0, duration}, {start_of(scene), std::move(later)}};
}

// ---- stays_in_place ----

TEST(StaysInPlace, PassesWithinTheLimitAndFailsBeyondIt) {
  SceneSpec scene;
  scene.bodies = {box_at(0, 0.5)};
  auto moved = start_of(scene);
  moved[0].position.x += 0.4;
  EXPECT_TRUE(stays_in_place(scene, from_start_to(scene, moved), 0.5, 0.5).pass);
  moved[0].position.x += 0.2;
  const Verdict verdict = stays_in_place(scene, from_start_to(scene, moved), 0.5, 0.5);
  EXPECT_FALSE(verdict.pass);
  EXPECT_NE(verdict.reason.find("moved 0.6 m"), std::string::npos) << verdict.reason;
}

TEST(StaysInPlace, FailsOnATurnBeyondTheLimit) {
  SceneSpec scene;
  scene.bodies = {box_at(0, 0.5)};
  auto turned = start_of(scene);
  turned[0].angle = 0.6;
  EXPECT_FALSE(stays_in_place(scene, from_start_to(scene, turned), 0.5, 0.5).pass);
}

TEST(StaysInPlace, MeasuresTurnsAcrossTheAngleWrap) {
  // From 3.1 rad to -3.1 rad is a turn of 2 pi - 6.2 = 0.083 rad, not 6.2 rad.
  SceneSpec scene;
  scene.bodies = {box_at(0, 0.5)};
  scene.bodies[0].angle = 3.1;
  auto wrapped = start_of(scene);
  wrapped[0].angle = -3.1;
  EXPECT_TRUE(stays_in_place(scene, from_start_to(scene, wrapped), 0.5, 0.1).pass);
}

TEST(StaysInPlace, IgnoresStaticBodies) {
  SceneSpec scene;
  scene.bodies = {box_at(0, -0.5, BodyType::static_body)};
  auto moved = start_of(scene);
  moved[0].position.y = 100.0;
  EXPECT_TRUE(stays_in_place(scene, from_start_to(scene, moved), 0.1, 0.1).pass);
}

// ---- top_holds ----

TEST(TopHolds, JudgesTheTopsSinkAgainstTheStackHeight) {
  // Three unit boxes from y = 0 to y = 3: a 1% limit allows the top to sink 3 cm.
  SceneSpec scene;
  scene.bodies = {box_at(0, -0.5, BodyType::static_body), box_at(0, 0.5), box_at(0, 1.5), box_at(0, 2.5)};
  auto sunk = start_of(scene);
  sunk[3].position.y -= 0.02;
  EXPECT_TRUE(top_holds(scene, from_start_to(scene, sunk), 0.01).pass);
  sunk[3].position.y -= 0.02;
  EXPECT_FALSE(top_holds(scene, from_start_to(scene, sunk), 0.01).pass);
}

// ---- slides_as_coulomb_predicts ----

// Gravity 10 m/s^2 tilted by 30 degrees; a box of friction 0.9 (above tan 30 = 0.577), one of 0.2
// (below), one of 0.57 (within the 0.02 margin, so unjudged).
SceneSpec ramp_scene() {
  const double angle = std::numbers::pi / 6.0;
  SceneSpec scene;
  scene.gravity = {10.0 * std::sin(angle), -10.0 * std::cos(angle)};
  for (double mu : {0.9, 0.2, 0.57}) {
    scene.bodies.push_back(box_at(0, 3.0 * static_cast<double>(scene.bodies.size())));
    scene.bodies.back().material.dynamic_friction = mu;
  }
  return scene;
}

// Final poses after 2 s: the 0.2 box has slid `slid` metres, the 0.9 box `crept`.
Trajectory ramp_run(const SceneSpec& scene, double slid, double crept) {
  auto end = start_of(scene);
  end[0].position.x += crept;
  end[1].position.x += slid;
  end[2].position.x += 50.0;
  return from_start_to(scene, end, 2.0);
}

TEST(SlidesAsCoulombPredicts, PassesTheExactSlideAndFailsOneTenPercentLong) {
  const SceneSpec scene = ramp_scene();
  // a = g (sin 30 - 0.2 cos 30) = 3.268 m/s^2; over 2 s, x = a T^2 / 2 = 2 a.
  const double exact = 2.0 * 10.0 * (0.5 - 0.2 * std::sqrt(3.0) / 2.0);
  EXPECT_TRUE(slides_as_coulomb_predicts(scene, ramp_run(scene, exact, 0.0), RampTolerances{}).pass);
  // 10% more than predicted exceeds the 5% + 0.05 m/s^2 tolerance (0.21 m/s^2 of 3.27).
  EXPECT_FALSE(slides_as_coulomb_predicts(scene, ramp_run(scene, 1.1 * exact, 0.0), RampTolerances{}).pass);
}

TEST(SlidesAsCoulombPredicts, FailsWhenABoxAboveTheFrictionAngleCreeps) {
  const SceneSpec scene = ramp_scene();
  const double exact = 2.0 * 10.0 * (0.5 - 0.2 * std::sqrt(3.0) / 2.0);
  EXPECT_TRUE(slides_as_coulomb_predicts(scene, ramp_run(scene, exact, 0.04), RampTolerances{}).pass);
  const Verdict verdict = slides_as_coulomb_predicts(scene, ramp_run(scene, exact, 0.1), RampTolerances{});
  EXPECT_FALSE(verdict.pass);
  EXPECT_NE(verdict.reason.find("mu = 0.90"), std::string::npos) << verdict.reason;
}

// ---- recovers_from_overlap ----

TEST(RecoversFromOverlap, FailsOnALaunchAndOnAnOverlapLeftAtTheEnd) {
  SceneSpec scene;
  scene.bodies = {box_at(0, -0.5, BodyType::static_body), box_at(0, 0.45)};
  auto settled = start_of(scene);
  settled[1].position.y = 0.5;
  EXPECT_TRUE(recovers_from_overlap(scene, from_start_to(scene, settled), 3.0, 0.02).pass);

  auto launched = settled;
  launched[1].linear_velocity.y = 3.5;
  EXPECT_FALSE(recovers_from_overlap(scene, from_start_to(scene, launched), 3.0, 0.02).pass);

  // Still 5 cm into the ground after the run: beyond a 2 cm limit.
  auto stuck = settled;
  stuck[1].position.y = 0.45;
  const Verdict verdict = recovers_from_overlap(scene, from_start_to(scene, stuck), 3.0, 0.02);
  EXPECT_FALSE(verdict.pass);
  EXPECT_NE(verdict.reason.find("0.05 m"), std::string::npos) << verdict.reason;
}

// ---- stays_on_its_side ----

TEST(StaysOnItsSide, FailsOnlyOnceTheBodyCrossesTheWallsMidPlane) {
  SceneSpec scene;
  scene.bodies = {box_at(0, 0, BodyType::static_body), box_at(-2, 0)};
  auto stopped = start_of(scene);
  stopped[1].position.x = -0.01;
  EXPECT_TRUE(stays_on_its_side(scene, from_start_to(scene, stopped)).pass);
  auto through = start_of(scene);
  through[1].position.x = 0.01;
  EXPECT_FALSE(stays_on_its_side(scene, from_start_to(scene, through)).pass);
}

TEST(StaysOnItsSide, AFloorWiderThanTallIsCrossedDownward) {
  SceneSpec scene;
  scene.bodies = {box_at(0, 0, BodyType::static_body), box_at(3, 2)};
  scene.bodies[0].half_extents = {5.0, 0.01};
  auto beside = start_of(scene);
  beside[1].position = {-3.0, 0.01};  // crossed x = 0, which is no wall here
  EXPECT_TRUE(stays_on_its_side(scene, from_start_to(scene, beside)).pass);
  auto through = start_of(scene);
  through[1].position.y = -0.01;
  const Verdict verdict = stays_on_its_side(scene, from_start_to(scene, through));
  EXPECT_FALSE(verdict.pass);
  EXPECT_NE(verdict.reason.find("floor"), std::string::npos) << verdict.reason;
  // What failed first and when: the sample at t = 1 s is step 60 of 1/60 s.
  EXPECT_EQ(verdict.criterion, "crossed");
  EXPECT_EQ(verdict.step, 60);
}

// ---- joints_hold ----

TEST(JointsHold, MeasuresTheGapBetweenWorldAnchors) {
  // Two links joined end to end at x = 0.5: anchors (0.5, 0) on a and (-0.5, 0) on b.
  SceneSpec scene;
  scene.bodies = {box_at(0, 0), box_at(1, 0)};
  scene.joints = {{JointKind::revolute, 0, 1, {0.5, 0.0}, {-0.5, 0.0}, -1.0}};
  auto pulled = start_of(scene);
  pulled[1].position.x = 1.05;
  EXPECT_TRUE(joints_hold(scene, from_start_to(scene, pulled), 0.1).pass);
  pulled[1].position.x = 1.2;
  EXPECT_FALSE(joints_hold(scene, from_start_to(scene, pulled), 0.1).pass);
  // Turned half a turn about its centre, b's anchor swings to (1.5, 0): a gap of 1 m.
  auto flipped = start_of(scene);
  flipped[1].angle = std::numbers::pi;
  const Verdict verdict = joints_hold(scene, from_start_to(scene, flipped), 0.1);
  EXPECT_FALSE(verdict.pass);
  EXPECT_NE(verdict.reason.find("opened 1 m"), std::string::npos) << verdict.reason;
}

// ---- find_boundary ----

std::function<Verdict(double)> passes_below(double threshold) {
  return [threshold](double value) { return value < threshold ? Verdict{} : Verdict{false, "too hard", "hard", std::nullopt}; };
}

TEST(FindBoundary, BracketsALinearThresholdToTheResolution) {
  const double threshold = 0.3141;
  const SearchResult result = find_boundary({0.01, 1.0, 0.001, Harder::increasing, Scale::linear, false}, passes_below(threshold));
  ASSERT_EQ(result.outcome, Outcome::boundary);
  EXPECT_LT(*result.last_pass, threshold);
  EXPECT_GE(*result.first_fail, threshold);
  EXPECT_LE(*result.first_fail - *result.last_pass, 0.001);
}

TEST(FindBoundary, BracketsAGeometricThresholdToTheRelativeResolution) {
  const double threshold = 777.0;
  const SearchResult result = find_boundary({1, 10000, 0.05, Harder::increasing, Scale::geometric, false}, passes_below(threshold));
  ASSERT_EQ(result.outcome, Outcome::boundary);
  EXPECT_LT(*result.last_pass, threshold);
  EXPECT_GE(*result.first_fail, threshold);
  EXPECT_LE(*result.first_fail / *result.last_pass, 1.05);
}

TEST(FindBoundary, FindsAnIntegerThresholdExactlyAndTriesOnlyWholeValues) {
  const SearchResult result = find_boundary({4, 128, 1, Harder::increasing, Scale::linear, true}, passes_below(42));
  ASSERT_EQ(result.outcome, Outcome::boundary);
  EXPECT_EQ(*result.last_pass, 41.0);
  EXPECT_EQ(*result.first_fail, 42.0);
  for (const Evaluation& evaluation : result.evaluations) EXPECT_EQ(evaluation.parameter, std::floor(evaluation.parameter));
}

TEST(FindBoundary, SearchesDownwardWhenLowerIsHarder) {
  // A card house that needs friction 0.183: passes at or above it.
  const auto holds = [](double friction) { return friction >= 0.183 ? Verdict{} : Verdict{false, "slid", "slid", std::nullopt}; };
  const SearchResult result = find_boundary({1, 0.01, 0.01, Harder::decreasing, Scale::linear, false}, holds);
  ASSERT_EQ(result.outcome, Outcome::boundary);
  EXPECT_GE(*result.last_pass, 0.183);
  EXPECT_LT(*result.first_fail, 0.183);
  EXPECT_LE(*result.last_pass - *result.first_fail, 0.01);
}

TEST(FindBoundary, ReportsHoldingToTheLimitAfterTryingItExactly) {
  const SearchResult result = find_boundary({5, 40, 0.5, Harder::increasing, Scale::linear, false}, passes_below(1e9));
  EXPECT_EQ(result.outcome, Outcome::holds_to_limit);
  EXPECT_EQ(*result.last_pass, 40.0);
  EXPECT_EQ(result.evaluations.back().parameter, 40.0);
  EXPECT_FALSE(result.first_fail.has_value());
}

TEST(FindBoundary, ReportsFailingAtTheStart) {
  const SearchResult result = find_boundary({5, 40, 0.5, Harder::increasing, Scale::linear, false}, passes_below(1));
  EXPECT_EQ(result.outcome, Outcome::fails_at_start);
  EXPECT_EQ(result.evaluations.size(), 1u);
  EXPECT_FALSE(result.last_pass.has_value());
}

TEST(FindBoundary, TriesTheSameSequenceEveryTime) {
  const SearchSpec spec{1, 10000, 0.1, Harder::increasing, Scale::geometric, false};
  const SearchResult first = find_boundary(spec, passes_below(123.0));
  const SearchResult second = find_boundary(spec, passes_below(123.0));
  ASSERT_EQ(first.evaluations.size(), second.evaluations.size());
  for (std::size_t i = 0; i < first.evaluations.size(); ++i)
    EXPECT_EQ(first.evaluations[i].parameter, second.evaluations[i].parameter);
}

// ---- a real search ----

const StabilityTest& suite_test(const std::string& name) {
  for (const StabilityTest& test : stability_suite())
    if (test.name == name) return test;
  throw std::runtime_error("no stability test " + name);
}

// The speed tests stop at the fastest body an engine builds: holding there is "engine limit at X",
// failing below it is a boundary as on any engine, and an engine faster than the test's limit
// holds to the test's limit.
TEST(StabilitySuite, ASpeedTestStopsAtTheEnginesFastestBody) {
  const StabilityTest& test = suite_test("thin_wall");
  ASSERT_EQ(test.search.limit, 1000.0);
  auto search = [&](double engine_speed, double tunnels_above) {
    EngineCapabilities capabilities;
    capabilities.max_linear_speed = engine_speed;
    SearchSpec spec = test.search;
    SearchResult result = find_engine_boundary(test, spec, capabilities, passes_below(tunnels_above));
    return std::pair{result, spec.limit};
  };
  const auto [capped, capped_limit] = search(400.0, 1e9);
  EXPECT_EQ(capped.outcome, Outcome::engine_limit);
  EXPECT_EQ(capped_limit, 400.0);
  EXPECT_EQ(*capped.last_pass, 400.0);
  const auto [tunnels, tunnels_limit] = search(400.0, 300.0);
  EXPECT_EQ(tunnels.outcome, Outcome::boundary);
  EXPECT_LE(*tunnels.last_pass, 300.0);
  const auto [holds, holds_limit] = search(1000.0, 1e9);
  EXPECT_EQ(holds.outcome, Outcome::holds_to_limit);
  EXPECT_EQ(holds_limit, 1000.0);
  EXPECT_EQ(*holds.last_pass, 1000.0);
}

TEST(StabilitySuite, Fx2dThinWallSearchFindsATunnellingSpeedAboveTheDiscreteBound) {
  const StabilityTest& test = suite_test("thin_wall");
  const EngineInfo* fx2d = find_engine("fx2d");
  ASSERT_NE(fx2d, nullptr);
  SearchSpec spec = test.search;
  spec.limit = 40.0;
  const auto evaluate = [&](double speed) {
    const SceneSpec scene = load_test_scene(test, FX2D_SOURCE_DIR "/scenes/stability", {}, speed);
    return test.judge(scene, simulate(scene, *fx2d, test.sample_every));
  };
  const SearchResult result = find_boundary(spec, evaluate);
  ASSERT_NE(result.outcome, Outcome::fails_at_start);
  // Starting clear of the wall (centre 0.1 m or more before its mid-plane: half its 0.1 m
  // thickness plus the 0.05 m radius), no discrete step can carry the centre past the mid-plane
  // unless it travels more than 0.1 m in one 1/60 s step: below 6 m/s nothing may tunnel.
  EXPECT_GE(*result.last_pass, 6.0);
  if (result.outcome == Outcome::boundary) {
    EXPECT_LE(*result.first_fail / *result.last_pass, 1.0 + spec.resolution);
    for (const Evaluation& evaluation : result.evaluations) {
      if (evaluation.parameter == *result.first_fail) {
        EXPECT_NE(evaluation.verdict.reason.find("crossed"), std::string::npos) << evaluation.verdict.reason;
      }
    }
  }
}

TEST(StabilitySuite, Fx2dHoldsAShortStackAndSaysSo) {
  const StabilityTest& test = suite_test("vertical_stack");
  const EngineInfo* fx2d = find_engine("fx2d");
  ASSERT_NE(fx2d, nullptr);
  const SearchSpec spec{2, 8, 1, Harder::increasing, Scale::linear, true};
  const auto evaluate = [&](double height) {
    const SceneSpec scene = load_test_scene(test, FX2D_SOURCE_DIR "/scenes/stability", {}, height);
    EXPECT_EQ(scene.bodies.size(), static_cast<std::size_t>(height) + 1);  // the ground and the column
    return test.judge(scene, simulate(scene, *fx2d, test.sample_every));
  };
  const SearchResult result = find_boundary(spec, evaluate);
  EXPECT_EQ(result.outcome, Outcome::holds_to_limit);
  EXPECT_EQ(result.evaluations.size(), 3u);  // 2, 4, 8
}

// Issue 19 asks that one relaxation pass push overlaps apart without launching anything, and that
// overlap_recovery reach 0.4 of a box so: the soft spring's pushes, capped at max_push_speed / 8,
// add up down the pyramid's columns, and one rigid pass leaves about two thirds of their sum. At
// max_push_speed 4 a box left at 3.06 m/s, over the test's 3 m/s; the default must keep under it.
TEST(StabilitySuite, Fx2dRecoversFromOverlapOfFourTenthsOfABoxWithOneRelaxationPass) {
  const StabilityTest& test = suite_test("overlap_recovery");
  const EngineInfo* fx2d = find_engine("fx2d");
  ASSERT_NE(fx2d, nullptr);
  for (const char* relax_passes : {"1", "3"}) {
    const SceneSpec scene = load_test_scene(test, FX2D_SOURCE_DIR "/scenes/stability",
                                            {{"/solver/fx2d/relax_passes", relax_passes}}, 0.4);
    const Verdict verdict = test.judge(scene, simulate(scene, *fx2d, test.sample_every));
    EXPECT_TRUE(verdict.pass) << relax_passes << " relaxation passes: " << verdict.reason;
  }
}

// A simulation that stops at the first sample its test's settled_failure holds on gets the very
// verdict of the whole trajectory (reason, criterion, step): the search sees no difference, only
// the time a collapsed structure is no longer simulated. The first three fail early (the full
// golden's evaluations); a pyramid of 24 stands on Box2D and is simulated to its end.
TEST(StabilitySuite, AFailureSettledEarlyIsTheWholeTrajectorysVerdict) {
  const std::vector<std::tuple<std::string, std::string, double>> cases = {
      {"card_house", "fx2d", 0.25}, {"mass_ratio", "fx2d", 4096}, {"vertical_stack", "ode", 24}, {"pyramid", "box2d", 24}};
  for (const auto& [name, engine_name, parameter] : cases) {
    const StabilityTest& test = suite_test(name);
    ASSERT_TRUE(test.settled_failure) << name;
    const EngineInfo* engine = find_engine(engine_name);
    ASSERT_NE(engine, nullptr);
    const SceneSpec scene = load_test_scene(test, FX2D_SOURCE_DIR "/scenes/stability", {}, parameter);
    const Trajectory whole = simulate(scene, *engine, test.sample_every);
    const Trajectory settled = simulate(scene, *engine, test.sample_every, test.settled_failure);
    const Verdict expected = test.judge(scene, whole);
    const Verdict early = test.judge(scene, settled);
    if (expected.pass)
      EXPECT_EQ(settled.states.size(), whole.states.size()) << name;
    else
      EXPECT_LT(settled.states.size(), whole.states.size()) << name;
    EXPECT_EQ(early.pass, expected.pass) << name;
    EXPECT_EQ(early.reason, expected.reason) << name;
    EXPECT_EQ(early.criterion, expected.criterion) << name;
    EXPECT_EQ(early.step, expected.step) << name;
  }
}

}  // namespace
}  // namespace fxbench
