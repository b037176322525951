// Engines timed in alternating rounds: two variants of one engine A B B A A B B A ..., the method
// behind `fx2d-bench ab`; several cells (an engine on a scene) in turn, forward then backward
// (A B C C B A A B C ...), the method behind `fx2d-bench run` with more than one engine and behind
// `fx2d-bench sweep`'s points; and the naming that lets one result file hold both variants.
//
// Why ABBA: on a shared machine the speed of everything drifts (other jobs, clock and thermal
// state); a drift that is linear over four rounds costs A and B the same in each ABBA block, so
// it cancels instead of landing on whichever variant ran later. Turning back at each end of the
// list does the same for any number of engines. Each round is one fresh instance
// timed over the scene's steps (runner.h's measure_engine with one repeat), so a round is exactly
// what a repeat of `fx2d-bench run` is, and the rounds of a variant become its repeats.
//
// Invariants: the first round of each engine records accuracy and state hashes as a first repeat
// does; every later round's final state hash is checked against it (deterministic); the rounds
// stop only when every engine has run the same number of rounds, unless a SIGINT (interrupt.h)
// cuts them short.
#pragma once

#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "common/results.h"
#include "engines/engine.h"
#include "measure/runner.h"
#include "scene/scene_spec.h"

namespace fxbench {

enum class Variant { a, b };

// The variant that runs round `round` (0-based): A B B A, repeated.
Variant variant_of_round(int round);

struct InterleavePlan {
  int rounds = 30;            // rounds per variant, >= 1
  double time_budget_s = 0;   // > 0: stop earlier, once both variants have run for this long
  int warmup_steps = 0;       // untimed steps on a discarded instance of each variant, first
  int hash_every = 50;        // 0: the last step's state only, whatever a scene's step count
  int accuracy_every = 10;
};

struct InterleavedRuns {
  RunRecord a;                // repeats = the rounds A ran
  RunRecord b;
  bool interrupted = false;   // a SIGINT cut the rounds short
};

// Called before each round with the round (0-based) and the planned total of rounds.
using RoundProgressFn = std::function<void(int round, int total_rounds)>;

// Times `a` and `b` on `scene` in ABBA rounds per `plan`. Engine failures propagate as thrown.
InterleavedRuns measure_interleaved(const SceneSpec& scene, const EngineInfo& a, const EngineInfo& b,
                                    const InterleavePlan& plan, const RoundProgressFn& progress = {});

// One engine on one scene: what each round times once.
struct TimedCell {
  const SceneSpec* scene;
  const EngineInfo* engine;
};

struct RoundRobinRuns {
  std::vector<RunRecord> runs;  // one per cell, in the order given; repeats = the rounds it ran
  bool interrupted = false;     // a SIGINT cut the rounds short
};

// The cell that runs the `turn`-th single round (0-based) among `cells`: forward through the list,
// then back. For two cells, variant_of_round().
std::size_t cell_of_turn(int turn, std::size_t cells);

// Called before each single round with the cell's index and its round (0-based).
using TurnProgressFn = std::function<void(std::size_t cell, int round)>;

// Times every one of `cells` (at least one) for plan.rounds rounds each, in the order
// cell_of_turn() gives, as measure_interleaved() does for two: `run`'s engines on a scene, `sweep`'s
// points of one engine on one scene.
RoundRobinRuns measure_round_robin(std::span<const TimedCell> cells, const InterleavePlan& plan,
                                   const TurnProgressFn& progress = {});

// "fx2d@A": the name a variant's runs carry in a result file.
std::string variant_engine_name(std::string_view engine, Variant variant);

// A result file written by `fx2d-bench ab` (every run's engine named X@A or X@B, both present),
// split back into A's and B's runs named X, each with the file's provenance and scenes; nullopt
// for any other file. What lets `fx2d-bench compare ab.h5` judge B against A.
struct VariantResults {
  ResultSet a;
  ResultSet b;
};
std::optional<VariantResults> split_variants(const ResultSet& results);

}  // namespace fxbench
