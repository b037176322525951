// One stability search spread over shards: when a single engine x test search costs more than a
// shard's fair share (common/shard.h), its pieces run in different processes, each the full cost
// of only some of its probes, and `fx2d-bench merge` joins what they found into the search the
// unsharded command runs.
//
// The search itself (find_boundary) is unchanged; only who evaluates which probe is. Each piece
// first walks the search on foresight: every probe simulated for its first tenth of the steps,
// which for a test with a settled_failure gives a failure exactly (the whole run would stop at the
// same sample with the same verdict) and otherwise predicts a pass. The predicted passes, the
// costly probes (a pass runs to the end), are dealt to the pieces by cost; each piece runs its own
// to the end. A piece whose own probe fails after all (a late failure) then follows the true
// search beyond it, evaluating every later probe itself. So whatever the verdicts, the probes of
// the true search are all in some piece: up to the first wrong prediction each is a foreseen
// failure or a pass its owner proved, and after it the owner of that probe went on alone.
//
// Invariant: replay_search over the union of the pieces' verdicts returns exactly the result
// find_boundary gives with the whole evaluations, for any number of pieces.
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <vector>

#include "analysis/stability_tests.h"

namespace fxbench {

// The share of a probe's steps its foresight simulates.
inline constexpr double foresight_fraction = 0.1;

// How a piece gets its verdicts, all for one engine and test.
struct ProbeSource {
  // The exact verdict of `parameter` when foresight settles it (a settled failure, or a scene
  // the engine cannot build), else none: a predicted pass.
  std::function<std::optional<Verdict>(double)> foresee;
  // The exact verdict, from the whole run (going on from foresight's where it can).
  std::function<Verdict(double)> evaluate;
  // What evaluating `parameter` to the end costs, in any unit: how the passes are dealt.
  std::function<double(double)> cost;
};

// The exact verdicts piece `piece` (0-based) of `pieces` finds, in the order found. `search` is
// as run: find_engine_boundary lowers its limit to the engine's.
std::vector<Evaluation> search_piece(const StabilityTest& test, SearchSpec& search, const EngineCapabilities& capabilities,
                                     int piece, int pieces, const ProbeSource& probes);

// find_boundary over recorded verdicts: `as_run` is the search as the pieces ran it, `capped`
// whether its limit is the engine's (so holding there is Outcome::engine_limit). Throws
// InputError when a verdict the search needs is in none of `verdicts`.
SearchResult replay_search(const SearchSpec& as_run, bool capped, const std::map<double, Verdict>& verdicts);

}  // namespace fxbench
