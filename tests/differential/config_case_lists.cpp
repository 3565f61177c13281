// The option lists of a configuration case (config_case_lists.hpp).
#include "config_case_lists.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>

namespace nodetrace::testing {

namespace {

constexpr std::array<const char*, 8> kPolicyNames = {"lru", "fifo", "random", "plru", "srrip", "brrip", "drrip", "opt"};
constexpr std::array<const char*, 5> kPrefetchNames = {"always", "miss", "tagged", "load-forward", "subblock"};

bool dinero_policy(const std::string& name) { return name == "lru" || name == "fifo" || name == "random"; }

std::uint32_t log2_of(std::uint64_t value) { return static_cast<std::uint32_t>(std::bit_width(value) - 1); }

}  // namespace

std::string join(const std::vector<std::string>& values, const char* separator) {
  std::string out;
  for (const auto& value : values) {
    if (!out.empty()) out += separator;
    out += value;
  }
  return out;
}

std::string assoc_text(std::uint32_t assoc) { return assoc == 0 ? "full" : std::to_string(assoc); }

// The largest byte a prefetch may reach beyond a reference, at any block and distance the lists take.
constexpr std::uint64_t kPrefetchReach = 4 * 64;

bool reaches_2_32(const std::vector<TraceRecord>& records) {
  // Sizes are at most 64: no sum below overflows.
  return std::any_of(records.begin(), records.end(), [](const TraceRecord& r) {
    return r.address >= (std::uint64_t{1} << 32) - 64 - kPrefetchReach;
  });
}

Lists make_lists(Draw& draw, const ConfigCase& c, const ConfigCaseOptions& options, bool invalidations) {
  const bool above_2_32 = reaches_2_32(c.facts.records);
  Lists l;
  const std::array<std::uint64_t, 10> block_choices = {1, 2, 4, 4, 8, 8, 8, 16, 32, 64};
  l.blocks.push_back(draw.pick(block_choices));
  if (draw.chance(25)) {
    const std::uint64_t other = draw.pick(block_choices);
    if (other != l.blocks[0]) l.blocks.push_back(other);
  }
  const std::uint64_t largest_block = *std::max_element(l.blocks.begin(), l.blocks.end());
  const auto low_k = std::max<std::uint32_t>(5, log2_of(largest_block) + 1);
  const std::uint64_t sizes = draw.between(1, 3);
  for (std::uint64_t i = 0; i < sizes; ++i) {
    const std::uint64_t size = std::uint64_t{1} << draw.between(low_k, 14);
    if (std::find(l.sizes.begin(), l.sizes.end(), size) == l.sizes.end()) l.sizes.push_back(size);
  }
  if (c.tagged) {
    const auto s = draw.below(10);
    l.schemes = s < 3 ? std::vector<std::string>{"single"} : s < 6 ? std::vector<std::string>{"split"}
                                                                   : std::vector<std::string>{"single", "split"};
    if (draw.chance(20)) std::reverse(l.schemes.begin(), l.schemes.end());
  } else {
    l.schemes = {"single"};
  }
  const bool split = std::find(l.schemes.begin(), l.schemes.end(), "split") != l.schemes.end();
  if (split && draw.chance(12)) {  // sizes of their own: one total
    const std::uint64_t total = l.sizes[0];
    l.sizes = {total};
    l.high_size = std::max<std::uint64_t>(largest_block, total >> draw.between(1, 3));
    if (draw.chance(50)) l.low_size = std::max<std::uint64_t>(largest_block, total >> draw.between(1, 2));
    if (!l.low_size && *l.high_size != total / 2) l.low_size = total - *l.high_size;  // not a power of two
    if (l.low_size && !std::has_single_bit(*l.low_size)) l.low_size = total / 2;
  }
  // The fewest blocks of any cache the lists make: every way count must fit it.
  const bool single = std::find(l.schemes.begin(), l.schemes.end(), "single") != l.schemes.end();
  std::uint64_t fewest = kTop, fewest_high = kTop;
  for (const std::uint64_t size : l.sizes) {
    const std::uint64_t high = l.high_size ? *l.high_size : (l.low_size ? size - *l.low_size : size / 2);
    const std::uint64_t low = l.low_size ? *l.low_size : size - high;
    if (single) fewest = std::min(fewest, size / largest_block);
    if (split) {
      fewest = std::min(fewest, low / largest_block);
      fewest_high = std::min(fewest_high, high / largest_block);
    }
  }
  // Under `cache` the high cache takes --assoc's ways unless --high-assoc says otherwise.
  const std::uint64_t fewest_ways = split && !l.high_assoc ? std::min(fewest, fewest_high) : fewest;
  const std::array<std::uint32_t, 7> assoc_choices = {1, 1, 2, 4, 8, 16, 0};
  const std::uint64_t assocs = draw.between(1, 3);
  for (std::uint64_t i = 0; i < assocs; ++i) {
    const std::uint32_t assoc = draw.pick(assoc_choices);
    if (assoc > fewest_ways) continue;
    if (std::find(l.assocs.begin(), l.assocs.end(), assoc) == l.assocs.end()) l.assocs.push_back(assoc);
  }
  if (l.assocs.empty()) l.assocs.push_back(1);
  std::vector<std::string> policies(kPolicyNames.begin(), kPolicyNames.end());
  const std::uint64_t count = draw.between(1, 4);
  for (std::uint64_t i = 0; i < count; ++i) {
    const std::string policy = policies[draw.below(policies.size())];
    if (std::find(l.policies.begin(), l.policies.end(), policy) == l.policies.end()) l.policies.push_back(policy);
  }
  if (std::find(l.policies.begin(), l.policies.end(), "opt") != l.policies.end()) {
    if (options.avoids('b') && invalidations) {
      l.policies.erase(std::find(l.policies.begin(), l.policies.end(), "opt"));
      if (l.policies.empty()) l.policies.push_back("lru");
    } else if (options.avoids('a')) {
      std::stable_partition(l.policies.begin(), l.policies.end(), [](const auto& p) { return p == "opt"; });
    }
  }
  if (split) {
    const bool markers = !c.facts.nodes_per_level.empty() && !c.facts.nodes_per_level[0].empty();
    if (markers && draw.chance(60)) l.split_levels.push_back("auto");
    const std::uint64_t levels = l.split_levels.empty() ? draw.between(1, 2) : draw.below(2);
    for (std::uint64_t i = 0; i < levels; ++i) {
      const std::string k = std::to_string(draw.below(10));
      if (std::find(l.split_levels.begin(), l.split_levels.end(), k) == l.split_levels.end()) {
        l.split_levels.push_back(k);
      }
    }
    const auto h = draw.below(3);
    l.high_policies = h == 0 ? std::vector<std::string>{"retain"} : h == 1 ? std::vector<std::string>{"cache"}
                                                                           : std::vector<std::string>{"cache", "retain"};
    if (draw.chance(12)) l.high_assoc = draw.chance(50) ? 1u : std::min<std::uint64_t>(2, fewest_high);
    if (draw.chance(12)) l.high_assoc = 0;
    l.count_loads = draw.chance(20);
  }
  const bool dinero_only = std::all_of(l.policies.begin(), l.policies.end(), dinero_policy);
  if (!split && dinero_only && draw.chance(25) && !(options.avoids('h') && above_2_32)) {
    l.fetch = draw.pick(kPrefetchNames);
    const bool in_block = l.fetch == "load-forward" || l.fetch == "subblock";
    if (draw.chance(60)) l.distance = in_block ? 1 : static_cast<std::uint32_t>(draw.between(1, 3));
  }
  const bool lru_fifo = std::all_of(l.policies.begin(), l.policies.end(),
                                    [](const auto& p) { return p == "lru" || p == "fifo"; });
  if (l.fetch == "demand" && c.facts.units > 1 && draw.chance(55)) l.private_units = true;
  if (l.fetch == "demand" && lru_fifo && draw.chance(30)) {
    reference::L2Config l2;
    l2.size = std::uint64_t{1} << draw.between(7, 15);
    l.l2_defaults = l2.size >= 512 && draw.chance(30);
    if (!l.l2_defaults) {
      l2.block = std::uint64_t{4} << draw.below(5);
      const std::array<std::uint32_t, 5> ways = {1, 2, 4, 8, 0};
      l2.assoc = draw.pick(ways);
      if (l2.assoc > l2.size / l2.block) l2.assoc = 1;
      l2.policy = draw.chance(50) ? Policy::Lru : Policy::Fifo;
    }
    l.l2 = l2;
  }
  const bool has_opt = std::find(l.policies.begin(), l.policies.end(), "opt") != l.policies.end();
  if (c.treelet_maps && l.fetch == "demand" && !l.private_units && !l.l2 && !has_opt && draw.chance(70)) {
    const std::array<const char*, 2> kinds = {"treelet", "treelet-low"};
    const std::uint64_t count = draw.between(1, 3);
    for (std::uint64_t i = 0; i < count; ++i) {
      std::string spec = draw.pick(kinds);
      if (draw.chance(15)) spec = "none";
      if (spec != "none" && draw.chance(60)) spec += fmt::format(":{}", std::uint64_t{1} << draw.between(0, 11));
      if (std::find(l.prefetches.begin(), l.prefetches.end(), spec) == l.prefetches.end()) l.prefetches.push_back(spec);
    }
  }
  if (c.form == 'b') l.other.insert(l.other.end(), {"--informat", "binary"});
  if (!c.container && c.form != 'b' && draw.chance(20)) {
    l.other.insert(l.other.end(), {"--informat", c.form == 'd' ? "din" : "xdin"});
  }
  if (!c.container && c.tagged) l.other.push_back("--tags-are-levels");
  if (draw.chance(30)) l.other.insert(l.other.end(), {"--threads", std::to_string(draw.between(1, 3))});
  if (c.facts.units > 1 && !l.private_units && draw.chance(30)) l.other.insert(l.other.end(), {"--units", "shared"});
  return l;
}

// The arguments of `lists` with the given value lists (a list run, or one configuration alone).
std::vector<std::string> arguments(const Lists& l, const std::vector<std::string>& sizes,
                                   const std::vector<std::string>& blocks, const std::vector<std::string>& assocs,
                                   const std::vector<std::string>& policies, const std::vector<std::string>& schemes,
                                   const std::vector<std::string>& split_levels,
                                   const std::vector<std::string>& high_policies) {
  std::vector<std::string> args = {"--size", join(sizes), "--block", join(blocks), "--assoc", join(assocs),
                                   "--policy", join(policies), "--scheme", join(schemes)};
  if (!split_levels.empty()) args.insert(args.end(), {"--split-level", join(split_levels)});
  if (!high_policies.empty()) args.insert(args.end(), {"--high-policy", join(high_policies)});
  const bool split = std::find(schemes.begin(), schemes.end(), "split") != schemes.end();
  if (split) {
    if (l.high_size) args.insert(args.end(), {"--high-size", std::to_string(*l.high_size)});
    if (l.low_size) args.insert(args.end(), {"--low-size", std::to_string(*l.low_size)});
    if (l.high_assoc) args.insert(args.end(), {"--high-assoc", assoc_text(*l.high_assoc)});
    if (l.count_loads) args.push_back("--count-loads");
  }
  if (l.fetch != "demand") args.insert(args.end(), {"--fetch", l.fetch});
  if (l.distance) args.insert(args.end(), {"--prefetch-distance", std::to_string(*l.distance)});
  if (!l.prefetches.empty()) args.insert(args.end(), {"--prefetch", join(l.prefetches)});
  if (l.private_units) args.insert(args.end(), {"--units", "private"});
  if (l.l2) {
    args.insert(args.end(), {"--l2-size", std::to_string(l.l2->size)});
    if (!l.l2_defaults) {
      args.insert(args.end(), {"--l2-block", std::to_string(l.l2->block), "--l2-assoc", assoc_text(l.l2->assoc),
                               "--l2-policy", l.l2->policy == Policy::Lru ? "lru" : "fifo"});
    }
  }
  args.insert(args.end(), l.other.begin(), l.other.end());
  args.insert(args.end(), {"--format", "csv"});
  return args;
}

std::string prefetch_text(const Config& config) {
  if (!config.prefetch) return "none";
  const std::string kind = config.prefetch_low ? "treelet-low" : "treelet";
  return config.prefetch_bytes == 0 ? kind : fmt::format("{}:{}", kind, config.prefetch_bytes);
}

std::vector<std::string> texts(const std::vector<std::uint64_t>& values) {
  std::vector<std::string> out;
  for (const auto v : values) out.push_back(std::to_string(v));
  return out;
}

std::vector<std::string> assoc_texts(const std::vector<std::uint32_t>& values) {
  std::vector<std::string> out;
  for (const auto v : values) out.push_back(assoc_text(v));
  return out;
}


}  // namespace nodetrace::testing
