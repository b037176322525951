// One stability search spread over shards: when a single engine x test search costs more than a
// shard's fair share (common/shard.h), its pieces run in different processes, each the full cost
// of only some of its probes, and `fx2d-bench merge` joins what they found into the search the
// unsharded command runs.
//
// The search itself (find_boundary) is unchanged; only who evaluates which probe is. Each piece
// first walks the search on predictions, which cost nothing: the boundary the pair's search found
// when it was last measured (analysis/stability_costs.h), every value no harder than its last pass
// predicted to pass and every harder one to fail. The probes of that predicted search are dealt
// to the pieces by their predicted cost (a failure that settles early is cheap, a pass runs to the
// end), and each piece evaluates its own, once, in one process only. The piece then walks the
// search again over its exact verdicts and the others' predictions; where one of its own verdicts
// contradicts the prediction, the true search leaves the predicted one there for probes the
// predicted search never made (it brackets or bisects on the other side of that probe), and this
// piece follows it alone, evaluating each. So whatever the
// verdicts, the probes of the true search are all in some piece: up to the first wrong prediction
// on it each is a probe of the predicted search, which its owner evaluated, and from that probe on
// its owner went on alone. A stale prediction costs balance (one piece finishes the search),
// never correctness.
//
// Invariant: replay_search over the union of the pieces' verdicts returns exactly the result
// find_boundary gives with the whole evaluations, for any number of pieces and any predictions.
#pragma once

#include <functional>
#include <map>
#include <vector>

#include "analysis/stability_tests.h"

namespace fxbench {

// How a piece gets its verdicts, all for one engine and test.
struct ProbeSource {
  // Whether `parameter` is predicted to pass.
  std::function<bool(double)> predict;
  // The exact verdict.
  std::function<Verdict(double)> evaluate;
  // What evaluating `parameter` is predicted to cost, in any unit, when it passes (`passes`) or
  // fails: how the probes are dealt.
  std::function<double(double parameter, bool passes)> cost;
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
