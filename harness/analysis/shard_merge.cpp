// Joining the files of a command's shards: see shard_merge.h.
#include "analysis/shard_merge.h"

#include <algorithm>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <variant>

#include "analysis/stability_pieces.h"
#include "analysis/stability_tests.h"
#include "common/errors.h"
#include "stats/pareto.h"

namespace fxbench {
namespace {

// Where a merged row comes from.
struct RowSource {
  std::size_t file = 0;
  std::size_t row = 0;
};

template <class T>
const T& attribute(const ShardFile& file, const std::string& name) {
  for (const auto& [key, value] : file.table.attributes)
    if (key == name && std::holds_alternative<T>(value)) return std::get<T>(value);
  throw InputError(file.path + ": " + file.table.path + ": missing attribute " + name +
                   "; expected a file written by sweep or stability with --shard");
}

// The column `name` of values of type T, of a shard's table or of the merged one (whose columns
// are the first shard's, so `path` names that file).
template <class T, class Table>
auto& column(Table& table, const std::string& path, const std::string& name) {
  for (auto& candidate : table.columns)
    if (candidate.name == name && std::holds_alternative<std::vector<T>>(candidate.values))
      return std::get<std::vector<T>>(candidate.values);
  throw InputError(path + ": " + table.path + ": missing column " + name + ", or not of the type written");
}

// The build that measured a file: shards of two builds never merge.
std::string build_of(const Provenance& provenance) {
  return provenance.fx2d_version + " " + provenance.fx2d_git_revision + " " + provenance.build_type + " " +
         provenance.compiler;
}

// Each column's name and type, in order: what gathering rows from several files relies on.
std::string layout_of(const H5Table& table) {
  std::string layout;
  for (const H5Column& column : table.columns) layout += column.name + ":" + std::to_string(column.values.index()) + " ";
  return layout;
}

void check_same_work(const std::vector<ShardFile>& files) {
  const ShardFile& first = files.front();
  std::set<int> shards;
  for (const ShardFile& file : files) {
    const auto refuse = [&](const std::string& what, const std::string& theirs, const std::string& ours) {
      throw InputError(file.path + ": " + what + " '" + theirs + "', but " + first.path + " has '" + ours + "'");
    };
    if (file.table.path != first.table.path) refuse("table", file.table.path, first.table.path);
    if (layout_of(file.table) != layout_of(first.table) ||
        (file.evaluations && layout_of(*file.evaluations) != layout_of(*first.evaluations)))
      refuse("columns", layout_of(file.table), layout_of(first.table));
    if (build_of(file.results.provenance) != build_of(first.results.provenance))
      refuse("build (revisions differ)", build_of(file.results.provenance), build_of(first.results.provenance));
    if (file.work_list != first.work_list) refuse("work list (scenes, engines or settings differ)", file.work_list, first.work_list);
    if (file.shard.count != first.shard.count) refuse("shard count", file.shard.text(), first.shard.text());
    if (!shards.insert(file.shard.index).second) throw InputError(file.path + ": shard " + file.shard.text() + " given twice");
  }
}

// The piece a row holds and how many its item has: 0 of 1 in a table without pieces (a sweep's).
std::pair<std::int32_t, std::int32_t> piece_of(const ShardFile& file, std::size_t row) {
  const bool has_pieces = std::ranges::any_of(file.table.columns, [](const H5Column& c) { return c.name == "pieces"; });
  if (!has_pieces) return {0, 1};
  return {column<std::int32_t>(file.table, file.path, "piece").at(row), column<std::int32_t>(file.table, file.path, "pieces").at(row)};
}

std::string piece_name(std::int32_t item, std::pair<std::int32_t, std::int32_t> piece) {
  return "work item " + std::to_string(item) +
         (piece.second > 1 ? " piece " + std::to_string(piece.first + 1) + "/" + std::to_string(piece.second) : "");
}

std::string missing_shards(const std::vector<ShardFile>& files) {
  std::string missing;
  for (int k = 1; k <= files.front().shard.count; ++k)
    if (std::ranges::none_of(files, [&](const ShardFile& file) { return file.shard.index == k; }))
      missing += (missing.empty() ? "" : ", ") + std::to_string(k) + "/" + std::to_string(files.front().shard.count);
  return missing.empty() ? "" : "; shards missing: " + missing;
}

// Every work item's rows, in work-list order: one, or one per piece of a search spread over
// shards, in piece order. Refuses an item (or a piece) two shards both ran and one none ran.
std::vector<std::vector<RowSource>> rows_in_order(const std::vector<ShardFile>& files) {
  std::map<std::int32_t, std::map<std::int32_t, RowSource>> by_item;
  std::map<std::int32_t, std::int32_t> pieces_of_item;
  for (std::size_t f = 0; f < files.size(); ++f) {
    const std::vector<std::int32_t>& items = column<std::int32_t>(files[f].table, files[f].path, "work_item");
    for (std::size_t row = 0; row < items.size(); ++row) {
      const auto piece = piece_of(files[f], row);
      if (items[row] < 0 || items[row] >= files[f].work_items)
        throw InputError(files[f].path + ": work item " + std::to_string(items[row]) + " is outside the work list of " +
                         std::to_string(files[f].work_items));
      const auto [count, first_seen] = pieces_of_item.try_emplace(items[row], piece.second);
      if (piece.first < 0 || piece.first >= piece.second || count->second != piece.second)
        throw InputError(files[f].path + ": " + piece_name(items[row], piece) + " does not fit the pieces of the other files");
      const auto [at, inserted] = by_item[items[row]].try_emplace(piece.first, RowSource{f, row});
      if (!inserted) throw InputError(files[f].path + ": " + piece_name(items[row], piece) + " is also in " + files[at->second.file].path);
    }
  }
  const std::int32_t total = files.front().work_items;
  std::vector<std::vector<RowSource>> rows;
  for (std::int32_t item = 0; item < total; ++item) {
    const auto pieces = pieces_of_item.find(item);
    if (pieces == pieces_of_item.end())
      throw InputError("merge: work item " + std::to_string(item) + " of " + std::to_string(total) + " is in no file given" +
                       missing_shards(files));
    rows.emplace_back();
    for (std::int32_t piece = 0; piece < pieces->second; ++piece) {
      const auto source = by_item[item].find(piece);
      if (source == by_item[item].end())
        throw InputError("merge: " + piece_name(item, {piece, pieces->second}) + " is in no file given" + missing_shards(files));
      rows.back().push_back(source->second);
    }
  }
  return rows;
}

// The table `path` of every file, its rows gathered in `rows` order.
H5Table gathered(const std::vector<const H5Table*>& tables, const std::vector<RowSource>& rows) {
  H5Table merged{tables.front()->path, tables.front()->attributes, {}};
  for (const H5Column& first : tables.front()->columns) {
    H5Column out{first.name, first.units, {}};
    std::visit(
        [&](const auto& typed) {
          std::remove_cvref_t<decltype(typed)> values;
          for (const RowSource& source : rows) {
            const auto& from = std::get<std::remove_cvref_t<decltype(typed)>>(
                std::ranges::find(tables[source.file]->columns, first.name, &H5Column::name)->values);
            values.push_back(from.at(source.row));
          }
          out.values = std::move(values);
        },
        first.values);
    merged.columns.push_back(std::move(out));
  }
  return merged;
}

void set_attribute(H5Table& table, const std::string& name, std::variant<std::string, double, std::int32_t> value) {
  for (auto& [key, current] : table.attributes)
    if (key == name) current = value;
}

// Row i's run, `run_of[i]` of its file, appended to `results` in row order, with its scene where
// the scene first comes, as the unsharded command lists them.
void gather_runs(const std::vector<ShardFile>& files, const std::vector<RowSource>& rows,
                 const std::vector<std::size_t>& run_of, ResultSet& results) {
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const ShardFile& file = files[rows[i].file];
    if (run_of[i] >= file.results.runs.size())
      throw InputError(file.path + ": a row names run " + std::to_string(run_of[i]) + ", which is not in /runs");
    results.runs.push_back(file.results.runs[run_of[i]]);
    const std::string& hash = results.runs.back().scene_hash;
    const auto scene = std::ranges::find(file.results.scenes, hash, &SceneRecord::hash);
    if (scene == file.results.scenes.end()) throw InputError(file.path + ": no /scenes entry for scene hash " + hash);
    if (std::ranges::find(results.scenes, hash, &SceneRecord::hash) == results.scenes.end()) results.scenes.push_back(*scene);
  }
}

// A sweep: the runs in the merged order, the run column pointing at them, and the fronts.
void merge_sweep(const std::vector<ShardFile>& files, const std::vector<RowSource>& rows, ResultSet& results,
                 H5Table& table) {
  std::vector<std::int32_t>& run = column<std::int32_t>(table, files.front().path, "run");
  gather_runs(files, rows, std::vector<std::size_t>(run.begin(), run.end()), results);
  std::iota(run.begin(), run.end(), 0);
  const std::vector<std::int32_t>& group = column<std::int32_t>(table, files.front().path, "pareto_group");
  const std::vector<double>& cost = column<double>(table, files.front().path, "ms_per_simulated_s");
  const std::vector<double>& error = column<double>(table, files.front().path, "primary_error");
  std::vector<ParetoPoint> points;
  for (std::size_t i = 0; i < rows.size(); ++i) points.push_back({group[i], cost[i], error[i]});
  const FrontMarks marks = mark_fronts(points);
  std::vector<std::uint8_t>& on_front = column<std::uint8_t>(table, files.front().path, "on_front");
  std::vector<std::int32_t>& front_rank = column<std::int32_t>(table, files.front().path, "front_rank");
  std::vector<std::int32_t>& dominated_by = column<std::int32_t>(table, files.front().path, "dominated_by");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    on_front[i] = marks.on_front[i] ? 1 : 0;
    front_rank[i] = marks.front_rank[i];
    dominated_by[i] = marks.dominated_by[i] ? static_cast<std::int32_t>(*marks.dominated_by[i]) : -1;
  }
}

// The evaluation rows of a merged stability row, in order, and its search; a whole search's are
// its shard's own rows, a spread search's those the search replayed over its pieces' verdicts needs.
struct MergedSearch {
  std::vector<RowSource> evaluations;
  std::optional<SearchResult> replayed;  // only for a spread search
};

template <class T>
const T& cell(const ShardFile& file, const std::string& name, std::size_t row) {
  return column<T>(file.table, file.path, name).at(row);
}

template <class T>
const T& evaluation_cell(const ShardFile& file, const std::string& name, std::size_t row) {
  return column<T>(*file.evaluations, file.path, name).at(row);
}

Verdict verdict_at(const ShardFile& file, std::size_t row) {
  const std::int32_t step = evaluation_cell<std::int32_t>(file, "step", row);
  return {evaluation_cell<std::uint8_t>(file, "pass", row) != 0, evaluation_cell<std::string>(file, "reason", row),
          evaluation_cell<std::string>(file, "criterion", row), step < 0 ? std::nullopt : std::optional<int>(step)};
}

// The search the pieces in `pieces` ran apart, replayed over the verdicts they found (which must
// agree where two found the same).
MergedSearch replayed_search(const std::vector<ShardFile>& files, const std::vector<RowSource>& pieces) {
  std::map<double, Verdict> verdicts;
  std::map<double, RowSource> found_in;
  for (const RowSource& piece : pieces) {
    const ShardFile& file = files[piece.file];
    const auto first = static_cast<std::size_t>(cell<std::int32_t>(file, "first_evaluation", piece.row));
    for (std::size_t e = first; e < first + static_cast<std::size_t>(cell<std::int32_t>(file, "evaluation_count", piece.row)); ++e) {
      const double parameter = evaluation_cell<double>(file, "parameter", e);
      const Verdict verdict = verdict_at(file, e);
      const auto [known, inserted] = verdicts.emplace(parameter, verdict);
      if (!inserted && (known->second.pass != verdict.pass || known->second.reason != verdict.reason))
        throw InputError(file.path + ": its verdict at " + evaluation_cell<std::string>(file, "overrides", e) + " differs from " +
                         files[found_in[parameter].file].path + "'s: the engine is not deterministic");
      found_in.try_emplace(parameter, RowSource{piece.file, e});
    }
  }
  const ShardFile& file = files[pieces.front().file];
  const std::string& name = cell<std::string>(file, "test", pieces.front().row);
  const auto test = std::ranges::find(stability_suite(), name, &StabilityTest::name);
  if (test == stability_suite().end()) throw InputError(file.path + ": test " + name + " is not in this build's suite");
  SearchSpec as_run = test->search;
  as_run.limit = cell<double>(file, "limit", pieces.front().row);
  const bool quick = attribute<std::int32_t>(file, "quick") != 0;
  const bool capped = as_run.limit != (quick ? test->quick_limit : test->search.limit);
  MergedSearch merged;
  try {
    merged.replayed = replay_search(as_run, capped, verdicts);
  } catch (const InputError& error) {
    throw InputError("merge: " + name + " on " + cell<std::string>(file, "engine", pieces.front().row) + ": " + error.what());
  }
  for (const Evaluation& evaluation : merged.replayed->evaluations) merged.evaluations.push_back(found_in.at(evaluation.parameter));
  return merged;
}

MergedSearch whole_search(const std::vector<ShardFile>& files, const RowSource& source) {
  MergedSearch merged;
  const ShardFile& file = files[source.file];
  const auto first = static_cast<std::size_t>(cell<std::int32_t>(file, "first_evaluation", source.row));
  for (std::size_t e = 0; e < static_cast<std::size_t>(cell<std::int32_t>(file, "evaluation_count", source.row)); ++e)
    merged.evaluations.push_back({source.file, first + e});
  return merged;
}

// Row i of the merged table made the spread search's: its result, and piece 0 of 1.
void write_result(H5Table& table, const std::string& path, std::size_t i, const SearchResult& result) {
  const double none = std::numeric_limits<double>::quiet_NaN();
  const Verdict failure = first_failure(result);
  column<std::string>(table, path, "outcome").at(i) = to_string(result.outcome);
  column<double>(table, path, "last_pass").at(i) = result.last_pass.value_or(none);
  column<double>(table, path, "first_fail").at(i) = result.first_fail.value_or(none);
  column<std::string>(table, path, "failure").at(i) = failure.reason;
  column<std::string>(table, path, "failed_criterion").at(i) = failure.criterion;
  column<std::int32_t>(table, path, "failed_step").at(i) = failure.step.value_or(-1);
  column<std::int32_t>(table, path, "piece").at(i) = 0;
  column<std::int32_t>(table, path, "pieces").at(i) = 1;
}

// A stability table: each merged row's evaluations after the previous row's, pointing at it; a
// search spread over pieces joined into one row.
H5Table merged_evaluations(const std::vector<ShardFile>& files, const std::vector<std::vector<RowSource>>& rows, H5Table& table) {
  std::vector<const H5Table*> evaluation_tables;
  std::vector<RowSource> evaluation_rows;
  for (const ShardFile& file : files) evaluation_tables.push_back(&*file.evaluations);
  const std::string& path = files.front().path;
  std::vector<std::int32_t> first;
  std::vector<std::int32_t> count;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const MergedSearch search = rows[i].size() == 1 ? whole_search(files, rows[i].front()) : replayed_search(files, rows[i]);
    if (search.replayed) write_result(table, path, i, *search.replayed);
    first.push_back(static_cast<std::int32_t>(evaluation_rows.size()));
    count.push_back(static_cast<std::int32_t>(search.evaluations.size()));
    evaluation_rows.insert(evaluation_rows.end(), search.evaluations.begin(), search.evaluations.end());
  }
  column<std::int32_t>(table, path, "first_evaluation") = first;
  column<std::int32_t>(table, path, "evaluation_count") = count;
  H5Table evaluations = gathered(evaluation_tables, evaluation_rows);
  std::vector<std::int32_t>& owner = column<std::int32_t>(evaluations, path, "row");
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (std::size_t e = 0; e < static_cast<std::size_t>(count[i]); ++e) owner[static_cast<std::size_t>(first[i]) + e] = static_cast<std::int32_t>(i);
  return evaluations;
}

}  // namespace

void read_shard_attributes(ShardFile& file) {
  file.shard = parse_shard(attribute<std::string>(file, "shard"), file.path + ": attribute shard");
  file.work_items = attribute<std::int32_t>(file, "work_items");
  file.work_list = attribute<std::string>(file, "work_list");
}

MergedFile merge_shards(std::vector<ShardFile> files) {
  check_same_work(files);
  std::ranges::sort(files, {}, [](const ShardFile& file) { return file.shard.index; });
  const std::vector<std::vector<RowSource>> item_rows = rows_in_order(files);
  std::vector<RowSource> rows;  // each item's first row: the only one but for a spread search
  for (const auto& pieces : item_rows) rows.push_back(pieces.front());
  MergedFile merged;
  merged.results.provenance = files.front().results.provenance;
  if (files.front().table.path == "/shard") {
    // A run's shards: the runs in order make the file the unsharded run writes, /shard and all.
    std::vector<std::size_t> run_of;
    for (const RowSource& source : rows) run_of.push_back(source.row);
    gather_runs(files, rows, run_of, merged.results);
    return merged;
  }
  std::vector<const H5Table*> tables;
  for (const ShardFile& file : files) tables.push_back(&file.table);
  merged.tables.push_back(gathered(tables, rows));
  H5Table& table = merged.tables.front();
  set_attribute(table, "shard", std::string("1/1"));
  table.attributes.emplace_back("merged_shards", static_cast<std::int32_t>(files.size()));
  // The provenance is shard 1's; where every other shard ran is kept here, one "K/N host" each.
  std::string hosts;
  for (const ShardFile& file : files)
    hosts += (hosts.empty() ? "" : "; ") + file.shard.text() + " " + file.results.provenance.hostname;
  table.attributes.emplace_back("shard_hosts", hosts);
  if (files.front().evaluations)
    merged.tables.push_back(merged_evaluations(files, item_rows, table));
  else
    merge_sweep(files, rows, merged.results, table);
  return merged;
}

}  // namespace fxbench
