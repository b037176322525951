// A stability search spread over pieces: see stability_pieces.h.
#include "analysis/stability_pieces.h"

#include <algorithm>
#include <cstdio>

#include "common/errors.h"
#include "common/shard.h"

namespace fxbench {
std::vector<Evaluation> search_piece(const StabilityTest& test, SearchSpec& search, const EngineCapabilities& capabilities,
                                     int piece, int pieces, const ProbeSource& probes) {
  const auto verdict_of = [](bool passes) { return passes ? Verdict{} : Verdict{false, "predicted", "", std::nullopt}; };
  // The walk on predictions.
  std::vector<double> predicted_probes;
  std::vector<double> costs;
  std::map<double, bool> predicted;
  const SearchSpec as_given = search;
  find_engine_boundary(test, search, capabilities, [&](double parameter) {
    const bool passes = probes.predict(parameter);
    predicted_probes.push_back(parameter);
    costs.push_back(probes.cost(parameter, passes));
    predicted.emplace(parameter, passes);
    return verdict_of(passes);
  });
  // This piece's probes, dealt by cost with the rule that deals work to shards, evaluated.
  std::vector<Evaluation> found;
  std::map<double, Verdict> exact;
  const auto record = [&](double parameter, const Verdict& verdict) {
    found.push_back({parameter, verdict});
    exact.emplace(parameter, verdict);
    return verdict;
  };
  const std::vector<int> owner = assign_parts(costs, pieces);
  for (std::size_t p = 0; p < predicted_probes.size(); ++p)
    if (owner[p] == piece) record(predicted_probes[p], probes.evaluate(predicted_probes[p]));
  // The search again, the other pieces' probes taken as predicted. Where a verdict of this piece
  // contradicts its prediction, the true search leaves the predicted one: it bisects below that
  // probe where the predicted search went on beyond it, or the other way round, so every probe
  // from there on is new, and evaluated here (a probe of another piece never comes again; if it
  // did, the replay would refuse).
  SearchSpec again = as_given;
  find_engine_boundary(test, again, capabilities, [&](double parameter) {
    if (const auto known = exact.find(parameter); known != exact.end()) return known->second;
    if (const auto prediction = predicted.find(parameter); prediction != predicted.end()) return verdict_of(prediction->second);
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
