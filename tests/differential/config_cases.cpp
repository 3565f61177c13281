// The generator and the checks of the configuration differential test (see
// config_cases.hpp).
#include "config_cases.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <map>
#include <set>
#include <sstream>

#include "nodetrace/formats/write/trace_writer.hpp"
#include "address_stream.hpp"
#include "seeded_draw.hpp"
#include "test_support.hpp"

namespace nodetrace::testing {

namespace {

using reference::Config;
using reference::Fetch;
using reference::Policy;
using reference::TraceRecord;

constexpr std::uint64_t kTop = ~std::uint64_t{0};
constexpr std::array<const char*, 8> kPolicyNames = {"lru", "fifo", "random", "plru", "srrip", "brrip", "drrip", "opt"};
constexpr std::array<const char*, 5> kPrefetchNames = {"always", "miss", "tagged", "load-forward", "subblock"};
constexpr const char* kTypeLetters = "rwimcv";

bool dinero_policy(const std::string& name) { return name == "lru" || name == "fifo" || name == "random"; }

std::string join(const std::vector<std::string>& values, const char* separator = ",") {
  std::string out;
  for (const auto& value : values) {
    if (!out.empty()) out += separator;
    out += value;
  }
  return out;
}

// Address regions: near 0, about 2^32 (crossing it), and the top of the
// 64-bit space. Binary records hold 32 bits: their second region ends at 2^32.
struct Region {
  std::uint64_t base, span;
};

std::vector<TraceRecord> make_records(Draw& draw, const ConfigCase& c, const ConfigCaseOptions& options) {
  std::uint64_t count = 0;
  const auto size_class = draw.below(20);
  if (size_class < 6) {
    count = draw.between(20, 300);
  } else if (size_class < 17) {
    count = draw.between(300, 1200);
  } else {
    count = draw.between(1200, 3000);
  }
  std::vector<Region> regions;
  const bool binary = c.form == 'b';
  regions.push_back({draw.below(4) * 0x1000, 0x10000});
  if (draw.chance(binary ? 50 : 35)) {
    regions.push_back(binary ? Region{0xFFFF0000ull, 0x10000} : Region{0xFFFF8000ull, 0x10000});
  }
  if (!binary && draw.chance(30)) regions.push_back({kTop - 0xFFFF, 0x10000});
  if (draw.chance(30)) std::swap(regions.front(), regions.back());  // the node pool's region
  const std::uint64_t pool = regions.front().base;

  // Some traces reach the edges: the last bytes below 2^32 and below 2^64.
  const bool edges = draw.chance(25);
  // Some are aligned 8-byte nodes, as a rendered kd-tree's: no reference spans blocks of 8 bytes or more.
  const bool aligned = draw.chance(25);
  std::vector<TraceRecord> records;
  records.reserve(count);
  AddressStream stream(StreamShape{300, 8, 40, 6, 15}, [&](Draw& d) {
    const Region& region = regions[d.below(regions.size())];
    return region.base + d.below(region.span / 2);
  });
  for (std::uint64_t i = 0; i < count; ++i) {
    TraceRecord r;
    r.address = stream.next(draw);
    const auto t = draw.below(100);
    r.type = t < 55 ? 0 : t < 70 ? 1 : t < 80 ? 2 : t < 86 ? 3 : t < 91 ? 4 : 5;
    const auto s = draw.below(10);
    r.size = s < 4 ? 8 : s < 6 ? 4 : static_cast<std::uint32_t>(draw.between(1, 64));
    if (c.tagged && draw.chance(35)) {
      // A node of the top levels, where the bfl layout puts it: level l,
      // node j at (2^l - 1 + j) x 8 from the pool.
      const std::uint32_t level = static_cast<std::uint32_t>(draw.below(8));
      r.level = level;
      r.address = pool + (((std::uint64_t{1} << level) - 1) + draw.below(std::uint64_t{1} << level)) * 8;
      r.size = 8;
    } else if (c.tagged) {
      r.level = static_cast<std::uint32_t>(draw.between(8, 13));
      if (draw.chance(2)) {  // a primitive list or triangle: counted apart
        r.level.reset();
        r.other_stream = draw.chance(50) ? 'p' : 't';
      }
    }
    if (edges && draw.chance(3)) {
      const std::uint64_t end = binary || draw.chance(40) ? std::uint64_t{1} << 32 : 0;  // 0: 2^64
      r.address = end - 1 - draw.below(80);
    }
    if (aligned) {
      r.address &= ~std::uint64_t{7};
      r.size = 8;
    }
    if (binary) r.address &= 0xFFFFFFFFull;
    if (c.form == 'd') r.size = 4;  // din: Dinero IV's size
    if (options.avoids('c') && r.address > kTop - r.size + 1) r.address = kTop - r.size + 1;  // ends at 2^64 - 1
    if (options.avoids('d') && r.address > kTop - r.size) r.address = kTop - r.size;  // short of 2^64 - 1
    if (c.form == 'd') r.address &= ~std::uint64_t{3};  // din: Dinero IV's address rounded down to 4
    r.unit = static_cast<unsigned>(draw.below(c.facts.units));
    r.frame = static_cast<std::uint32_t>(i * c.facts.frames / count);
    records.push_back(r);
  }
  return records;
}

std::uint32_t log2_of(std::uint64_t value) { return static_cast<std::uint32_t>(std::bit_width(value) - 1); }

// The option lists of one case, before they are expanded.
struct Lists {
  std::vector<std::uint64_t> sizes, blocks;
  std::vector<std::uint32_t> assocs;  // 0: full
  std::vector<std::string> policies, schemes, split_levels, high_policies;
  std::optional<std::uint64_t> high_size, low_size;
  std::optional<std::uint32_t> high_assoc;
  bool count_loads = false;
  std::string fetch = "demand";
  std::optional<std::uint32_t> distance;
  bool private_units = false;
  std::optional<reference::L2Config> l2;
  bool l2_defaults = false;  // --l2-block and --l2-assoc left to their defaults (64, 8)
  std::vector<std::string> other;  // --threads, --informat, --tags-are-levels, --units shared
};

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

std::uint32_t resolved_ways(std::uint32_t assoc, std::uint64_t size, std::uint64_t block) {
  return assoc == 0 ? static_cast<std::uint32_t>(std::max<std::uint64_t>(1, size / block)) : assoc;
}

// The configurations of `l` in the report's order (size, block, ways,
// policy, scheme, split level, high policy), repeats merged as cachesim merges them
// (the high cache's ways count even under retain, where they do not matter).
std::vector<ListedConfig> expand(const Lists& l) {
  std::vector<ListedConfig> listed;
  std::set<std::string> seen;
  for (const std::uint64_t size : l.sizes) {
    for (const std::uint64_t block : l.blocks) {
      for (const std::uint32_t assoc : l.assocs) {
        for (const std::string& policy : l.policies) {
          for (const std::string& scheme : l.schemes) {
            Config config;
            config.size = size;
            config.block = block;
            config.policy = *reference::policy_named(policy);
            config.fetch = *reference::fetch_named(l.fetch);
            config.prefetch_distance = l.distance.value_or(1);
            config.private_units = l.private_units;
            config.l2 = l.l2;
            if (config.l2 && config.l2->assoc == 0) config.l2->assoc = static_cast<std::uint32_t>(l.l2->size / l.l2->block);
            std::vector<std::string> split_levels = {""}, high_policies = {""};
            if (scheme == "split") {
              config.split = true;
              config.high_size = l.high_size ? *l.high_size : (l.low_size ? size - *l.low_size : size / 2);
              config.low_size = l.low_size ? *l.low_size : size - config.high_size;
              config.size = config.high_size + config.low_size;
              config.count_loads = l.count_loads;
              config.assoc = resolved_ways(assoc, config.low_size, block);
              config.high_assoc = resolved_ways(l.high_assoc.value_or(assoc), config.high_size, block);
              split_levels = l.split_levels;
              high_policies = l.high_policies;
            } else {
              config.assoc = resolved_ways(assoc, size, block);
            }
            for (const std::string& k : split_levels) {
              for (const std::string& high : high_policies) {
                ListedConfig one;
                one.config = config;
                if (config.split) {
                  if (k != "auto") one.config.split_level = static_cast<std::uint32_t>(std::stoul(k));
                  one.config.retain = high == "retain";
                }
                const std::string key = fmt::format(
                    "{} {} {} {} {} {} {} {} {} {} {} {}", scheme, one.config.size, block, one.config.assoc, policy,
                    config.split ? high : "", one.config.high_size, one.config.low_size,
                    one.config.high_assoc, k, config.split && l.count_loads, 0);
                if (!seen.insert(key).second) continue;
                one.name = fmt::format("{} size {} block {} assoc {} policy {}{}", scheme, size, block,
                                       assoc_text(assoc), policy,
                                       config.split ? fmt::format(" K {} high {}", k, high) : "");
                one.alone_args = arguments(l, {std::to_string(size)}, {std::to_string(block)}, {assoc_text(assoc)},
                                           {policy}, {scheme}, config.split ? std::vector<std::string>{k}
                                                                            : std::vector<std::string>{},
                                           config.split ? std::vector<std::string>{high} : std::vector<std::string>{});
                listed.push_back(std::move(one));
              }
            }
          }
        }
      }
    }
  }
  return listed;
}

std::vector<std::vector<std::uint64_t>> make_nodes_per_level(const ConfigCase& c) {
  std::vector<std::vector<std::uint64_t>> frames;
  for (std::uint32_t f = 0; f < c.facts.frames; ++f) {
    std::vector<std::uint64_t> levels;
    const std::uint32_t depth = 10 + static_cast<std::uint32_t>((f + c.seed) % 4);
    for (std::uint32_t l = 0; l < depth; ++l) levels.push_back(l < 8 ? std::uint64_t{1} << l : 150 + 40 * l + 7 * f);
    frames.push_back(levels);
  }
  return frames;
}

}  // namespace

ConfigCase make_config_case(std::uint64_t seed, const ConfigCaseOptions& options) {
  Draw draw(seed);
  ConfigCase c;
  c.seed = seed;
  const auto f = draw.below(10);
  c.container = f >= 6;
  c.form = f < 2 || f >= 8 ? 'd' : f < 5 || f >= 6 ? 'D' : 'b';
  c.trace_name = fmt::format("trace.{}{}", c.form == 'd' ? "din" : c.form == 'D' ? "xdin" : "bin",
                             c.container ? ".zst" : "");
  c.tagged = c.container || (c.form != 'b' && draw.chance(75));
  c.facts.units = c.container && draw.chance(35) ? static_cast<unsigned>(draw.between(2, 4)) : 1;
  c.facts.frames = c.container ? static_cast<std::uint32_t>(draw.between(1, 3)) : 1;
  c.facts.contiguous_levels = draw.chance(70);
  if (c.container) c.facts.nodes_per_level = make_nodes_per_level(c);
  c.facts.records = make_records(draw, c, options);
  const bool invalidations = std::any_of(c.facts.records.begin(), c.facts.records.end(),
                                         [](const TraceRecord& r) { return r.type == 5; });
  // Lists until every retained high cache fits (a few cases keep one that
  // does not, and the run must fail).
  Lists lists;
  for (int attempt = 0;; ++attempt) {
    lists = make_lists(draw, c, options, invalidations);
    c.configs = expand(lists);
    if (c.configs.size() > 10) continue;
    if (attempt >= 4 || draw.chance(15)) break;
    const bool fits = std::none_of(c.configs.begin(), c.configs.end(), [&](const ListedConfig& one) {
      return one.config.split && one.config.retain && reference::simulate(c.facts, one.config).high_levels_do_not_fit;
    });
    if (fits) break;
  }
  const bool has_opt = std::find(lists.policies.begin(), lists.policies.end(), "opt") != lists.policies.end();
  c.per_level = c.tagged && !has_opt && !lists.private_units && !lists.l2 && draw.chance(25);
  c.per_frame = !has_opt && !lists.private_units && !lists.l2 && draw.chance(25);
  c.sampling_allowed = !c.per_level && !c.per_frame && !lists.private_units && !lists.l2 && lists.fetch == "demand";
  c.list_args = arguments(lists, texts(lists.sizes), texts(lists.blocks), assoc_texts(lists.assocs), lists.policies,
                          lists.schemes, lists.split_levels, lists.high_policies);

  // Odd seeds sample sets (even ones windows), unless (g) is avoided and a reference spans blocks.
  const bool spans = std::any_of(c.facts.records.begin(), c.facts.records.end(), [&](const TraceRecord& r) {
    return r.type != 4 && r.type != 5 && !r.other_stream && r.address % lists.blocks[0] + r.size > lists.blocks[0];
  });
  c.sample_sets = c.sampling_allowed && c.seed % 2 == 1 && !(options.avoids('g') && spans);
  if (c.sample_sets && spans) c.known_defect_triggers.push_back("(g) --sample-sets with references that span blocks");
  c.sets_leave_out_random = true;  // random is refused with --sample-sets (once defect i)
  if (lists.fetch != "demand" && reaches_2_32(c.facts.records)) {
    c.known_defect_triggers.push_back("(h) a prefetching --fetch with addresses from 2^32 on");
  }
  // A curve allocates caches up to 64 MB: blocks of 16 bytes or more keep each run short.
  if (lists.fetch == "demand" && !lists.l2 && !lists.private_units && lists.policies.size() <= 2 &&
      *std::min_element(lists.blocks.begin(), lists.blocks.end()) >= 16 && draw.chance(40)) {
    // Fully associative curves are one LRU stack (lru) or MIN's layered stack (opt), without invalidations.
    std::vector<std::string> assocs = assoc_texts(lists.assocs), policies = lists.policies;
    if (std::find(assocs.begin(), assocs.end(), "full") != assocs.end()) {
      if (invalidations) {
        assocs.erase(std::find(assocs.begin(), assocs.end(), "full"));
      } else {
        std::erase_if(policies, [](const std::string& p) { return p != "lru" && p != "opt"; });
      }
    }
    if (!assocs.empty() && !policies.empty()) {
      c.curve_args = {"--curve", "--block", join(texts(lists.blocks)), "--assoc", join(assocs), "--policy",
                      join(policies), "--scheme", "single", "--format", "csv"};
      for (std::size_t i = 0; i < lists.other.size(); ++i) {
        if (lists.other[i] == "--units") {
          ++i;
        } else {
          c.curve_args.push_back(lists.other[i]);
        }
      }
    }
  }
  if (has_opt && lists.policies.front() != "opt") c.known_defect_triggers.push_back("(a) opt listed after another policy");
  if (has_opt && invalidations) c.known_defect_triggers.push_back("(b) opt on a trace with invalidations");
  const bool wraps = std::any_of(c.facts.records.begin(), c.facts.records.end(), [](const TraceRecord& r) {
    return r.type != 4 && r.type != 5 && r.address > kTop - r.size + 1;
  });
  if (wraps) c.known_defect_triggers.push_back("(c) a reference past 2^64 - 1");
  const bool last_byte = std::any_of(c.facts.records.begin(), c.facts.records.end(), [](const TraceRecord& r) {
    return r.type != 4 && (r.address == kTop || (r.type != 5 && r.address > kTop - r.size));
  });
  if (last_byte && std::find(lists.blocks.begin(), lists.blocks.end(), 1u) != lists.blocks.end()) {
    c.known_defect_triggers.push_back("(d) block 2^64 - 1 (1-byte blocks)");
  }
  return c;
}

void write_config_case_trace(const ConfigCase& c, const std::filesystem::path& file) {
  if (!c.container) {
    std::string out;
    for (const TraceRecord& r : c.facts.records) {
      const std::string tag = r.level ? fmt::format(" {}", *r.level) : r.other_stream ? fmt::format(" {}", r.other_stream) : "";
      if (c.form == 'd') {
        out += fmt::format("{} {:x}{}\n", r.type, r.address + 0, tag);
      } else if (c.form == 'D') {
        out += fmt::format("{} {:x} {:x}{}\n", kTypeLetters[r.type], r.address, r.size, tag);
      } else {
        const auto a = static_cast<std::uint32_t>(r.address);
        const char bytes[8] = {static_cast<char>(a), static_cast<char>(a >> 8), static_cast<char>(a >> 16),
                               static_cast<char>(a >> 24), static_cast<char>(r.size),
                               static_cast<char>(r.size >> 8), static_cast<char>(r.type), 0};
        out.append(bytes, 8);
      }
    }
    write_file(file, out);
    return;
  }
  formats::WriterOptions options;
  options.form = c.form == 'd' ? formats::RecordForm::Din : formats::RecordForm::ExtendedDin;
  options.kind = formats::OutputKind::Container;
  options.threads = 1;
  options.records_per_data_frame = 1 + c.seed % 700;
  options.units = c.facts.units;
  options.address_digits = 16;
  nlohmann::json header;
  header["layout"] = {{"name", c.facts.contiguous_levels ? "bfl" : "dfl"}, {"node_size", 8}, {"node_base", 0}};
  auto writer = formats::TraceWriter::create(file.string(), header, options);
  std::uint32_t frame = ~std::uint32_t{0};
  for (const TraceRecord& r : c.facts.records) {
    if (r.frame != frame) {
      frame = r.frame;
      formats::AnimationFrameMarker marker;
      marker.frame = frame;
      marker.time = frame;
      marker.nodes_per_level = c.facts.nodes_per_level.at(frame);
      for (const auto n : marker.nodes_per_level) marker.nodes += n;
      marker.depth = static_cast<std::uint32_t>(marker.nodes_per_level.size());
      writer->begin_animation_frame(marker);
    }
    formats::Record record;
    record.address = r.address;
    record.size = r.size;
    record.type = static_cast<formats::AccessType>(r.type);
    record.unit = formats::traversal_unit(r.unit);
    record.tag = r.level                     ? static_cast<formats::Tag>(*r.level)
                 : r.other_stream == 'p'     ? formats::kTagPrimitiveList
                 : r.other_stream == 't'     ? formats::kTagTriangle
                                             : formats::kTagNone;
    writer->write(record);
  }
  writer->finish();
}

namespace {

using Row = std::map<std::string, std::string>;

// A row as text, for messages.
std::string row_text(const Row& row) {
  std::string text;
  for (const auto& [column, value] : row) text += (text.empty() ? "" : " ") + column + "=" + value;
  return text;
}

// The counts a row must show for `config`, column by column.
std::map<std::string, std::string> expected_cells(const Config& config, const reference::Counts& counts) {
  std::map<std::string, std::string> cells;
  auto number = [](std::uint64_t v) { return std::to_string(v); };
  cells["refs"] = number(counts.refs);
  cells["fetches"] = number(counts.fetches);
  cells["misses"] = number(counts.misses);
  cells["high_refs"] = config.split ? number(counts.high_refs) : "";
  cells["high_misses"] = config.split ? number(counts.high_misses) : "";
  cells["high_loads"] = config.split && config.retain ? number(counts.high_loads) : "";
  cells["low_refs"] = config.split ? number(counts.low_refs) : "";
  cells["low_misses"] = config.split ? number(counts.low_misses) : "";
  cells["split_level"] = config.split ? number(counts.split_level) : "";
  if (config.l2) {
    cells["l2_refs"] = number(counts.l2_refs);
    cells["l2_fetches"] = number(counts.l2_fetches);
    cells["l2_misses"] = number(counts.l2_misses);
  }
  return cells;
}

std::string compare_cells(const std::map<std::string, std::string>& expected,
                          const std::map<std::string, std::string>& row) {
  std::string out;
  for (const auto& [column, value] : expected) {
    const auto found = row.find(column);
    const std::string got = found == row.end() ? "(no column)" : found->second;
    if (got != value) out += fmt::format(" {} {} (expected {})", column, got, value);
  }
  return out;
}

std::uint64_t cell(const std::map<std::string, std::string>& row, const std::string& column) {
  const auto found = row.find(column);
  if (found == row.end() || found->second.empty()) return 0;
  return std::stoull(found->second);
}

// The Dinero IV options of a single-scheme configuration.
std::vector<std::string> dinero_arguments(const Config& config) {
  const char* policies = "lfr";
  const char* fetches = "damtls";
  std::vector<std::string> args = {"-informat", "D", "-l1-usize", std::to_string(config.size), "-l1-ubsize",
                                   std::to_string(config.block), "-l1-uassoc", std::to_string(config.assoc),
                                   "-l1-urepl", std::string(1, policies[static_cast<int>(config.policy)]),
                                   "-l1-ufetch", std::string(1, fetches[static_cast<int>(config.fetch)])};
  if (config.fetch != Fetch::Demand) args.insert(args.end(), {"-l1-upfdist", std::to_string(config.prefetch_distance)});
  if (config.l2) {
    args.insert(args.end(), {"-l2-usize", std::to_string(config.l2->size), "-l2-ubsize",
                             std::to_string(config.l2->block), "-l2-uassoc", std::to_string(config.l2->assoc),
                             "-l2-urepl", config.l2->policy == Policy::Lru ? "l" : "f"});
  }
  return args;
}

// Dinero IV's total demand fetches and misses of the cache whose section
// `section` names (l1-ucache, l2-ucache).
std::optional<std::pair<std::uint64_t, std::uint64_t>> dinero_totals(const std::string& out,
                                                                     const std::string& section) {
  const auto at = out.find(section);
  if (at == std::string::npos) return std::nullopt;
  auto number_after = [&](const std::string& label) -> std::optional<std::uint64_t> {
    const auto line = out.find(label, at);
    if (line == std::string::npos) return std::nullopt;
    std::istringstream in(out.substr(line + label.size()));
    double value = 0;
    if (!(in >> value)) return std::nullopt;
    return static_cast<std::uint64_t>(value);
  };
  const auto fetches = number_after(" Demand Fetches");
  const auto misses = number_after(" Demand Misses");
  if (!fetches || !misses) return std::nullopt;
  return std::make_pair(*fetches, *misses);
}

}  // namespace

ConfigCaseResult check_config_case(const ConfigCase& c, const Programs& programs, const std::filesystem::path& work) {
  ConfigCaseResult result;
  const auto trace = work / c.trace_name;
  write_config_case_trace(c, trace);
  auto differ = [&](std::string what) { result.differences.push_back(std::move(what)); };
  auto run = [&](const std::string& name, const std::string& command, const std::string& input = {}) {
    const auto outcome = run_command(command, input);
    std::string shown;  // as run from the kept case's folder
    const std::string folder = work.string();
    std::size_t from = 0;
    for (auto at = command.find(folder); at != std::string::npos; at = command.find(folder, from)) {
      shown += command.substr(from, at - from) + ".";
      from = at + folder.size();
    }
    shown += command.substr(from);
    result.runs.push_back({name, shown, outcome.exit_code, outcome.out, outcome.err});
    return result.runs.back();
  };
  auto cachesim = [&](const std::string& name, const std::vector<std::string>& args) {
    std::string command = shell_quoted(programs.cachesim) + " run " + shell_quoted(trace);
    for (const auto& a : args) command += " " + a;
    return run(name, command);
  };

  std::vector<reference::Result> expected;
  bool any_does_not_fit = false;
  for (const ListedConfig& one : c.configs) {
    expected.push_back(reference::simulate(c.facts, one.config));
    any_does_not_fit = any_does_not_fit || expected.back().high_levels_do_not_fit;
  }

  // The list.
  std::vector<std::string> list_args = c.list_args;
  const auto levels_file = work / "levels.csv", frames_file = work / "frames.csv";
  std::filesystem::remove(levels_file);
  std::filesystem::remove(frames_file);
  if (c.per_level) list_args.insert(list_args.end(), {"--per-level", shell_quoted(levels_file)});
  if (c.per_frame) list_args.insert(list_args.end(), {"--per-frame", shell_quoted(frames_file)});
  const KeptRun list = cachesim("list", list_args);
  std::vector<Row> list_table;
  // Levels that do not fit a retained high cache are a usage error (exit 2).
  if (list.status != (any_does_not_fit ? 2 : 0)) {
    differ(fmt::format("list run: exit {} (expected {}{}): {}", list.status, any_does_not_fit ? 2 : 0,
                       any_does_not_fit ? ", a retained high cache that its levels do not fit" : "",
                       list.err.substr(0, 300)));
  } else if (list.status == 0) {
    list_table = csv_table(list.out);
    if (list_table.size() != c.configs.size()) {
      differ(fmt::format("list run: {} rows for {} configurations", list_table.size(), c.configs.size()));
      list_table.clear();
    }
  }
  const bool list_rows = !list_table.empty();

  // Each configuration alone, and against the reference.
  std::vector<std::map<std::string, std::string>> alone_rows(c.configs.size());
  for (std::size_t i = 0; i < c.configs.size(); ++i) {
    const ListedConfig& one = c.configs[i];
    const bool fits = !expected[i].high_levels_do_not_fit;
    const KeptRun alone = cachesim(fmt::format("alone-{}", i), one.alone_args);
    if (alone.status != (fits ? 0 : 2)) {
      differ(fmt::format("{}: alone: exit {} (expected {}): {}", one.name, alone.status, fits ? 0 : 2,
                         alone.err.substr(0, 300)));
      continue;
    }
    if (!fits) continue;
    const std::vector<Row> alone_table = csv_table(alone.out);
    if (alone_table.size() != 1) {
      differ(fmt::format("{}: alone: {} rows", one.name, alone_table.size()));
      continue;
    }
    alone_rows[i] = alone_table[0];
    ++result.rows;
    const auto cells = expected_cells(one.config, expected[i].total);
    if (const auto d = compare_cells(cells, alone_table[0]); !d.empty()) {
      differ(fmt::format("{}: alone differs from the reference:{}", one.name, d));
    }
    if (list_rows) {
      if (list_table[i] != alone_table[0]) {
        differ(fmt::format("{}: its row in the list differs from the row alone: {} against {}", one.name,
                           row_text(list_table[i]), row_text(alone_table[0])));
      }
      if (const auto d = compare_cells(cells, list_table[i]); !d.empty()) {
        differ(fmt::format("{}: in the list, differs from the reference:{}", one.name, d));
      }
    }
  }

  // Dinero IV, where it can express the configuration.
  // Dinero IV keeps 32-bit addresses: compared where no reference or prefetch reaches 2^32.
  const bool l2_comparable = std::none_of(c.facts.records.begin(), c.facts.records.end(), [](const TraceRecord& r) {
    return r.type == 1 || r.type == 4 || r.type == 5;  // writes back, copies back, invalidates: not L2-visible alike
  });
  if (programs.dinero && !reaches_2_32(c.facts.records)) {
    std::string xdin;
    for (const TraceRecord& r : c.facts.records) {
      if (!r.other_stream) xdin += fmt::format("{} {:x} {:x}\n", kTypeLetters[r.type], r.address, r.size);
    }
    const auto dinero_trace = work / "dinero.xdin";
    write_file(dinero_trace, xdin);
    for (std::size_t i = 0; i < c.configs.size(); ++i) {
      const Config& config = c.configs[i].config;
      const bool expressible = !config.split && (config.policy == Policy::Lru || config.policy == Policy::Fifo ||
                                                 config.policy == Policy::Random) &&
                               (!config.private_units || c.facts.units == 1);
      if (!expressible || alone_rows[i].empty()) continue;
      std::string command = "timeout 10 " + shell_quoted(*programs.dinero);
      for (const auto& a : dinero_arguments(config)) command += " " + a;
      const KeptRun real = run(fmt::format("dinero-{}", i), command + " < " + shell_quoted(dinero_trace));
      const auto l1 = dinero_totals(real.out, "l1-ucache");
      if (real.status != 0 || !l1) {
        differ(fmt::format("{}: Dinero IV failed (exit {}): {}", c.configs[i].name, real.status, real.err.substr(0, 200)));
        continue;
      }
      ++result.dinero_rows;
      const auto& row = alone_rows[i];
      if (cell(row, "fetches") != l1->first || cell(row, "misses") != l1->second) {
        differ(fmt::format("{}: Dinero IV counts {} fetches, {} misses; cachesim {}, {}", c.configs[i].name, l1->first,
                           l1->second, cell(row, "fetches"), cell(row, "misses")));
      }
      if (config.l2 && l2_comparable) {
        const auto l2 = dinero_totals(real.out, "l2-ucache");
        if (!l2 || cell(row, "l2_fetches") != l2->first || cell(row, "l2_misses") != l2->second) {
          differ(fmt::format("{}: Dinero IV's second level counts {} fetches, {} misses; cachesim {}, {}",
                             c.configs[i].name, l2 ? l2->first : 0, l2 ? l2->second : 0, cell(row, "l2_fetches"),
                             cell(row, "l2_misses")));
        }
      }
    }
  }

  // Properties of the rows the runs printed.
  auto same_geometry = [](const Config& a, const Config& b) {
    return a.split == b.split && a.size == b.size && a.block == b.block && a.assoc == b.assoc &&
           a.retain == b.retain && a.high_size == b.high_size && a.low_size == b.low_size &&
           a.high_assoc == b.high_assoc && a.split_level == b.split_level;
  };
  for (const auto* rows : {&list_table, &alone_rows}) {
    if (rows->size() != c.configs.size()) continue;
    const char* which = rows == &alone_rows ? "alone" : "in the list";
    for (std::size_t i = 0; i < c.configs.size(); ++i) {
      if (c.configs[i].config.policy != Policy::Opt || (*rows)[i].empty()) continue;
      for (std::size_t j = 0; j < c.configs.size(); ++j) {
        if (j == i || (*rows)[j].empty() || !same_geometry(c.configs[i].config, c.configs[j].config)) continue;
        ++result.properties;
        if (cell((*rows)[i], "misses") > cell((*rows)[j], "misses")) {
          differ(fmt::format("OPT is not a bound ({}): {} misses {} > {} misses {}", which, c.configs[i].name,
                             cell((*rows)[i], "misses"), c.configs[j].name, cell((*rows)[j], "misses")));
        }
      }
    }
    // A fully associative LRU cache misses no more when it grows.
    for (std::size_t i = 0; i < c.configs.size(); ++i) {
      for (std::size_t j = 0; j < c.configs.size(); ++j) {
        const Config& a = c.configs[i].config;
        const Config& b = c.configs[j].config;
        if ((*rows)[i].empty() || (*rows)[j].empty() || a.split || b.split || a.policy != Policy::Lru ||
            b.policy != Policy::Lru || a.fetch != Fetch::Demand || a.block != b.block || a.size >= b.size ||
            a.assoc != a.size / a.block || b.assoc != b.size / b.block) {
          continue;
        }
        ++result.properties;
        if (cell((*rows)[j], "misses") > cell((*rows)[i], "misses")) {
          differ(fmt::format("fully associative LRU misses more when it grows ({}): {} {} against {} {}", which,
                             c.configs[j].name, cell((*rows)[j], "misses"), c.configs[i].name,
                             cell((*rows)[i], "misses")));
        }
      }
    }
  }

  // The per-level and per-frame tables: each configuration's rows sum to
  // its totals and equal the reference's.
  auto config_key = [](const std::map<std::string, std::string>& row, bool with_k) {
    std::string key;
    for (const char* column : {"scheme", "size", "block", "assoc", "policy", "high_policy", "high_size", "low_size"}) {
      key += row.count(column) ? row.at(column) + "|" : "|";
    }
    if (with_k && row.count("split_level")) key += row.at("split_level");
    return key;
  };
  if (list_rows && c.per_level) {
    const std::vector<Row> levels = csv_table(read_file(levels_file));
    std::map<std::string, std::vector<std::size_t>> configs_of;
    for (std::size_t i = 0; i < c.configs.size(); ++i) configs_of[config_key(list_table[i], true)].push_back(i);
    std::map<std::size_t, std::map<std::uint32_t, reference::LevelCounts>> got;
    for (const auto& row : levels) {
      const auto found = configs_of.find(config_key(row, true));
      if (found == configs_of.end()) {
        differ(fmt::format("per-level table: a row of no configuration of the list ({})", config_key(row, true)));
        continue;
      }
      if (found->second.size() != 1) continue;  // two configurations print alike: not told apart
      auto& counts = got[found->second[0]][static_cast<std::uint32_t>(cell(row, "level"))];
      counts.refs += cell(row, "refs");
      counts.misses += cell(row, "misses");
    }
    for (const auto& [i, by_level] : got) {
      std::uint64_t refs = 0, misses = 0;
      for (const auto& [level, counts] : by_level) {
        refs += counts.refs;
        misses += counts.misses;
        const auto want = expected[i].levels.count(level) ? expected[i].levels.at(level) : reference::LevelCounts{};
        if (counts.refs != want.refs || counts.misses != want.misses) {
          differ(fmt::format("{}: per-level table, level {}: {} refs, {} misses; the reference {}, {}",
                             c.configs[i].name, level, counts.refs, counts.misses, want.refs, want.misses));
        }
      }
      ++result.properties;
      // Untagged records have no level row: the table sums to the tagged records' totals.
      if (refs != cell(list_table[i], "refs") || misses != cell(list_table[i], "misses")) {
        differ(fmt::format("{}: per-level table sums to {} refs, {} misses; the totals are {}, {}", c.configs[i].name,
                           refs, misses, cell(list_table[i], "refs"), cell(list_table[i], "misses")));
      }
    }
  }
  if (list_rows && c.per_frame) {
    const std::vector<Row> frames = csv_table(read_file(frames_file));
    std::map<std::string, std::vector<std::size_t>> configs_of;
    for (std::size_t i = 0; i < c.configs.size(); ++i) configs_of[config_key(list_table[i], false)].push_back(i);
    std::map<std::size_t, std::vector<std::map<std::string, std::string>>> got;
    for (const auto& row : frames) {
      const auto found = configs_of.find(config_key(row, false));
      if (found == configs_of.end()) {
        differ(fmt::format("per-frame table: a row of no configuration of the list ({})", config_key(row, false)));
        continue;
      }
      if (found->second.size() == 1) got[found->second[0]].push_back(row);
    }
    const char* summed[] = {"refs", "fetches", "misses", "high_refs", "high_misses", "high_loads", "low_refs",
                            "low_misses"};
    for (const auto& [i, rows] : got) {
      std::map<std::string, std::uint64_t> sums;
      for (const auto& row : rows) {
        const std::uint64_t frame = cell(row, "frame");
        if (frame >= expected[i].frames.size()) {
          differ(fmt::format("{}: per-frame table: frame {} of {}", c.configs[i].name, frame, expected[i].frames.size()));
          continue;
        }
        if (const auto d = compare_cells(expected_cells(c.configs[i].config, expected[i].frames[frame]), row);
            !d.empty()) {
          differ(fmt::format("{}: per-frame table, frame {}, differs from the reference:{}", c.configs[i].name, frame, d));
        }
        for (const char* column : summed) sums[column] += cell(row, column);
      }
      ++result.properties;
      for (const char* column : summed) {
        if (sums[column] != cell(list_table[i], column)) {
          differ(fmt::format("{}: per-frame table's {} sum to {}; the total is {}", c.configs[i].name, column,
                             sums[column], cell(list_table[i], column)));
        }
      }
    }
  }

  // A curve's points (up to 16k) against the reference.
  if (!c.curve_args.empty()) {
    const KeptRun curve = cachesim("curve", c.curve_args);
    ++result.properties;
    if (curve.status != 0) {
      differ(fmt::format("--curve: exit {}: {}", curve.status, curve.err.substr(0, 300)));
    }
    for (const Row& point : curve.status == 0 ? csv_table(curve.out) : std::vector<Row>{}) {
      Config config;
      config.size = cell(point, "size");
      config.block = cell(point, "block");
      // The reference searches a set way by way: points of up to 1,024 blocks, 256 ways.
      if (config.size > 16384 || config.size < config.block || config.size / config.block > 1024) continue;
      config.assoc = point.at("assoc") == "full" ? static_cast<std::uint32_t>(config.size / config.block)
                                                  : static_cast<std::uint32_t>(cell(point, "assoc"));
      if (config.assoc > 256) continue;
      if (config.size / config.block < config.assoc) continue;
      config.policy = *reference::policy_named(point.at("policy"));
      const reference::Counts want = reference::simulate(c.facts, config).total;
      ++result.curve_points;
      if (cell(point, "fetches") != want.fetches || cell(point, "misses") != want.misses) {
        differ(fmt::format("--curve: {} at {} bytes, block {}, assoc {}: {} fetches, {} misses; the reference {}, {}",
                           point.at("policy"), config.size, config.block, point.at("assoc"), cell(point, "fetches"),
                           cell(point, "misses"), want.fetches, want.misses));
      }
    }
  }

  // Sampling at 1/1 is the full run.
  if (list_rows && c.sampling_allowed) {
    const bool sets = c.sample_sets;
    std::vector<std::size_t> kept;
    std::vector<std::string> policies;
    for (std::size_t i = 0; i < c.configs.size(); ++i) {
      const Policy p = c.configs[i].config.policy;
      if (p == Policy::Opt || (sets && (p == Policy::Brrip || p == Policy::Drrip))) continue;
      if (sets && p == Policy::Random) continue;  // refused with --sample-sets (once defect i)
      kept.push_back(i);
    }
    std::vector<std::string> args = c.list_args;
    const auto policy_at = std::find(args.begin(), args.end(), "--policy") + 1;
    for (const auto& p : [&] {
           std::vector<std::string> names;
           std::istringstream in(*policy_at);
           for (std::string name; std::getline(in, name, ',');) {
             if (name == "opt" || (sets && (name == "brrip" || name == "drrip"))) continue;
             if (!(sets && name == "random")) names.push_back(name);
           }
           return names;
         }()) {
      policies.push_back(p);
    }
    const bool one_block = std::count(args.begin(), args.end(), "--block") == 1 &&
                           (std::find(args.begin(), args.end(), "--block") + 1)->find(',') == std::string::npos;
    if (!policies.empty() && !kept.empty() && (!sets || one_block)) {
      *policy_at = join(policies);
      if (sets) {
        args.insert(args.end(), {"--sample-sets", "1/1"});
      } else {
        args.insert(args.end(), {"--sample-windows", "1/1", "--window-records", std::to_string(1 + c.seed % 500)});
      }
      const KeptRun sampled = cachesim("sampled", args);
      std::vector<std::map<std::string, std::string>> rows;
      for (const auto& row : csv_table(sampled.out)) {
        if (row.count("scheme") && row.at("scheme") != "gain") rows.push_back(row);
      }
      ++result.properties;
      if (sampled.status != 0 || rows.size() != kept.size()) {
        differ(fmt::format("sampled at 1/1: exit {}, {} rows for {} configurations: {}", sampled.status, rows.size(),
                           kept.size(), sampled.err.substr(0, 200)));
      } else {
        (sets ? result.sampled_sets : result.sampled_windows) += kept.size();
        for (std::size_t r = 0; r < kept.size(); ++r) {
          for (const char* column : {"refs", "fetches", "misses", "high_refs", "high_misses", "high_loads",
                                     "low_refs", "low_misses", "split_level"}) {
            const auto& full = list_table[kept[r]];
            const std::string want = full.count(column) ? full.at(column) : "";
            const std::string got = rows[r].count(column) ? rows[r].at(column) : "";
            if (want != got) {
              differ(fmt::format("{}: sampled at 1/1 ({}), {} {} against {} in the full run", c.configs[kept[r]].name,
                                 sets ? "sets" : "windows", column, got, want));
            }
          }
        }
      }
    }
  }
  return result;
}

ConfigCaseResult check_render_case(std::uint64_t seed, const Programs& programs, const std::filesystem::path& work) {
  ConfigCaseResult result;
  Draw draw(seed ^ 0x5EED0F4E4DE4ull);
  const std::array<const char*, 3> scenes = {"sphereflake:1", "mountain:6", "forest:1"};
  const std::array<const char*, 3> layouts = {"--layout dfl", "--layout bfl", "--layout hybrid --high-size 512"};
  ConfigCase c;  // what the list generator needs to know of the trace
  c.seed = seed;
  c.container = true;
  c.tagged = true;
  c.facts.units = draw.chance(30) ? 2 : 1;
  c.facts.nodes_per_level = {{1}};  // markers with level counts: K auto is allowed
  const Lists lists = make_lists(draw, c, ConfigCaseOptions{}, false);
  const std::string list = join(arguments(lists, texts(lists.sizes), texts(lists.blocks), assoc_texts(lists.assocs),
                                          lists.policies, lists.schemes, lists.split_levels, lists.high_policies),
                                " ");
  const auto trace = work / "render.din.zst", report = work / "render.csv";
  std::filesystem::remove(trace);
  std::filesystem::remove(report);
  const std::string render = fmt::format(
      "{} render {} --width 16 --height 12 --quiet {}{} -o {} --simulate '{}' --report {}",
      shell_quoted(*programs.tracer), draw.pick(scenes), draw.pick(layouts),
      c.facts.units > 1 ? " --rays-in-flight 4 --units 2" : "", shell_quoted(trace), list, shell_quoted(report));
  const auto rendered = run_command(render);
  result.runs.push_back({"render", render, rendered.exit_code, rendered.out, rendered.err});
  const std::string run = shell_quoted(programs.cachesim) + " run " + shell_quoted(trace) + " " + list;
  const auto simulated = run_command(run);
  result.runs.push_back({"cachesim", run, simulated.exit_code, simulated.out, simulated.err});
  ++result.properties;
  if (rendered.exit_code != 0 && !std::filesystem::exists(trace)) {
    // Refused before rendering (cachesim's own checks): nothing to compare with.
    if (rendered.exit_code != 2) result.differences.push_back(fmt::format("render: exit {}: {}", rendered.exit_code,
                                                                          rendered.err.substr(0, 300)));
    return result;
  }
  const std::string reported = read_file(report);
  if (simulated.exit_code == 0) result.rows = csv_table(simulated.out).size();
  if (rendered.exit_code != simulated.exit_code || (simulated.exit_code == 0 && reported != simulated.out)) {
    result.differences.push_back(fmt::format(
        "tracer render --simulate (exit {}) and cachesim run on its trace (exit {}) differ: {}", rendered.exit_code,
        simulated.exit_code, reported == simulated.out ? "(same report)" : "reports differ"));
  }
  return result;
}

void keep_runs(const ConfigCaseResult& result, const std::filesystem::path& folder, const std::string& header) {
  std::filesystem::create_directories(folder);
  for (const KeptRun& run : result.runs) {
    write_file(folder / (run.name + ".cmd"), run.command + "\n");
    write_file(folder / (run.name + ".out"), run.out);
    write_file(folder / (run.name + ".err"), run.err);
    write_file(folder / (run.name + ".status"), fmt::format("{}\n", run.status));
  }
  std::string text = header;
  for (const auto& d : result.differences) text += d + "\n";
  write_file(folder / "differences", text);
}

void keep_config_case(const ConfigCase& c, const ConfigCaseResult& result, const std::filesystem::path& folder) {
  std::string header = fmt::format("seed {}\n", c.seed);
  for (const auto& trigger : c.known_defect_triggers) header += "known-defect trigger: " + trigger + "\n";
  keep_runs(result, folder, header);
  write_config_case_trace(c, folder / c.trace_name);
  write_file(folder / "args", join(c.list_args, " ") + "\n");
}

}  // namespace nodetrace::testing
