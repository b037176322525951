// Parsing --shard, the longest-processing-time split and the work list's identity; invariants in
// shard.h.
#include "common/shard.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <numeric>
#include <optional>
#include <string_view>

#include "common/errors.h"
#include "common/hash.h"

namespace fxbench {
namespace {

// A whole number in [min, max], or nothing: the text must be digits only.
std::optional<int> whole_number(std::string_view text, int min, int max) {
  int value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size() || value < min || value > max)
    return std::nullopt;
  return value;
}

constexpr int most_parts = 100000;

Shard shard_from_environment(const std::string& option) {
  for (const ShardEnvironment& variables : shard_environments) {
    const char* index = std::getenv(variables.index);
    const char* count = std::getenv(variables.count);
    if (index == nullptr && count == nullptr) continue;
    const std::string where = option + " auto: " + variables.index + "=" + (index ? index : "(unset)") + " " +
                              variables.count + "=" + (count ? count : "(unset)");
    const std::optional<int> parts = count ? whole_number(count, 1, most_parts) : std::nullopt;
    const std::optional<int> zero_based = index ? whole_number(index, 0, most_parts - 1) : std::nullopt;
    if (!parts || !zero_based || *zero_based >= *parts)
      throw InputError(where + ": expected both set, the count >= 1 and the index in 0..count-1");
    return {*zero_based + 1, *parts};
  }
  std::string names;
  for (const ShardEnvironment& variables : shard_environments)
    names += std::string(names.empty() ? "" : " or ") + variables.index + "/" + variables.count;
  throw InputError(option + " auto: no scheduler's shard in the environment; expected " + names);
}

}  // namespace

Shard parse_shard(const std::string& text, const std::string& option) {
  if (text == "auto") return shard_from_environment(option);
  const auto slash = text.find('/');
  const std::optional<int> count =
      slash == std::string::npos ? std::nullopt : whole_number(std::string_view(text).substr(slash + 1), 1, most_parts);
  const std::optional<int> index =
      count ? whole_number(std::string_view(text).substr(0, slash), 1, *count) : std::nullopt;
  if (!index) throw InputError(option + " " + text + ": expected K/N with 1 <= K <= N, or auto");
  return {*index, *count};
}

namespace {

// The longest-processing-time rule over pieces: each, in decreasing cost, to the part with the
// least cost so far that holds no other piece of its item (ties to the lower part).
std::vector<int> assign_pieces(std::span<const double> costs, std::span<const ItemPiece> pieces, int parts) {
  std::vector<std::size_t> order(pieces.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  const auto cost = [&](std::size_t p) { return costs[pieces[p].item] / pieces[p].pieces; };
  std::ranges::stable_sort(order, [&](std::size_t a, std::size_t b) { return cost(a) > cost(b); });
  std::vector<double> load(static_cast<std::size_t>(parts), 0.0);
  std::vector<int> part_of(pieces.size(), -1);
  const auto holds_item = [&](int part, std::size_t p) {
    if (pieces[p].pieces == 1) return false;
    for (std::size_t other = 0; other < pieces.size(); ++other)
      if (part_of[other] == part && pieces[other].item == pieces[p].item) return true;
    return false;
  };
  for (std::size_t p : order) {
    int lightest = -1;
    for (int part = 0; part < parts; ++part)
      if (!holds_item(part, p) && (lightest < 0 || load[static_cast<std::size_t>(part)] < load[static_cast<std::size_t>(lightest)]))
        lightest = part;
    part_of[p] = lightest;
    load[static_cast<std::size_t>(lightest)] += cost(p);
  }
  return part_of;
}

// Every item cut into its pieces, in work-list order.
std::vector<ItemPiece> cut(std::span<const double> costs, const std::vector<bool>& spreadable, int parts) {
  const double fair_share = std::accumulate(costs.begin(), costs.end(), 0.0) / parts;
  std::vector<ItemPiece> pieces;
  for (std::size_t item = 0; item < costs.size(); ++item) {
    const int count = spreadable[item] && costs[item] > fair_share
                          ? std::min(parts, static_cast<int>(std::ceil(costs[item] / fair_share)))
                          : 1;
    for (int piece = 0; piece < count; ++piece) pieces.push_back({item, piece, count});
  }
  return pieces;
}

}  // namespace

std::vector<int> assign_parts(std::span<const double> costs, int parts) {
  const std::vector<ItemPiece> whole = cut(costs, std::vector<bool>(costs.size(), false), parts);
  return assign_pieces(costs, whole, parts);
}

std::vector<std::size_t> items_of(const Shard& shard, std::span<const double> costs) {
  std::vector<std::size_t> items;
  for (const ItemPiece& piece : pieces_of(shard, costs, std::vector<bool>(costs.size(), false))) items.push_back(piece.item);
  return items;
}

std::vector<ItemPiece> pieces_of(const Shard& shard, std::span<const double> costs, const std::vector<bool>& spreadable) {
  const std::vector<ItemPiece> pieces = cut(costs, spreadable, shard.count);
  const std::vector<int> part_of = assign_pieces(costs, pieces, shard.count);
  std::vector<ItemPiece> mine;
  for (std::size_t p = 0; p < pieces.size(); ++p)
    if (part_of[p] == shard.index - 1) mine.push_back(pieces[p]);
  return mine;
}

std::string work_list_identity(std::span<const std::string> item_keys) {
  Fnv1a64 hash;
  for (const std::string& key : item_keys) {
    hash.add(key);
    hash.add(std::string_view("\n"));
  }
  return hash.hex();
}

}  // namespace fxbench
