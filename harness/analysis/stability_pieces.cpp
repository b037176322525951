// A stability search spread over pieces: see stability_pieces.h.
#include "analysis/stability_pieces.h"

#include <algorithm>
#include <cstdio>

#include "common/errors.h"
#include "common/shard.h"

namespace fxbench {
std::vector<Evaluation> search_piece(const StabilityTest& test, SearchSpec& search, const EngineCapabilities& capabilities,
                                     int piece, int pieces, const ProbeSource& probes) {
  std::vector<Evaluation> found;
  std::map<double, Verdict> exact;
  const auto record = [&](double parameter, const Verdict& verdict) {
    found.push_back({parameter, verdict});
    exact.emplace(parameter, verdict);
    return verdict;
  };
  // The walk on foresight.
  std::vector<double> predicted_passes;
  const SearchSpec as_given = search;
  find_engine_boundary(test, search, capabilities, [&](double parameter) {
    if (const std::optional<Verdict> settled = probes.foresee(parameter)) return record(parameter, *settled);
    predicted_passes.push_back(parameter);
    return Verdict{};
  });
  // This piece's passes, run to the end: dealt by cost with the rule that deals work to shards.
  std::vector<double> costs;
  for (const double parameter : predicted_passes) costs.push_back(probes.cost(parameter));
  const std::vector<int> owner = assign_parts(costs, pieces);
  std::vector<double> others;
  for (std::size_t p = 0; p < predicted_passes.size(); ++p) {
    if (owner[p] == piece)
      record(predicted_passes[p], probes.evaluate(predicted_passes[p]));
    else
      others.push_back(predicted_passes[p]);
  }
  // The search again, the other pieces' passes taken on trust. Where a pass of this piece failed
  // after all, the true search leaves the predicted one: it bisects between the last pass and that
  // probe, where the predicted search went on beyond it, so every probe from there on is new, and
  // evaluated here (a probe of another piece never comes again; if it did, the replay would refuse).
  SearchSpec again = as_given;
  find_engine_boundary(test, again, capabilities, [&](double parameter) {
    if (const auto known = exact.find(parameter); known != exact.end()) return known->second;
    if (std::ranges::find(others, parameter) != others.end()) return Verdict{};
    return record(parameter, probes.evaluate(parameter));
  });
  return found;
}

SearchResult replay_search(const SearchSpec& as_run, bool capped, const std::map<double, Verdict>& verdicts) {
  SearchResult result = find_boundary(as_run, [&](double parameter) {
    const auto known = verdicts.find(parameter);
    if (known == verdicts.end()) {
      char text[64];
      std::snprintf(text, sizeof text, "%.17g", parameter);
      throw InputError(std::string("the search needs the verdict at ") + text + ", which no piece found");
    }
    return known->second;
  });
  if (capped && result.outcome == Outcome::holds_to_limit) result.outcome = Outcome::engine_limit;
  return result;
}

}  // namespace fxbench
