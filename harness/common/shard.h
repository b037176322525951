// Sharding a command's work across machines: `--shard K/N` picks the K-th of N parts of a work
// list (sweep points, stability test x engine pairs, run scene x engine cells), so that N jobs of
// an ordinary scheduler (a CI job matrix, a Slurm array) each run one part and write their own
// result file, which `fx2d-bench merge` joins.
//
// Invariants: the split is a pure function of the work list's costs and N, so every machine that
// is given the same work list computes the same parts; every item belongs to exactly one part;
// the parts are balanced by cost, not by count, with the longest-processing-time rule (items in
// decreasing cost, each to the part with the least cost so far, ties to the lower part and the
// earlier item), which keeps the largest part within 4/3 of the best possible. An item that may be
// spread (a stability search, whose probes its pieces share: analysis/stability_pieces.h) and
// costs more than a part's fair share (the total over N) is cut into pieces of equal cost, as many
// as it has fair shares (rounded up, at most N), each on a different part; one piece runs it whole.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace fxbench {

struct Shard {
  int index = 1;  // K, 1-based
  int count = 1;  // N; 1 is the whole work list

  std::string text() const { return std::to_string(index) + "/" + std::to_string(count); }
};

// The environment variables `--shard auto` reads, in order: the first pair that is set wins.
// SLURM_ARRAY_TASK_ID is taken as 0-based (an array declared --array=0-(N-1)), as
// FX2D_SHARD_INDEX is (a CI matrix index).
struct ShardEnvironment {
  const char* index;
  const char* count;
};
inline constexpr ShardEnvironment shard_environments[] = {
    {"FX2D_SHARD_INDEX", "FX2D_SHARD_COUNT"},
    {"SLURM_ARRAY_TASK_ID", "SLURM_ARRAY_TASK_COUNT"},
};

// "K/N" with 1 <= K <= N, or "auto" (shard_environments). Throws InputError naming `option` and
// what was expected.
Shard parse_shard(const std::string& text, const std::string& option = "--shard");

// For each item of the work list, the 0-based part it belongs to, by longest processing time.
std::vector<int> assign_parts(std::span<const double> costs, int parts);

// The indices of the items `shard` runs, in work-list order.
std::vector<std::size_t> items_of(const Shard& shard, std::span<const double> costs);

// A piece of a work item: the item, and which of its `pieces` (0-based) a part runs.
struct ItemPiece {
  std::size_t item = 0;
  int piece = 0;
  int pieces = 1;
};

// The pieces `shard` runs, in work-list order, items marked in `spreadable` spread as above; with
// nothing spread, the items of items_of, each whole.
std::vector<ItemPiece> pieces_of(const Shard& shard, std::span<const double> costs, const std::vector<bool>& spreadable);

// An identity of the whole work list: a hash of every item's key in order, so two shards built
// from different scenes, settings or builds of the list never merge.
std::string work_list_identity(std::span<const std::string> item_keys);

}  // namespace fxbench
