// ABBA rounds and variant names; the method and its invariants are in interleave.h.
#include "measure/interleave.h"

#include <chrono>

namespace fxbench {
namespace {

constexpr std::string_view variant_suffix[] = {"@A", "@B"};

// A later round adds its samples as one more repeat, and only its final state to check.
void append_round(RunRecord& record, const RunRecord& round) {
  const auto append = [](auto& into, const auto& from) { into.insert(into.end(), from.begin(), from.end()); };
  append(record.wall_ms, round.wall_ms);
  append(record.cpu_ms, round.cpu_ms);
  append(record.cycles, round.cycles);
  append(record.contacts, round.contacts);
  append(record.phase_ms, round.phase_ms);
  record.repeats += round.repeats;
  if (round.final_state_hash != record.final_state_hash) record.deterministic = false;
}

// The first round of a variant samples accuracy and hashes along the way, as a run's first repeat
// does; later rounds hash only their final state, to check determinism.
RunPlan round_plan(const InterleavePlan& plan, bool first_round, int steps) {
  if (first_round)
    return {1, plan.warmup_steps, plan.hash_every > 0 ? plan.hash_every : steps, plan.accuracy_every};
  return {1, 0, steps, steps};
}

}  // namespace

std::size_t cell_of_turn(int turn, std::size_t cells) {
  const auto round = static_cast<std::size_t>(turn) / cells, place = static_cast<std::size_t>(turn) % cells;
  return round % 2 == 0 ? place : cells - 1 - place;
}

Variant variant_of_round(int round) { return cell_of_turn(round, 2) == 0 ? Variant::a : Variant::b; }

RoundRobinRuns measure_round_robin(std::span<const TimedCell> cells, const InterleavePlan& plan,
                                   const TurnProgressFn& progress) {
  using clock = std::chrono::steady_clock;
  const clock::time_point start = clock::now();
  const auto over_budget = [&] {
    return plan.time_budget_s > 0 && std::chrono::duration<double>(clock::now() - start).count() >= plan.time_budget_s;
  };
  RoundRobinRuns runs;
  runs.runs.resize(cells.size());
  const int turns = plan.rounds * static_cast<int>(cells.size());
  for (int turn = 0; turn < turns; ++turn) {
    const bool balanced = turn % static_cast<int>(cells.size()) == 0;  // every cell has run as often
    if (balanced && turn > 0 && over_budget()) break;
    const std::size_t c = cell_of_turn(turn, cells.size());
    const TimedCell& cell = cells[c];
    RunRecord& record = runs.runs[c];
    if (progress) progress(c, record.repeats);
    const bool first_round = record.repeats == 0;
    RunRecord measured =
        measure_engine(*cell.scene, *cell.engine, round_plan(plan, first_round, cell.scene->steps));
    if (measured.repeats == 0) {  // interrupt.h: a SIGINT stopped this round
      runs.interrupted = true;
      break;
    }
    if (first_round)
      record = std::move(measured);
    else
      append_round(record, measured);
  }
  return runs;
}

InterleavedRuns measure_interleaved(const SceneSpec& scene, const EngineInfo& a, const EngineInfo& b,
                                    const InterleavePlan& plan, const RoundProgressFn& progress) {
  const TimedCell cells[] = {{&scene, &a}, {&scene, &b}};
  int turn = 0;
  const TurnProgressFn each_turn = [&](std::size_t, int) {
    if (progress) progress(turn, 2 * plan.rounds);
    ++turn;
  };
  RoundRobinRuns runs = measure_round_robin(cells, plan, each_turn);
  return {std::move(runs.runs[0]), std::move(runs.runs[1]), runs.interrupted};
}

std::string variant_engine_name(std::string_view engine, Variant variant) {
  return std::string(engine) + std::string(variant_suffix[variant == Variant::a ? 0 : 1]);
}

std::optional<VariantResults> split_variants(const ResultSet& results) {
  VariantResults split;
  for (ResultSet* side : {&split.a, &split.b}) {
    side->provenance = results.provenance;
    side->scenes = results.scenes;
    side->partial = results.partial;
  }
  for (const RunRecord& run : results.runs) {
    const bool is_a = run.engine.ends_with(variant_suffix[0]);
    if (!is_a && !run.engine.ends_with(variant_suffix[1])) return std::nullopt;
    RunRecord& renamed = (is_a ? split.a : split.b).runs.emplace_back(run);
    renamed.engine.resize(renamed.engine.size() - variant_suffix[0].size());
  }
  if (split.a.runs.empty() || split.b.runs.empty()) return std::nullopt;
  return split;
}

}  // namespace fxbench
