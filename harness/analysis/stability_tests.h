// The stability suite behind `fx2d-bench stability`: scenes built to break solvers, each with a
// stress parameter, the overrides that put the parameter into its scene file
// (scenes/stability/<test>.json), a pass criterion judged from poses alone, and the deterministic
// bracket-and-bisect search that finds where an engine first fails.
//
// Invariants: every criterion is a pure function of the scene and the sampled poses (BodyState),
// never of an engine's own reports or of time taken, so one engine cannot be judged more kindly
// than another and the same trajectory always gets the same verdict; the search evaluates a
// sequence of parameters fixed by its spec and by the verdicts alone, so a deterministic engine
// always gives the same boundary. The search assumes that failure is monotone in the parameter
// (once a value fails, every harder value fails); where an engine is not, the boundary it reports
// is one of its boundaries, the one the fixed sequence of probes reaches.
#pragma once

#include <functional>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "engines/engine.h"
#include "scene/scene_spec.h"

namespace fxbench {

// ---- The search ----

enum class Harder { increasing, decreasing };  // which way of the parameter the test gets harder
enum class Scale { linear, geometric };        // how the bracket is bisected

struct SearchSpec {
  double start = 1.0;       // the easiest value tried; expected to pass
  double limit = 1.0;       // the hardest value tried: a cap when increasing, a floor when decreasing
  double resolution = 1.0;  // linear: the bracket's width; geometric: its ratio minus 1 (0.1 is 10%)
  Harder harder = Harder::increasing;
  Scale scale = Scale::linear;
  bool integer = false;     // only whole values are tried
};

// Whether `a` is a harder value of the parameter than `b`.
bool is_harder(const SearchSpec& spec, double a, double b);

struct Verdict {
  bool pass = true;
  std::string reason;        // why it failed, with the numbers; empty when it passed
  std::string criterion;     // which check failed first, one word ("moved", "crossed", ...); empty when it passed
  std::optional<int> step;   // the step at whose sample it failed; none when no step is to blame
};

struct Evaluation {
  double parameter = 0.0;
  Verdict verdict;
};

// engine_limit: held up to the hardest value the engine accepts, which is below the test's limit
// (a speed beyond the engine's maximum): set by the suite's search, never by find_boundary.
enum class Outcome { boundary, holds_to_limit, fails_at_start, engine_limit };

// "boundary", "holds_to_limit", "fails_at_start", "engine_limit".
std::string to_string(Outcome outcome);

struct SearchResult {
  Outcome outcome = Outcome::boundary;
  std::optional<double> last_pass;   // the hardest value that passed
  std::optional<double> first_fail;  // the easiest value that failed, next to last_pass
  std::vector<Evaluation> evaluations;  // in the order tried
};

// Tries `start`; then doubles (halves, when decreasing) the parameter until it fails or reaches
// the limit (tried exactly); then bisects [last pass, first fail] until it is within the
// resolution (an integer bracket of width 1 cannot shrink further). Midpoints are arithmetic
// (linear) or geometric, rounded down for integers.
SearchResult find_boundary(const SearchSpec& spec, const std::function<Verdict(double)>& evaluate);

// ---- Trajectories and criteria ----

// Poses sampled during one simulation: states[0] at t = 0, then one entry per sample.
struct Trajectory {
  std::vector<double> times;                  // seconds
  std::vector<std::vector<BodyState>> states;  // each in SceneSpec::bodies order
};

// Collapse: no dynamic body may move farther than `max_move` (metres) from its start, nor turn
// more than `max_turn` (radians), at any sample.
Verdict stays_in_place(const SceneSpec& scene, const Trajectory& trajectory, double max_move, double max_turn);

// Sag: the topmost dynamic body at the start (highest top face) may not sink by more than
// `max_fraction` of the structure's starting height (that top face's height above the lowest
// dynamic body's bottom face), at any sample.
Verdict top_holds(const SceneSpec& scene, const Trajectory& trajectory, double max_fraction);

// Friction on a slope made by tilting gravity by angle a = atan2(g.x, -g.y) (sliding toward +x):
// at the last sample, a dynamic box whose friction mu (its dynamic friction) exceeds tan a by more
// than `margin` must have moved less than `hold_distance` metres; one below tan a by more than
// `margin` must have slid with the constant acceleration g (sin a - mu cos a), measured as
// 2 dx / T^2, within `relative_tolerance` of it plus `absolute_tolerance` (m/s^2). Boxes within
// `margin` of the threshold are not judged.
struct RampTolerances {
  double margin = 0.02;
  double hold_distance = 0.05;
  double relative_tolerance = 0.05;
  double absolute_tolerance = 0.05;
};
Verdict slides_as_coulomb_predicts(const SceneSpec& scene, const Trajectory& trajectory, const RampTolerances& tolerances);

// Launch: no dynamic body may move upward faster than `max_upward_speed` (m/s) at any sample;
// resolution: at the last sample the deepest overlap between any two shapes (accuracy.h) must be
// at most `max_final_penetration` metres.
Verdict recovers_from_overlap(const SceneSpec& scene, const Trajectory& trajectory, double max_upward_speed,
                              double max_final_penetration);

// Tunnelling: no dynamic body may end up, at any sample, on the other side of the first static
// body's mid-plane across its thinner side (x = its x for a wall, taller than wide; y = its y for
// a floor) from where it started. That body must be a box.
Verdict stays_on_its_side(const SceneSpec& scene, const Trajectory& trajectory);

// Joint gap: at every sample, the two world anchors of every joint lie within `max_gap` metres.
Verdict joints_hold(const SceneSpec& scene, const Trajectory& trajectory, double max_gap);

// ---- The suite ----

// True once the poses sampled so far fail a test with the verdict the whole trajectory gets.
using SettledFailure = std::function<bool(const SceneSpec&, const Trajectory&)>;

struct StabilityTest {
  std::string name;        // what --test selects; the scene is scenes/stability/<name>.json
  std::string parameter;   // e.g. "height"
  std::string units;       // e.g. "boxes"
  std::string criterion;   // one line: what failing means
  SearchSpec search;
  double quick_limit = 0;  // the limit under --quick
  int sample_every = 10;   // steps between pose samples (the last step is always sampled)
  // The parameter as --set assignments (JSON pointer, JSON value) on the scene file.
  std::function<std::vector<std::pair<std::string, std::string>>(double)> overrides;
  std::function<Verdict(const SceneSpec&, const Trajectory&)> judge;
  // The hardest parameter an engine accepts (increasing tests), or empty when any is: the search
  // stops there instead of probing values the engine refuses to build.
  std::function<double(const EngineCapabilities&)> engine_limit;
  // Optional: true once the poses sampled so far fail the test with the very verdict the whole
  // trajectory gets (a check the judge makes first and that reports its first failing sample), so
  // the simulation stops there: a collapsed tower costs its first second, not its five.
  SettledFailure settled_failure = nullptr;
};

// The suite in its fixed order.
std::span<const StabilityTest> stability_suite();

// ---- One evaluation ----

// The test's scene, <suite_dir>/<test.name>.json, with `user_sets` applied and then the
// parameter's overrides. Throws InputError.
SceneSpec load_test_scene(const StabilityTest& test, const std::string& suite_dir,
                          const std::vector<std::pair<std::string, std::string>>& user_sets, double parameter);

// Builds `scene` into a fresh instance of `engine` and steps it through scene.steps, untimed,
// sampling poses at the start, every `sample_every` steps and after the last step; or up to the
// first sample at which `settled_failure` (when given) holds.
Trajectory simulate(const SceneSpec& scene, const EngineInfo& engine, int sample_every, const SettledFailure& settled_failure = {});

// ---- One engine x test, searched ----

// An engine and a test of the suite: one search.
using EngineTest = std::pair<const EngineInfo*, const StabilityTest*>;

// find_boundary of `test` over `search` on an engine with `capabilities`: when the test's
// engine_limit is below search.limit the search stops there (search.limit is lowered to it, as
// run), and holding there is Outcome::engine_limit.
SearchResult find_engine_boundary(const StabilityTest& test, SearchSpec& search, const EngineCapabilities& capabilities,
                                  const std::function<Verdict(double)>& evaluate);

// One engine's search of one test, as run: what the table, the JSON and the file report.
struct TestResult {
  const EngineInfo* engine = nullptr;
  const StabilityTest* test = nullptr;
  SearchSpec search;          // as run: the limit is the quick one under --quick
  std::string settings;       // the engine's /solver entry of the resolved scene, as compact JSON
  SearchResult result;
  std::vector<std::string> overrides;  // per evaluation, the --set assignments of its parameter
  std::size_t work_item = 0;           // the pair's index in the whole work list
  // A search spread over shards (analysis/stability_pieces.h) is run in `pieces`; this is piece
  // `piece` (0-based), whose result holds only the verdicts it found, in `evaluations`.
  int piece = 0;
  int pieces = 1;
};

// The verdict of the easiest value that failed: what failed first there, and when; empty when
// nothing failed.
Verdict first_failure(const SearchResult& result);

}  // namespace fxbench
