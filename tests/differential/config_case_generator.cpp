// The generator of the configuration differential test: its traces and
// lists (config_cases.hpp).
#include "config_cases.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <set>


#include "nodetrace/formats/read/trace_reader.hpp"
#include "nodetrace/formats/write/trace_writer.hpp"
#include "address_stream.hpp"
#include "config_case_lists.hpp"
#include "seeded_draw.hpp"
#include "test_support.hpp"

namespace nodetrace::testing {

namespace {

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

// A --prefetch value as the reference takes it: none (or not given), treelet[:B], treelet-low[:B].
void set_prefetch(Config& config, const std::string& spec) {
  if (spec.empty() || spec == "none") return;
  config.prefetch = true;
  config.prefetch_low = spec.starts_with("treelet-low");
  const auto colon = spec.find(':');
  if (colon != std::string::npos) config.prefetch_bytes = std::stoull(spec.substr(colon + 1));
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
            const std::vector<std::string> prefetches =
                l.prefetches.empty() ? std::vector<std::string>{""} : l.prefetches;
            for (const std::string& k : split_levels) {
              for (const std::string& high : high_policies) {
                for (const std::string& prefetch : prefetches) {
                  ListedConfig one;
                  one.config = config;
                  if (config.split) {
                    if (k != "auto") one.config.split_level = static_cast<std::uint32_t>(std::stoul(k));
                    one.config.retain = high == "retain";
                  }
                  set_prefetch(one.config, prefetch);
                  const std::string key = fmt::format(
                      "{} {} {} {} {} {} {} {} {} {} {} {} {}", scheme, one.config.size, block, one.config.assoc,
                      policy, config.split ? high : "", one.config.high_size, one.config.low_size,
                      one.config.high_assoc, k, config.split && l.count_loads, 0, prefetch_text(one.config));
                  if (!seen.insert(key).second) continue;
                  one.name = fmt::format("{} size {} block {} assoc {} policy {}{}{}", scheme, size, block,
                                         assoc_text(assoc), policy,
                                         config.split ? fmt::format(" K {} high {}", k, high) : "",
                                         prefetch.empty() ? "" : " prefetch " + prefetch);
                  Lists alone = l;
                  if (!prefetch.empty()) alone.prefetches = {prefetch};
                  one.alone_args = arguments(
                      alone, {std::to_string(size)}, {std::to_string(block)}, {assoc_text(assoc)}, {policy}, {scheme},
                      config.split ? std::vector<std::string>{k} : std::vector<std::string>{},
                      config.split ? std::vector<std::string>{high} : std::vector<std::string>{});
                  listed.push_back(std::move(one));
                }
              }
            }
          }
        }
      }
    }
  }
  return listed;
}

// Random treelet maps, one per frame, over the frame's nodes [0, nodes x 8):
// treelets of 1 to 1024 bytes, some with a gap before them.
void draw_treelet_maps(Draw& draw, ConfigCase& c) {
  for (std::uint32_t f = 0; f < c.facts.frames; ++f) {
    std::uint64_t nodes = 0;
    for (const std::uint64_t n : c.facts.nodes_per_level.at(f)) nodes += n;
    std::vector<reference::Treelet> map;
    std::uint64_t at = draw.below(4) * 8;
    while (at < nodes * 8) {
      const std::uint64_t bytes = std::min(nodes * 8 - at, draw.chance(50) ? 8 * draw.between(1, 128)
                                                                               : draw.between(1, 1024));
      map.push_back({at, bytes});
      at += bytes + (draw.chance(20) ? draw.between(1, 200) : 0);
    }
    c.facts.treelets.emplace_back(std::move(map));
  }
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
  if (c.container && draw.chance(50)) {
    c.treelet_maps = true;
    draw_treelet_maps(draw, c);
    if (draw.chance(70)) c.rays = draw.between(1, 5000);
  }
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
  // Per-level and per-frame rows do not name the prefetcher: one at most.
  const bool one_prefetcher = lists.prefetches.size() <= 1;
  c.per_level = c.tagged && !has_opt && !lists.private_units && !lists.l2 && one_prefetcher && draw.chance(25);
  c.per_frame = !has_opt && !lists.private_units && !lists.l2 && one_prefetcher && draw.chance(25);
  c.prefetch_columns = std::any_of(lists.prefetches.begin(), lists.prefetches.end(),
                                   [](const std::string& spec) { return spec != "none"; });
  c.sampling_allowed = !c.per_level && !c.per_frame && !lists.private_units && !lists.l2 && lists.fetch == "demand" &&
                       lists.prefetches.empty();
  c.list_args = arguments(lists, texts(lists.sizes), texts(lists.blocks), assoc_texts(lists.assocs), lists.policies,
                          lists.schemes, lists.split_levels, lists.high_policies);

  // Odd seeds sample sets (even ones windows), unless (g) is avoided and a
  // reference spans blocks of some listed size.
  const bool spans = std::any_of(c.facts.records.begin(), c.facts.records.end(), [&](const TraceRecord& r) {
    return r.type != 4 && r.type != 5 && !r.other_stream &&
           std::any_of(lists.blocks.begin(), lists.blocks.end(),
                       [&](std::uint64_t block) { return r.address % block + r.size > block; });
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
  options.treelet_maps = c.treelet_maps;
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
      if (c.treelet_maps) {
        marker.treelets.emplace();
        for (const reference::Treelet& t : *c.facts.treelets.at(frame)) marker.treelets->treelets.push_back({t.first, t.bytes});
      }
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
  if (c.rays) writer->add_totals({{"rays", {{"primary", *c.rays}}}});
  writer->finish();
}

}  // namespace nodetrace::testing
