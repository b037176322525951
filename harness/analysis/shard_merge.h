// Joining the result files of a command's shards (`--shard K/N`, common/shard.h) into the file the
// unsharded command writes: the checks that they are shards of one work list by one build, each
// work item exactly once, and the join itself, with what indexes across rows recomputed (a
// sweep's Pareto fronts and run indices, a stability table's evaluation indices). Reads and writes
// no file: `fx2d-bench merge` (commands/merge.cpp) does, through storage/.
//
// Invariant: the merged table holds exactly the rows of the unsharded command, in its order,
// every column taken from the shard that ran the row; only the columns that index across rows are
// rewritten.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/column_tables.h"
#include "common/results.h"
#include "common/shard.h"

namespace fxbench {

// One shard's file as read: its runs, its table (/sweep, /stability or a run's /shard) and what
// the table's attributes say of the shard.
struct ShardFile {
  std::string path;
  ResultSet results;
  H5Table table;                       // /sweep or /stability
  std::optional<H5Table> evaluations;  // /stability/evaluations
  Shard shard;
  std::int32_t work_items = 0;
  std::string work_list;
};

// The shard, the size and the identity of the work list, from the table's attributes. Throws
// InputError naming `file.path` when one is missing or malformed.
void read_shard_attributes(ShardFile& file);

// What the unsharded command would have written: its runs and scenes, and its tables (none for
// the shards of a run, whose /shard the runs themselves make).
struct MergedFile {
  ResultSet results;
  std::vector<H5Table> tables;
};

// Refuses, one line each (InputError), files of different tables, columns, builds, work lists or
// shard counts, a shard given twice, a work item in two files or in none.
MergedFile merge_shards(std::vector<ShardFile> files);

}  // namespace fxbench
