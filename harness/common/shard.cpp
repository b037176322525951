// Parsing --shard, the longest-processing-time split and the work list's identity; invariants in
// shard.h.
#include "common/shard.h"

#include <algorithm>
#include <charconv>
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

std::vector<int> assign_parts(std::span<const double> costs, int parts) {
  std::vector<std::size_t> order(costs.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::ranges::stable_sort(order, [&](std::size_t a, std::size_t b) { return costs[a] > costs[b]; });
  std::vector<double> load(static_cast<std::size_t>(parts), 0.0);
  std::vector<int> part_of(costs.size(), 0);
  for (std::size_t item : order) {
    const auto lightest = std::ranges::min_element(load);  // the first of equals: the lower part
    part_of[item] = static_cast<int>(lightest - load.begin());
    *lightest += costs[item];
  }
  return part_of;
}

std::vector<std::size_t> items_of(const Shard& shard, std::span<const double> costs) {
  const std::vector<int> part_of = assign_parts(costs, shard.count);
  std::vector<std::size_t> items;
  for (std::size_t item = 0; item < part_of.size(); ++item)
    if (part_of[item] == shard.index - 1) items.push_back(item);
  return items;
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
