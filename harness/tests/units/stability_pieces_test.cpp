// Tests of a stability search spread over pieces (stability_pieces.h) on synthetic verdicts: for
// every number of pieces, the verdicts the pieces find, replayed, give exactly the search
// find_boundary runs alone, whether the predicted boundary is right, wrong either way, or the
// verdicts are not monotone at all; and when the prediction is right, each probe is evaluated by
// one piece only, and the pieces' predicted costs are close.
#include "analysis/stability_pieces.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "common/errors.h"

namespace fxbench {
namespace {

// What a probe truly gives, and what a piece predicts it gives.
struct Truth {
  std::function<bool(double)> passes;
  std::function<bool(double)> predicted;
};

// A pass costs its parameter squared (bodies of a pyramid grow so), a failure a tenth of that.
double cost_of(double parameter, bool passes) { return parameter * parameter * (passes ? 1.0 : 0.1); }

Verdict verdict_of(const Truth& truth, double parameter) {
  if (truth.passes(parameter)) return {};
  return {false, "failed at " + std::to_string(parameter), "moved", 30};
}

struct PieceRun {
  std::vector<Evaluation> found;
  int evaluations = 0;  // probes evaluated
};

PieceRun run_piece(const StabilityTest& test, const Truth& truth, int piece, int pieces) {
  PieceRun run;
  SearchSpec search = test.search;
  const ProbeSource source{truth.predicted,
                           [&](double parameter) {
                             ++run.evaluations;
                             return verdict_of(truth, parameter);
                           },
                           cost_of};
  run.found = search_piece(test, search, EngineCapabilities{}, piece, pieces, source);
  return run;
}

// Replays the pieces' verdicts and expects the search find_boundary runs with every verdict at
// hand; returns how many probes the pieces evaluated, together.
int expect_pieces_give_the_whole_search(const StabilityTest& test, const Truth& truth, int pieces) {
  const SearchResult whole = find_boundary(test.search, [&](double parameter) { return verdict_of(truth, parameter); });
  std::map<double, Verdict> found;
  int evaluations = 0;
  for (int piece = 0; piece < pieces; ++piece) {
    const PieceRun run = run_piece(test, truth, piece, pieces);
    evaluations += run.evaluations;
    for (const Evaluation& evaluation : run.found) {
      EXPECT_EQ(evaluation.verdict.pass, truth.passes(evaluation.parameter)) << evaluation.parameter;
      found.emplace(evaluation.parameter, evaluation.verdict);
    }
  }
  const SearchResult replayed = replay_search(test.search, false, found);
  EXPECT_EQ(replayed.outcome, whole.outcome);
  EXPECT_EQ(replayed.last_pass, whole.last_pass);
  EXPECT_EQ(replayed.first_fail, whole.first_fail);
  EXPECT_EQ(replayed.evaluations.size(), whole.evaluations.size());
  for (std::size_t i = 0; i < std::min(replayed.evaluations.size(), whole.evaluations.size()); ++i) {
    EXPECT_EQ(replayed.evaluations[i].parameter, whole.evaluations[i].parameter);
    EXPECT_EQ(replayed.evaluations[i].verdict.pass, whole.evaluations[i].verdict.pass);
    EXPECT_EQ(replayed.evaluations[i].verdict.reason, whole.evaluations[i].verdict.reason);
  }
  return evaluations;
}

StabilityTest integer_test() {
  StabilityTest test;
  test.name = "synthetic";
  test.search = {4, 128, 1, Harder::increasing, Scale::linear, true};
  return test;
}

TEST(SpreadSearch, PredictionRightEveryProbeRunsOnceAndTheReplayIsTheSearch) {
  const StabilityTest test = integer_test();
  for (const double boundary : {3.0, 4.0, 5.0, 33.0, 55.0, 63.0, 64.0, 100.0, 128.0}) {
    const auto passes = [=](double x) { return x <= boundary; };
    const Truth truth{passes, passes};
    const SearchResult whole = find_boundary(test.search, [&](double x) { return verdict_of(truth, x); });
    for (int pieces = 1; pieces <= 4; ++pieces) {
      SCOPED_TRACE("boundary " + std::to_string(boundary) + ", " + std::to_string(pieces) + " pieces");
      EXPECT_EQ(expect_pieces_give_the_whole_search(test, truth, pieces), static_cast<int>(whole.evaluations.size()));
    }
  }
}

// Two pieces of a search with a dozen probes, the prediction right: what each piece evaluates
// costs within 3% of the other (the deal is by cost; by count of probes one piece would hold the
// five largest passes).
TEST(SpreadSearch, PredictionRightTwoPiecesCostAlike) {
  const StabilityTest test = integer_test();
  for (const double boundary : {55.0, 63.0, 100.0}) {
    const auto passes = [=](double x) { return x <= boundary; };
    const Truth truth{passes, passes};
    double piece_cost[2] = {0.0, 0.0};
    for (int piece = 0; piece < 2; ++piece)
      for (const Evaluation& evaluation : run_piece(test, truth, piece, 2).found)
        piece_cost[piece] += cost_of(evaluation.parameter, evaluation.verdict.pass);
    EXPECT_LT(std::abs(piece_cost[0] - piece_cost[1]), 0.03 * (piece_cost[0] + piece_cost[1])) << "boundary " << boundary;
  }
}

TEST(SpreadSearch, WrongPredictionsEitherWayStillGiveTheSearch) {
  const StabilityTest test = integer_test();
  for (const double boundary : {4.0, 17.0, 47.0, 55.0, 100.0})
    for (const double error : {-1000.0, -20.0, -3.0, -1.0, 1.0, 3.0, 20.0, 1000.0}) {  // predicted boundary - true
      const Truth truth{[=](double x) { return x <= boundary; }, [=](double x) { return x <= boundary + error; }};
      for (int pieces = 1; pieces <= 4; ++pieces) {
        SCOPED_TRACE("boundary " + std::to_string(boundary) + ", error " + std::to_string(error) + ", " + std::to_string(pieces) + " pieces");
        expect_pieces_give_the_whole_search(test, truth, pieces);
      }
    }
}

TEST(SpreadSearch, VerdictsThatAreNotMonotoneStillGiveTheSearch) {
  StabilityTest geometric = integer_test();
  geometric.search = {1, 10000, 0.1, Harder::increasing, Scale::geometric, false};
  StabilityTest decreasing = integer_test();
  decreasing.search = {1, 0.01, 0.01, Harder::decreasing, Scale::linear, false};
  for (const StabilityTest& test : {integer_test(), geometric, decreasing})
    for (std::uint32_t seed = 1; seed <= 40; ++seed) {
      const auto hashed = [=](double x, std::uint32_t salt) {
        std::uint64_t h = std::hash<double>{}(x) ^ (std::uint64_t{seed} * 0x9e3779b97f4a7c15ULL) ^ salt;
        h ^= h >> 29;
        h *= 0xbf58476d1ce4e5b9ULL;
        return h ^ (h >> 32);
      };
      const Truth truth{[=](double x) { return hashed(x, 1) % 4 != 0; }, [=](double x) { return hashed(x, 2) % 2 == 0; }};
      for (int pieces = 2; pieces <= 3; ++pieces) {
        SCOPED_TRACE(test.search.integer ? "integer" : test.search.scale == Scale::geometric ? "geometric" : "decreasing");
        SCOPED_TRACE("seed " + std::to_string(seed) + ", " + std::to_string(pieces) + " pieces");
        expect_pieces_give_the_whole_search(test, truth, pieces);
      }
    }
}

TEST(SpreadSearch, AReplayMissingAVerdictIsRefused) {
  const StabilityTest test = integer_test();
  EXPECT_THROW(replay_search(test.search, false, {{4.0, Verdict{}}, {8.0, Verdict{}}}), InputError);
}

}  // namespace
}  // namespace fxbench
