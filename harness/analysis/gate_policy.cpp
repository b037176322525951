// The gating policy and the judgement of a comparison; the invariants are in gate_policy.h.
//
// Reads top to bottom: validating the policy file field by field, then judging each compare row
// (quarantine, thresholds, the time and exact rules, accuracy, controls), then the night's verdict.
#include "analysis/gate_policy.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <map>
#include <sstream>

#include "analysis/compare.h"
#include "common/bounded_read.h"
#include "scene/json_reader.h"
#include "stats/statistics.h"

namespace fxbench {
namespace {

using nlohmann::json;

// --- the policy file ------------------------------------------------------------------------------

// Walks the policy JSON; every complaint names the file, the line and column and the JSON pointer
// of the offending value (of its key, for an unknown key), as the scene loader's do.
class PolicyReader {
 public:
  // `text` is the file's, and must outlive the reader.
  PolicyReader(std::string_view text, std::string label) : errors_(text, std::move(label)) {}

  [[noreturn]] void fail(const std::string& pointer, const std::string& what, bool at_key = false) const {
    errors_.fail(pointer, what, at_key);
  }

  // `value` must be an object whose keys are all among `allowed` and include every `required`.
  void expect_object(const json& value, const std::string& pointer, std::initializer_list<const char*> allowed,
                     std::initializer_list<const char*> required = {}) const {
    if (!value.is_object()) fail(pointer, "expected an object");
    for (const auto& [key, member] : value.items()) {
      if (std::ranges::find(allowed, key) == allowed.end()) {
        std::string names;
        for (const char* name : allowed) names += std::string(names.empty() ? "" : ", ") + name;
        fail(scene_detail::child_pointer(pointer, key), "unknown key; expected one of " + names, true);
      }
    }
    for (const char* name : required)
      if (!value.contains(name)) fail(pointer, std::string("missing '") + name + "'");
  }

  double number(const json& value, const std::string& pointer, double low, double high) const {
    if (!value.is_number() || !(value.get<double>() >= low && value.get<double>() <= high))
      fail(pointer, "expected a number in [" + shortest(low) + ", " + shortest(high) + "], got " + value.dump());
    return value.get<double>();
  }

  int integer(const json& value, const std::string& pointer, int low, int high) const {
    if (!value.is_number_integer() || value.get<long long>() < low || value.get<long long>() > high)
      fail(pointer, "expected an integer in [" + std::to_string(low) + ", " + std::to_string(high) + "], got " +
                        value.dump());
    return value.get<int>();
  }

  std::string text(const json& value, const std::string& pointer) const {
    if (!value.is_string() || value.get<std::string>().empty()) fail(pointer, "expected a non-empty string");
    return value.get<std::string>();
  }

  std::vector<std::string> texts(const json& value, const std::string& pointer) const {
    if (!value.is_array() || value.empty()) fail(pointer, "expected a non-empty list of strings");
    std::vector<std::string> result;
    for (std::size_t i = 0; i < value.size(); ++i) result.push_back(text(value[i], pointer + "/" + std::to_string(i)));
    return result;
  }

  // Overrides `thresholds` with whichever of its fields `value` sets.
  void thresholds(const json& value, const std::string& pointer, Thresholds& thresholds, bool allow_reason) const {
    if (allow_reason)
      expect_object(value, pointer, {"noise", "alpha", "accuracy_tolerance", "instructions_tolerance", "reason"});
    else
      expect_object(value, pointer, {"noise", "alpha", "accuracy_tolerance", "instructions_tolerance"});
    const auto set = [&](const char* name, double& field, double low, double high) {
      if (value.contains(name)) field = number(value[name], pointer + "/" + name, low, high);
    };
    set("noise", thresholds.noise, 0.0, 0.5);
    set("alpha", thresholds.alpha, 1e-9, 0.5);
    set("accuracy_tolerance", thresholds.accuracy_tolerance, 0.0, 10.0);
    set("instructions_tolerance", thresholds.instructions_tolerance, 0.0, 0.5);
    if (allow_reason && value.contains("reason")) text(value["reason"], pointer + "/reason");
  }

  // `alpha`: the strictest significance level the policy judges at, which sets the fewest rounds.
  Suite suite(const json& value, const std::string& pointer, double alpha) const {
    expect_object(value, pointer, {"engines", "scenes", "rounds", "steps"}, {"engines", "scenes", "rounds", "steps"});
    Suite suite;
    suite.engines = texts(value["engines"], pointer + "/engines");
    const json& scenes = value["scenes"];
    if (!scenes.is_array() || scenes.empty()) fail(pointer + "/scenes", "expected a non-empty list of {scene, bodies}");
    for (std::size_t i = 0; i < scenes.size(); ++i) {
      const std::string where = pointer + "/scenes/" + std::to_string(i);
      expect_object(scenes[i], where, {"scene", "bodies"}, {"scene"});
      const json& bodies = scenes[i].contains("bodies") ? scenes[i]["bodies"] : json();
      SuiteScene scene{text(scenes[i]["scene"], where + "/scene"),
                       bodies.is_null() ? 0 : integer(bodies, where + "/bodies", 1, 1'000'000), ""};
      scene.name = std::filesystem::path(scene.scene).stem().string();
      if (scene.bodies > 0) scene.name += "_" + std::to_string(scene.bodies);
      // Two scenes of one name would write over each other's files in the night.
      if (std::ranges::find(suite.scenes, scene.name, &SuiteScene::name) != suite.scenes.end()) {
        fail(where + "/scene", "expected a scene a night can name apart from the others, got a second '" +
                                   scene.name + "' (its file's stem, and _N at a size)");
      }
      suite.scenes.push_back(scene);
    }
    suite.rounds = rounds(value["rounds"], pointer + "/rounds", alpha);
    suite.steps = integer(value["steps"], pointer + "/steps", 1, 1'000'000);
    return suite;
  }

  // The rounds are judged by a sign test (compare's Method); with fewer than it can decide on,
  // no slowdown could ever gate.
  int rounds(const json& value, const std::string& pointer, double alpha) const {
    const int fewest = sign_test_min_pairs(alpha);
    if (value.is_number_integer() && value.get<long long>() >= 1 && value.get<long long>() < fewest) {
      std::ostringstream why;
      why << "expected at least " << fewest << " rounds, got " << value.dump() << ": the sign test over fewer rounds "
          << "cannot reach p < " << alpha << " (the policy's strictest alpha) however the builds differ";
      fail(pointer, why.str());
    }
    return integer(value, pointer, fewest, 10'000);
  }

  Quarantine quarantine(const json& value, const std::string& pointer) const {
    expect_object(value, pointer, {"engine", "scene", "bodies", "metric", "reason"}, {"engine", "scene", "reason"});
    Quarantine entry{text(value["engine"], pointer + "/engine"), text(value["scene"], pointer + "/scene"), {}, {},
                     text(value["reason"], pointer + "/reason")};
    if (value.contains("bodies")) entry.bodies = integer(value["bodies"], pointer + "/bodies", 1, 1'000'000);
    if (value.contains("metric")) entry.metric = text(value["metric"], pointer + "/metric");
    return entry;
  }

 private:
  static std::string shortest(double value) {
    std::ostringstream text;
    text << value;
    return text.str();
  }

  scene_detail::ErrorReporter errors_;
};

// --- judging rows ---------------------------------------------------------------------------------

bool is_exact(const GateRow& row) { return !row.p_value.has_value(); }

// Exact counts have no noise: only the size of the change matters.
Speed exact_speed(double ratio, double tolerance) {
  if (ratio > 1.0 + tolerance) return Speed::slower;
  if (ratio < 1.0 - tolerance) return Speed::faster;
  return Speed::no_change;
}

Speed time_speed(const GateRow& row, int repeats, const Thresholds& thresholds) {
  const RatioEstimate estimate{row.ratio, {row.ci_low, row.ci_high}};
  RankTest test;
  test.p_value = *row.p_value;
  return decide_speed(estimate, test, repeats, VerdictRules{thresholds.noise, thresholds.alpha, VerdictRules{}.min_repeats})
      .speed;
}

// compare's accuracy rule (harness/README.md, compare) at the scene's own tolerance: lengths move
// beyond tolerance * |a| + 0.1 mm; counts of lost bodies may not grow at all; a displacement
// judges only in a scene whose primary metric it is.
AccuracyChange accuracy_change(const json& accuracy, double tolerance) {
  if (!accuracy.is_object() || !accuracy.contains("figures")) return AccuracyChange::same;
  const std::string primary = accuracy.value("primary_metric", std::string());
  AccuracyChange worst = AccuracyChange::same;
  for (const auto& [name, figure] : accuracy["figures"].items()) {
    const double a = figure.value("a", 0.0);
    const double b = figure.value("b", 0.0);
    const bool is_length = name == "max_penetration" || name == "max_displacement";
    if (name == "max_displacement" && primary != "displacement") continue;
    const double allowance = is_length ? tolerance * std::abs(a) + accuracy_floor_m : 0.0;
    if (std::abs(b - a) <= allowance) continue;
    if (b > a) return AccuracyChange::worse;
    worst = AccuracyChange::better;
  }
  return worst;
}

std::string accuracy_suffix(AccuracyChange change) {
  if (change == AccuracyChange::worse) return ", less accurate";
  if (change == AccuracyChange::better) return ", more accurate";
  return "";
}

class RowReader {
 public:
  explicit RowReader(std::string label) : label_(std::move(label)) {}

  GateRow read(const json& row, std::size_t index) const {
    where_ = "/rows/" + std::to_string(index);
    if (!row.is_object()) fail("", "expected an object");
    GateRow gate;
    gate.engine = text(row, "engine");
    gate.scene = text(row, "scene");
    gate.bodies = static_cast<int>(number(row, "bodies"));
    gate.metric = text(row, "metric");
    gate.a = number(row, "a");
    gate.b = number(row, "b");
    gate.ratio = number(row, "ratio");
    gate.ci_low = number(row, "ci_low");
    gate.ci_high = number(row, "ci_high");
    if (!row.contains("p_value")) fail("/p_value", "missing (null for an exact row)");
    if (!row["p_value"].is_null()) gate.p_value = number(row, "p_value");
    gate.compare_verdict = row.contains("verdict") && row["verdict"].is_string() ? row["verdict"].get<std::string>() : "";
    return gate;
  }

 private:
  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw InputError(label_ + ": " + where_ + field + ": " + what);
  }
  std::string text(const json& row, const char* name) const {
    if (!row.contains(name) || !row[name].is_string()) fail(std::string("/") + name, "expected a string");
    return row[name].get<std::string>();
  }
  double number(const json& row, const char* name) const {
    if (!row.contains(name) || !row[name].is_number()) fail(std::string("/") + name, "expected a number");
    return row[name].get<double>();
  }

  std::string label_;
  mutable std::string where_;
};

// Fewer recorded repeats than the rule needs stays inconclusive; an input without the counts is
// taken at its word that it had enough.
int repeats_of(const json& row) {
  const int needed = VerdictRules{}.min_repeats;
  return std::min(row.value("repeats_a", needed), row.value("repeats_b", needed));
}

void judge_row(const json& source, const Policy& policy, GateRow& row) {
  const Thresholds& thresholds = policy.thresholds_for(row.scene);
  row.control = policy.is_control(base_engine(row.engine));
  if (const Quarantine* entry = policy.quarantined(base_engine(row.engine), row.scene, row.bodies, row.metric)) {
    row.quarantined = true;
    row.reason = entry->reason;
    row.verdict = "quarantined";
    return;
  }
  row.band = is_exact(row) ? thresholds.instructions_tolerance : thresholds.noise;
  const Speed speed = is_exact(row) ? exact_speed(row.ratio, row.band) : time_speed(row, repeats_of(source), thresholds);
  const AccuracyChange accuracy =
      source.contains("accuracy") ? accuracy_change(source["accuracy"], thresholds.accuracy_tolerance) : AccuracyChange::same;
  row.verdict = to_string(speed) + accuracy_suffix(accuracy);
  const bool changed = speed == Speed::faster || speed == Speed::slower || accuracy != AccuracyChange::same;
  if (row.control) {
    row.verdict = (changed ? "control changed: " : "control: ") + row.verdict;
    return;
  }
  row.step_detected = changed;
  row.regression = speed == Speed::slower || accuracy == AccuracyChange::worse;
}

// A control that moved says the machine, not the code, changed: no time verdict of that night can
// be trusted to mean a regression.
void distrust_time_on_noisy_machine(GateReport& report) {
  for (const GateRow& row : report.rows) {
    if (row.control && !row.quarantined && !is_exact(row) && row.verdict.starts_with("control changed")) {
      std::ostringstream text;
      text << base_engine(row.engine) << " " << row.scene << " " << row.bodies << " " << row.metric << ": "
           << row.verdict.substr(std::string("control changed: ").size()) << " (ratio " << row.ratio << ")";
      report.noisy_controls.push_back(text.str());
    }
  }
  if (report.noisy_controls.empty()) return;
  for (GateRow& row : report.rows) {
    if (row.control || row.quarantined || is_exact(row) || !row.verdict.starts_with("slower")) continue;
    row.verdict = "inconclusive (noisy machine)" + row.verdict.substr(std::string("slower").size());
    row.step_detected = false;
    row.regression = row.verdict.ends_with("less accurate");
  }
}

bool is_inconclusive(const GateRow& row) { return row.verdict.starts_with("inconclusive"); }

// A control is steady only when it was judged `no change`: an undecided one vouches for nothing.
const char* control_state(const GateRow& row) {
  if (row.verdict.starts_with("control changed")) return "controls changed";
  return row.verdict.starts_with("control: no change") ? "controls steady" : "controls inconclusive";
}

}  // namespace

// --- the policy -----------------------------------------------------------------------------------

const Thresholds& Policy::thresholds_for(const std::string& scene) const {
  const auto found = std::ranges::find(scene_thresholds, scene, &std::pair<std::string, Thresholds>::first);
  return found == scene_thresholds.end() ? defaults : found->second;
}

const Quarantine* Policy::quarantined(const std::string& engine, const std::string& scene, int bodies,
                                      const std::string& metric) const {
  for (const Quarantine& entry : quarantine)
    if (entry.engine == engine && entry.scene == scene && entry.bodies.value_or(bodies) == bodies &&
        entry.metric.value_or(metric) == metric)
      return &entry;
  return nullptr;
}

bool Policy::is_control(const std::string& engine) const { return std::ranges::find(controls, engine) != controls.end(); }

Policy parse_policy(const std::string& text, const std::string& label) {
  const json document =
      scene_detail::parse_json_text(text, label, std::string("a ") + gating_schema + " object");
  const PolicyReader reader(text, label);
  reader.expect_object(document, "", {"schema", "suite", "smoke", "controls", "defaults", "scenes", "quarantine"},
                       {"schema", "suite", "smoke", "defaults"});
  if (document["schema"] != gating_schema)
    reader.fail("/schema", std::string("expected \"") + gating_schema + "\", got " + document["schema"].dump());
  Policy policy;
  reader.thresholds(document["defaults"], "/defaults", policy.defaults, false);
  if (document.contains("scenes")) {
    if (!document["scenes"].is_object()) reader.fail("/scenes", "expected an object: scene name -> thresholds");
    for (const auto& [scene, overrides] : document["scenes"].items()) {
      Thresholds thresholds = policy.defaults;
      reader.thresholds(overrides, scene_detail::child_pointer("/scenes", scene), thresholds, true);
      policy.scene_thresholds.emplace_back(scene, thresholds);
    }
  }
  double strictest_alpha = policy.defaults.alpha;
  for (const auto& [scene, thresholds] : policy.scene_thresholds) strictest_alpha = std::min(strictest_alpha, thresholds.alpha);
  policy.suite = reader.suite(document["suite"], "/suite", strictest_alpha);
  policy.smoke = reader.suite(document["smoke"], "/smoke", strictest_alpha);
  if (document.contains("controls")) policy.controls = reader.texts(document["controls"], "/controls");
  if (document.contains("quarantine")) {
    const json& entries = document["quarantine"];
    if (!entries.is_array()) reader.fail("/quarantine", "expected a list of {engine, scene, bodies, metric, reason}");
    for (std::size_t i = 0; i < entries.size(); ++i)
      policy.quarantine.push_back(reader.quarantine(entries[i], "/quarantine/" + std::to_string(i)));
  }
  return policy;
}

Policy read_policy(const std::string& path) {
  return parse_policy(read_bounded_file(path, "a gating policy"), path);
}

std::string base_engine(const std::string& engine) { return engine.substr(0, engine.find('@')); }

// --- the judgement --------------------------------------------------------------------------------

namespace {

// Appends the gating rows of one comparison, judged one by one.
void judge_rows(const json& compare, const std::string& label, const Policy& policy, std::vector<GateRow>& rows) {
  if (!compare.is_object() || compare.value("schema", std::string()) != compare_schema)
    throw InputError(label + ": expected a " + std::string(compare_schema) + " object (fx2d-bench compare --json)");
  if (compare.value("mode", std::string("ab")) != "ab")
    throw InputError(label + ": a cross-engine comparison does not gate; expected an A/B comparison");
  if (!compare.contains("rows") || !compare["rows"].is_array()) throw InputError(label + ": /rows: expected a list");
  const RowReader reader(label);
  const std::size_t before = rows.size();
  for (std::size_t i = 0; i < compare["rows"].size(); ++i) {
    const json& source = compare["rows"][i];
    GateRow row = reader.read(source, i);
    if (row.metric != step_metric && row.metric != instructions_metric) continue;
    judge_row(source, policy, row);
    rows.push_back(std::move(row));
  }
  if (rows.size() == before)
    throw InputError(label + ": no " + std::string(step_metric) + " or " + instructions_metric + " rows to gate");
}

}  // namespace

GateReport judge(const json& compare, const std::string& label, const Policy& policy) {
  GateReport report;
  judge_rows(compare, label, policy, report.rows);
  distrust_time_on_noisy_machine(report);
  return report;
}

GateReport judge_files(const std::vector<std::string>& compare_paths, const Policy& policy) {
  GateReport report;
  for (const std::string& path : compare_paths) {
    const json compare = json::parse(read_bounded_file(path, "fx2d-bench compare --json output"), nullptr, false);
    if (compare.is_discarded()) throw InputError(path + ": not valid JSON; expected fx2d-bench compare --json output");
    judge_rows(compare, path, policy, report.rows);
  }
  // One night is judged whole: a control that moved in any scene makes every time verdict suspect.
  distrust_time_on_noisy_machine(report);
  return report;
}

int GateReport::regressions() const {
  return static_cast<int>(std::ranges::count_if(rows, &GateRow::regression));
}

ExitCode GateReport::exit_code() const {
  if (regressions() > 0) return exit_regression;
  const bool undecided = std::ranges::any_of(rows, [](const GateRow& row) {
    return !row.control && !row.quarantined && is_inconclusive(row);
  });
  return undecided || !noisy_controls.empty() ? exit_inconclusive : exit_ok;
}

std::string GateReport::headline() const {
  std::map<std::string, int> counts;
  for (const GateRow& row : rows) {
    if (row.quarantined) ++counts["quarantined"];
    else if (row.control) ++counts[control_state(row)];
    else if (row.regression) ++counts["regressions"];
    else if (is_inconclusive(row)) ++counts["inconclusive"];
    else if (row.step_detected) ++counts["improvements"];
    else ++counts["unchanged"];
  }
  std::string text;
  for (const char* name : {"regressions", "improvements", "unchanged", "inconclusive", "quarantined", "controls steady",
                           "controls inconclusive", "controls changed"})
    text += std::string(text.empty() ? "" : ", ") + std::to_string(counts[name]) + " " + name;
  if (!noisy_controls.empty()) text += " (noisy machine: time verdicts not trusted)";
  return text;
}

}  // namespace fxbench
