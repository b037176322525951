// The stability suite, its criteria and its search; invariants in stability_tests.h.
#include "analysis/stability_tests.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>
#include <stdexcept>

#include "metrics/accuracy.h"
#include "scene/scene_loader.h"

namespace fxbench {

bool is_harder(const SearchSpec& spec, double a, double b) {
  return spec.harder == Harder::increasing ? a > b : a < b;
}

namespace {

// ---- the search ----

// The next bracket probe: twice as hard, never past the limit.
double next_probe(const SearchSpec& spec, double value) {
  double next = spec.harder == Harder::increasing ? value * 2.0 : value / 2.0;
  if (spec.integer) next = spec.harder == Harder::increasing ? std::ceil(next) : std::floor(next);
  return is_harder(spec, next, spec.limit) ? spec.limit : next;
}

bool within_resolution(const SearchSpec& spec, double pass, double fail) {
  const double low = std::min(pass, fail);
  const double high = std::max(pass, fail);
  if (spec.integer && high - low <= 1.0) return true;
  return spec.scale == Scale::linear ? high - low <= spec.resolution : high <= low * (1.0 + spec.resolution);
}

double midpoint(const SearchSpec& spec, double pass, double fail) {
  const double middle = spec.scale == Scale::linear ? 0.5 * (pass + fail) : std::sqrt(pass * fail);
  return spec.integer ? std::floor(middle) : middle;
}

// ---- geometry of poses ----

std::string formatted(const char* format, auto... values) {
  char text[200];
  std::snprintf(text, sizeof text, format, values...);
  return text;
}

// A failure of `criterion` seen at the sample taken at `time` (seconds).
Verdict failed(std::string criterion, const SceneSpec& scene, double time, std::string reason) {
  return {false, std::move(reason), std::move(criterion), static_cast<int>(std::lround(time / scene.dt))};
}

double half_height(const BodySpec& body) {
  switch (body.shape) {
    case ShapeKind::circle: return body.radius;
    case ShapeKind::box: return body.half_extents.y;
    case ShapeKind::polygon: {
      double extent = 0.0;
      for (const Vec2& vertex : body.vertices) extent = std::max(extent, std::abs(vertex.y));
      return extent;
    }
  }
  return 0.0;
}

double distance(Vec2 a, Vec2 b) { return std::hypot(a.x - b.x, a.y - b.y); }

double turned(double from, double to) { return std::abs(std::remainder(to - from, 2.0 * std::numbers::pi)); }

Vec2 world_point(const BodyState& body, Vec2 local) {
  const double c = std::cos(body.angle);
  const double s = std::sin(body.angle);
  return {body.position.x + c * local.x - s * local.y, body.position.y + s * local.x + c * local.y};
}

bool is_dynamic(const SceneSpec& scene, std::size_t body) { return scene.bodies[body].type == BodyType::dynamic; }

void check_shape(const SceneSpec& scene, const Trajectory& trajectory) {
  if (trajectory.states.empty() || trajectory.states.size() != trajectory.times.size())
    throw std::invalid_argument("stability criterion: a trajectory needs one time per sample and a start");
  for (const auto& states : trajectory.states)
    if (states.size() != scene.bodies.size()) throw std::invalid_argument("stability criterion: states do not match the scene");
}

// ---- the pyramid both pyramid tests build ----

// One box_grid generator per row of a pyramid of unit boxes with `base` boxes in its bottom row,
// each row sunk into the one below (the bottom row into the ground at y = 0) by `overlap` metres.
std::vector<std::pair<std::string, std::string>> pyramid_rows(int base, double overlap) {
  std::vector<std::pair<std::string, std::string>> rows;
  for (int row = 0; row < base; ++row) {
    const int count = base - row;
    const nlohmann::json generator = {
        {"type", "box_grid"},
        {"count", count},
        {"per_row", count},
        {"origin", {-0.5 * (base - 1) + 0.5 * row, 0.5 - overlap + row * (1.0 - overlap)}},
        {"spacing", {1.0, 1.0}},
    };
    rows.emplace_back("/generators/-", generator.dump());
  }
  return rows;
}

std::vector<std::pair<std::string, std::string>> set(const std::string& pointer, const nlohmann::json& value) {
  return {{pointer, value.dump()}};
}

// The friction ramp: lane i's strip is /bodies/i and its box /bodies/(i + 9); each lane's friction
// is tan a plus its offset. Five boxes are past their friction limit, four within it, all beyond
// the judge's 0.02 margin; a box just past its limit accelerates at g cos(a) times the offset, so
// the steeper the slope, the longer it creeps before it slides (at 70 degrees a 0.025 box gains
// 0.04 m/s in its first half second), and an engine that lets it stop or sleep fails.
constexpr std::array<double, 9> ramp_friction_offsets = {-0.3, -0.15, -0.08, -0.04, -0.025, 0.025, 0.04, 0.08, 0.15};

std::vector<std::pair<std::string, std::string>> ramp_at(double angle_degrees) {
  const double angle = angle_degrees * std::numbers::pi / 180.0;
  auto overrides = set("/gravity", {10.0 * std::sin(angle), -10.0 * std::cos(angle)});
  const std::size_t lanes = ramp_friction_offsets.size();
  for (std::size_t lane = 0; lane < lanes; ++lane) {
    const std::string friction = nlohmann::json(std::tan(angle) + ramp_friction_offsets[lane]).dump();
    for (const std::size_t body : {lane, lane + lanes})
      overrides.emplace_back("/bodies/" + std::to_string(body) + "/material/friction", friction);
  }
  return overrides;
}

// Both tower tests: a collapse moves a box half its width, or topples it; a sag sinks the top.
constexpr double tower_max_move = 0.5;        // m: half a unit box
constexpr double tower_max_turn = 0.5;        // rad: about 30 degrees, a toppled box
constexpr double tower_max_sag = 0.01;        // of the tower's height: 1 cm per metre
// Boxes at rest under a heavy one: anything beyond settling by a few solver slops (Box2D's is
// 5 mm) means they were crushed through or pushed out.
constexpr double rest_max_move = 0.1;         // m
constexpr double rest_max_turn = 0.1;         // rad
// Cards rest on corners, which settle by a few degrees as their contacts find a pose; a card that
// slides a quarter of its length or leans 20 degrees further has let the house fall.
constexpr double card_max_move = 0.25;        // m
constexpr double card_max_turn = 0.35;        // rad
constexpr int overlap_pyramid_base = 8;       // boxes in the bottom row of the overlap test
// m/s upward: a box thrown 0.45 m into the air; Box2D v3 caps its own push-out at this speed.
constexpr double launch_speed = 3.0;
constexpr double resolved_depth = 0.02;       // m: 2% of a box, several solver slops
constexpr double chain_max_gap = 0.1;         // m: a tenth of a link's length

Verdict tower(const SceneSpec& scene, const Trajectory& trajectory) {
  const Verdict collapse = stays_in_place(scene, trajectory, tower_max_move, tower_max_turn);
  return collapse.pass ? top_holds(scene, trajectory, tower_max_sag) : collapse;
}

Verdict at_rest(const SceneSpec& scene, const Trajectory& trajectory) {
  return stays_in_place(scene, trajectory, rest_max_move, rest_max_turn);
}

Verdict cards_stand(const SceneSpec& scene, const Trajectory& trajectory) {
  return stays_in_place(scene, trajectory, card_max_move, card_max_turn);
}

// Each judge above checks stays_in_place first, which reports the first sample where a box moved
// or turned too far: once the samples so far show one, the whole trajectory's verdict is that.
bool tower_collapsed(const SceneSpec& scene, const Trajectory& so_far) {
  return !stays_in_place(scene, so_far, tower_max_move, tower_max_turn).pass;
}

bool rest_broken(const SceneSpec& scene, const Trajectory& so_far) { return !at_rest(scene, so_far).pass; }

bool cards_fell(const SceneSpec& scene, const Trajectory& so_far) { return !cards_stand(scene, so_far).pass; }

// The speed tests stop at the fastest body an engine builds.
double accepted_speed(const EngineCapabilities& capabilities) { return capabilities.max_linear_speed; }

std::vector<StabilityTest> make_suite() {
  return {
      {"vertical_stack", "height", "boxes", "a box moves 0.5 m or turns 0.5 rad, or the top sinks 1% of the height, within 10 s",
       {4, 128, 1, Harder::increasing, Scale::linear, true}, 32, 10,
       [](double height) { return set("/size", static_cast<int>(height)); }, tower, nullptr, tower_collapsed},
      {"pyramid", "base width", "boxes", "a box moves 0.5 m or turns 0.5 rad, or the apex sinks 1% of the height, within 5 s",
       {4, 128, 1, Harder::increasing, Scale::linear, true}, 16, 10,
       [](double base) { return pyramid_rows(static_cast<int>(base), 0.0); }, tower, nullptr, tower_collapsed},
      {"mass_ratio", "mass ratio", "heavy/light", "any box moves 0.1 m or turns 0.1 rad within 3 s (crushed through or pushed out)",
       {1, 10000, 0.1, Harder::increasing, Scale::geometric, false}, 1000, 10,
       // The heavy box has 5 times a light box's area.
       [](double ratio) { return set("/bodies/2/material/density", ratio / 5.0); }, at_rest, nullptr, rest_broken},
       // From 20 degrees, where the lowest lane's friction is still 0.06, to 75, short of where a
       // flat box that holds would tip (tan a = 5).
      {"friction_ramp", "slope angle", "degrees", "a box above the friction angle slides, or one below it misses g (sin a - mu cos a) by 5%",
       {20, 75, 0.5, Harder::increasing, Scale::linear, false}, 40, 10, ramp_at,
       [](const SceneSpec& scene, const Trajectory& trajectory) {
         return slides_as_coulomb_predicts(scene, trajectory, RampTolerances{});
       },
       nullptr},
      {"overlap_recovery", "overlap", "fraction of a box", "a box is thrown upward faster than 3 m/s, or an overlap deeper than 2 cm remains after 2 s",
       {0.02, 0.5, 0.01, Harder::increasing, Scale::linear, false}, 0.32, 1,
       [](double overlap) { return pyramid_rows(overlap_pyramid_base, overlap); },
       [](const SceneSpec& scene, const Trajectory& trajectory) {
         return recovers_from_overlap(scene, trajectory, launch_speed, resolved_depth);
       },
       nullptr},
      {"thin_wall", "speed", "m/s", "the circle ends up beyond the wall's mid-plane (tunnelled)",
       {5, 1000, 0.05, Harder::increasing, Scale::geometric, false}, 200, 1,
       [](double speed) { return set("/bodies/1/velocity", {speed, 0.0}); }, stays_on_its_side, accepted_speed},
      // The fast-body tests: each starts far beyond what a broad phase's fat box covers, so only
      // continuous collision (a time of impact) keeps the body on its side.
      {"far_start", "speed", "m/s", "the circle, 60 m away at the start, ends up beyond the wall's mid-plane",
       {100, 1000, 0.05, Harder::increasing, Scale::geometric, false}, 200, 1,
       [](double speed) { return set("/bodies/1/velocity", {speed, 0.0}); }, stays_on_its_side, accepted_speed},
      {"spinning_plank", "speed", "m/s", "the spinning plank's centre ends up beyond the wall's mid-plane",
       {50, 1000, 0.05, Harder::increasing, Scale::geometric, false}, 200, 1,
       [](double speed) { return set("/bodies/1/velocity", {speed, 0.0}); }, stays_on_its_side, accepted_speed},
      {"thin_floor", "speed", "m/s", "the small box ends up below the thin floor's mid-plane",
       {50, 1000, 0.05, Harder::increasing, Scale::geometric, false}, 200, 1,
       [](double speed) { return set("/bodies/1/velocity", {0.0, -speed}); }, stays_on_its_side, accepted_speed},
      {"card_house", "friction", "coefficient", "any card moves 0.25 m or turns 0.35 rad within 3 s",
       {1, 0.01, 0.01, Harder::decreasing, Scale::linear, false}, 0.05, 10,
       [](double friction) { return set("/material/friction", friction); }, cards_stand, nullptr, cards_fell},
      {"chain_load", "load ratio", "load/link", "a joint's anchors drift 0.1 m apart within 3 s",
       {1, 10000, 0.1, Harder::increasing, Scale::geometric, false}, 1000, 10,
       // The load has a link's area, so its density is the ratio.
       [](double ratio) { return set("/bodies/9/material/density", ratio); },
       [](const SceneSpec& scene, const Trajectory& trajectory) { return joints_hold(scene, trajectory, chain_max_gap); },
       nullptr},
  };
}

}  // namespace

std::string to_string(Outcome outcome) {
  switch (outcome) {
    case Outcome::boundary: return "boundary";
    case Outcome::holds_to_limit: return "holds_to_limit";
    case Outcome::fails_at_start: return "fails_at_start";
    case Outcome::engine_limit: return "engine_limit";
  }
  return "boundary";
}

SearchResult find_boundary(const SearchSpec& spec, const std::function<Verdict(double)>& evaluate) {
  SearchResult result;
  const auto probe = [&](double value) {
    result.evaluations.push_back({value, evaluate(value)});
    return result.evaluations.back().verdict.pass;
  };
  if (!probe(spec.start)) {
    result.outcome = Outcome::fails_at_start;
    result.first_fail = spec.start;
    return result;
  }
  double pass = spec.start;
  while (true) {
    if (pass == spec.limit || !is_harder(spec, spec.limit, pass)) {
      result.outcome = Outcome::holds_to_limit;
      result.last_pass = pass;
      return result;
    }
    const double next = next_probe(spec, pass);
    if (!probe(next)) {
      result.first_fail = next;
      break;
    }
    pass = next;
  }
  double fail = *result.first_fail;
  while (!within_resolution(spec, pass, fail)) {
    const double middle = midpoint(spec, pass, fail);
    if (middle == pass || middle == fail) break;
    (probe(middle) ? pass : fail) = middle;
  }
  result.last_pass = pass;
  result.first_fail = fail;
  return result;
}

SearchResult find_engine_boundary(const StabilityTest& test, SearchSpec& search, const EngineCapabilities& capabilities,
                                  const std::function<Verdict(double)>& evaluate) {
  const bool capped = test.engine_limit && test.engine_limit(capabilities) < search.limit;
  if (capped) search.limit = test.engine_limit(capabilities);
  SearchResult result = find_boundary(search, evaluate);
  if (capped && result.outcome == Outcome::holds_to_limit) result.outcome = Outcome::engine_limit;
  return result;
}

Verdict stays_in_place(const SceneSpec& scene, const Trajectory& trajectory, double max_move, double max_turn) {
  check_shape(scene, trajectory);
  const auto& start = trajectory.states.front();
  for (std::size_t sample = 1; sample < trajectory.states.size(); ++sample) {
    const auto& now = trajectory.states[sample];
    for (std::size_t body = 0; body < now.size(); ++body) {
      if (!is_dynamic(scene, body)) continue;
      const double moved = distance(now[body].position, start[body].position);
      const double turn = turned(start[body].angle, now[body].angle);
      if (!(moved <= max_move))
        return failed("moved", scene, trajectory.times[sample], formatted("body %zu moved %.3g m (limit %g) by t = %.2f s", body, moved, max_move, trajectory.times[sample]));
      if (!(turn <= max_turn))
        return failed("turned", scene, trajectory.times[sample], formatted("body %zu turned %.3g rad (limit %g) by t = %.2f s", body, turn, max_turn, trajectory.times[sample]));
    }
  }
  return {};
}

Verdict top_holds(const SceneSpec& scene, const Trajectory& trajectory, double max_fraction) {
  check_shape(scene, trajectory);
  const auto& start = trajectory.states.front();
  std::optional<std::size_t> top;
  double bottom = std::numeric_limits<double>::infinity();
  for (std::size_t body = 0; body < start.size(); ++body) {
    if (!is_dynamic(scene, body)) continue;
    const double extent = half_height(scene.bodies[body]);
    bottom = std::min(bottom, start[body].position.y - extent);
    if (!top || start[body].position.y + extent > start[*top].position.y + half_height(scene.bodies[*top])) top = body;
  }
  if (!top) return {};
  const double height = start[*top].position.y + half_height(scene.bodies[*top]) - bottom;
  for (std::size_t sample = 1; sample < trajectory.states.size(); ++sample) {
    const double sag = start[*top].position.y - trajectory.states[sample][*top].position.y;
    if (!(sag <= max_fraction * height))
      return failed("sank", scene, trajectory.times[sample], formatted("the top sank %.3g m, %.2g%% of the %.3g m height (limit %g%%), by t = %.2f s", sag,
                              100.0 * sag / height, height, 100.0 * max_fraction, trajectory.times[sample]));
  }
  return {};
}

Verdict slides_as_coulomb_predicts(const SceneSpec& scene, const Trajectory& trajectory, const RampTolerances& tolerances) {
  check_shape(scene, trajectory);
  const double g = std::hypot(scene.gravity.x, scene.gravity.y);
  const double angle = std::atan2(scene.gravity.x, -scene.gravity.y);
  const double duration = trajectory.times.back() - trajectory.times.front();
  const auto& start = trajectory.states.front();
  const auto& end = trajectory.states.back();
  for (std::size_t body = 0; body < start.size(); ++body) {
    if (!is_dynamic(scene, body)) continue;
    const double mu = scene.bodies[body].material.dynamic_friction;
    const double excess = mu - std::tan(angle);
    if (excess > tolerances.margin) {
      const double moved = distance(end[body].position, start[body].position);
      if (!(moved < tolerances.hold_distance))
        return failed("slid", scene, trajectory.times.back(), formatted("the mu = %.2f box slid %.3g m (limit %g) on a %.1f degree slope it should hold", mu, moved,
                                tolerances.hold_distance, angle * 180.0 / std::numbers::pi));
    } else if (excess < -tolerances.margin && duration > 0.0) {
      const double expected = g * (std::sin(angle) - mu * std::cos(angle));
      const double measured = 2.0 * (end[body].position.x - start[body].position.x) / (duration * duration);
      if (!(std::abs(measured - expected) <= tolerances.relative_tolerance * expected + tolerances.absolute_tolerance))
        return failed("slide_rate", scene, trajectory.times.back(), formatted("the mu = %.2f box slid at %.3g m/s^2 on a %.1f degree slope; Coulomb friction gives %.3g",
                                mu, measured, angle * 180.0 / std::numbers::pi, expected));
    }
  }
  return {};
}

Verdict recovers_from_overlap(const SceneSpec& scene, const Trajectory& trajectory, double max_upward_speed,
                              double max_final_penetration) {
  check_shape(scene, trajectory);
  for (std::size_t sample = 1; sample < trajectory.states.size(); ++sample) {
    const auto& now = trajectory.states[sample];
    for (std::size_t body = 0; body < now.size(); ++body) {
      if (is_dynamic(scene, body) && !(now[body].linear_velocity.y <= max_upward_speed))
        return failed("thrown_up", scene, trajectory.times[sample], formatted("body %zu was thrown upward at %.3g m/s (limit %g) at t = %.2f s", body,
                                now[body].linear_velocity.y, max_upward_speed, trajectory.times[sample]));
    }
  }
  AccuracyProbe probe(scene, trajectory.states.front());
  const double depth = probe.measure(0, trajectory.states.back()).max_penetration;
  if (!(depth <= max_final_penetration))
    return failed("overlap_remained", scene, trajectory.times.back(), formatted("an overlap of %.3g m (limit %g) remained at t = %.2f s", depth, max_final_penetration,
                            trajectory.times.back()));
  return {};
}

Verdict stays_on_its_side(const SceneSpec& scene, const Trajectory& trajectory) {
  check_shape(scene, trajectory);
  const auto barrier = std::ranges::find(scene.bodies, BodyType::static_body, &BodySpec::type);
  if (barrier == scene.bodies.end() || barrier->shape != ShapeKind::box)
    throw std::invalid_argument("stays_on_its_side: the scene's first static body is not a box");
  const bool is_wall = barrier->half_extents.x <= barrier->half_extents.y;
  const auto across = [is_wall](const Vec2& point) { return is_wall ? point.x : point.y; };
  const double middle = across(barrier->position);
  const auto& start = trajectory.states.front();
  for (std::size_t sample = 1; sample < trajectory.states.size(); ++sample) {
    const auto& now = trajectory.states[sample];
    for (std::size_t body = 0; body < now.size(); ++body) {
      if (!is_dynamic(scene, body)) continue;
      if (!((across(now[body].position) - middle) * (across(start[body].position) - middle) > 0.0))
        return failed("crossed", scene, trajectory.times[sample], formatted("body %zu crossed the %s's mid-plane at t = %.3f s (%s = %.3g m)", body,
                                is_wall ? "wall" : "floor", trajectory.times[sample], is_wall ? "x" : "y",
                                across(now[body].position)));
    }
  }
  return {};
}

Verdict joints_hold(const SceneSpec& scene, const Trajectory& trajectory, double max_gap) {
  check_shape(scene, trajectory);
  for (std::size_t sample = 0; sample < trajectory.states.size(); ++sample) {
    const auto& now = trajectory.states[sample];
    for (std::size_t k = 0; k < scene.joints.size(); ++k) {
      const JointSpec& joint = scene.joints[k];
      const double gap = distance(world_point(now.at(static_cast<std::size_t>(joint.body_a)), joint.local_anchor_a),
                                  world_point(now.at(static_cast<std::size_t>(joint.body_b)), joint.local_anchor_b));
      if (!(gap <= max_gap))
        return failed("opened", scene, trajectory.times[sample], formatted("joint %zu opened %.3g m (limit %g) at t = %.2f s", k, gap, max_gap, trajectory.times[sample]));
    }
  }
  return {};
}

SceneSpec load_test_scene(const StabilityTest& test, const std::string& suite_dir,
                          const std::vector<std::pair<std::string, std::string>>& user_sets, double parameter) {
  SceneOverrides overrides;
  overrides.sets = user_sets;
  const auto applied = test.overrides(parameter);
  overrides.sets.insert(overrides.sets.end(), applied.begin(), applied.end());
  return load_scene_file((std::filesystem::path(suite_dir) / (test.name + ".json")).string(), overrides);
}

Trajectory simulate(const SceneSpec& scene, const EngineInfo& engine, int sample_every, const SettledFailure& settled_failure) {
  const std::unique_ptr<Engine> instance = engine.make();
  instance->build(scene);
  Trajectory trajectory;
  const auto sample = [&](int step) {
    trajectory.times.push_back(step * scene.dt);
    trajectory.states.emplace_back();
    instance->read_state(trajectory.states.back());
  };
  sample(0);
  for (int step = 1; step <= scene.steps; ++step) {
    instance->step();
    if (step % sample_every != 0 && step != scene.steps) continue;
    sample(step);
    if (settled_failure && settled_failure(scene, trajectory)) break;
  }
  return trajectory;
}

std::span<const StabilityTest> stability_suite() {
  static const std::vector<StabilityTest> suite = make_suite();
  return suite;
}

Verdict first_failure(const SearchResult& result) {
  for (const Evaluation& evaluation : result.evaluations)
    if (result.first_fail && evaluation.parameter == *result.first_fail) return evaluation.verdict;
  return {};
}

}  // namespace fxbench
