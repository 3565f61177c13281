#include "nodetrace/cachesim/sweep/config.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>

#include "nodetrace/base/error.hpp"

namespace nodetrace::cachesim {

using base::FormatError;
using base::UsageError;

std::string_view scheme_name(Scheme scheme) {
  return scheme == Scheme::Single ? "single" : "split";
}

std::optional<Scheme> parse_scheme_name(std::string_view name) {
  if (name == "single") return Scheme::Single;
  if (name == "split") return Scheme::Split;
  return std::nullopt;
}

std::string_view high_policy_name(HighPolicy policy) {
  return policy == HighPolicy::Retain ? "retain" : "cache";
}

std::optional<HighPolicy> parse_high_policy_name(std::string_view name) {
  if (name == "retain") return HighPolicy::Retain;
  if (name == "cache") return HighPolicy::Cache;
  return std::nullopt;
}

std::uint32_t parse_assoc(std::string_view text) {
  if (text == "full") return 0;
  std::uint32_t value = 0;
  const auto [next, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc{} || next != text.data() + text.size() || value == 0) {
    throw UsageError(fmt::format(
        "'{}' is not an associativity: expected a positive number of ways or 'full'", text));
  }
  return value;
}

namespace {

std::uint32_t resolve_ways(std::uint32_t assoc, std::uint64_t size, std::uint32_t block) {
  if (assoc != 0) return assoc;
  return static_cast<std::uint32_t>(std::max<std::uint64_t>(1, size / block));
}

}  // namespace

std::vector<Configuration> expand_configurations(const SweepOptions& options) {
  if (options.fetch != FetchPolicy::Demand) {
    if (std::find(options.schemes.begin(), options.schemes.end(), Scheme::Split) != options.schemes.end()) {
      throw UsageError(fmt::format("--fetch {}: prefetching is simulated for --scheme single only (the "
                                   "split scheme's caches are demand-fetch)",
                                   fetch_policy_name(options.fetch)));
    }
    if (options.prefetch_distance == 0) throw UsageError("--prefetch-distance 0: the distance is at least 1 block");
    // Dinero IV's rule; a block is one sub-block here.
    if ((options.fetch == FetchPolicy::LoadForward || options.fetch == FetchPolicy::SubBlock) &&
        options.prefetch_distance > 1) {
      throw UsageError(fmt::format("--fetch {} --prefetch-distance {}: the distance cannot exceed the "
                                   "block (1), as Dinero IV requires",
                                   fetch_policy_name(options.fetch), options.prefetch_distance));
    }
  }
  const bool treelets = std::any_of(options.prefetches.begin(), options.prefetches.end(),
                                   [](const PrefetchSpec& spec) { return spec.kind != TreeletPrefetch::None; });
  if (treelets && options.fetch != FetchPolicy::Demand) {
    throw UsageError(fmt::format("--prefetch treelet with --fetch {}: the treelet prefetcher runs with demand "
                                 "fetch only; give one of them",
                                 fetch_policy_name(options.fetch)));
  }
  for (const ReplacementPolicy policy : options.policies) {
    if (treelets && policy == ReplacementPolicy::Opt) {
      throw UsageError("--policy opt with --prefetch treelet: the treelet prefetcher runs with lru, fifo, random, "
                       "plru, srrip, brrip and drrip (MIN looks ahead at demand fetches only)");
    }
    if (!dinero_has_policy(policy) && options.fetch != FetchPolicy::Demand) {
      throw UsageError(fmt::format("--policy {} with --fetch {}: prefetching is simulated with Dinero IV's "
                                   "policies only (lru, fifo, random); give --fetch demand",
                                   policy_name(policy), fetch_policy_name(options.fetch)));
    }
    if (policy == ReplacementPolicy::Opt && (options.per_level || options.per_animation_frame)) {
      throw UsageError(fmt::format("--policy opt: not with {} (MIN counts its misses only at the end of the "
                                   "trace); run per-level or per-frame tables with lru, fifo, random, plru, "
                                   "srrip, brrip or drrip",
                                   options.per_level ? "--per-level" : "--per-frame"));
    }
  }
  std::vector<Configuration> configs;
  for (const std::uint64_t size : options.sizes) {
    for (const std::uint32_t block : options.blocks) {
      for (const std::uint32_t assoc : options.assocs) {
        for (const ReplacementPolicy policy : options.policies) {
          for (const Scheme scheme : options.schemes) {
            Configuration base;
            base.scheme = scheme;
            base.size = size;
            base.block = block;
            base.policy = policy;
            base.count_loads = options.count_loads;
            base.fetch = options.fetch;
            base.prefetch_distance = options.prefetch_distance;
            if (scheme == Scheme::Single) {
              base.assoc = resolve_ways(assoc, size, block);
              validate_geometry({size, block, base.assoc, policy}, fmt::format("{}-byte cache", size));
              configs.push_back(base);
              continue;
            }
            // Both sides given: the split cache is their sum whatever the
            // size, so it is made once, with the first size.
            if (options.high_size && options.low_size && size != options.sizes.front()) continue;
            std::uint64_t high = 0;
            if (options.high_size) {
              high = *options.high_size;
            } else if (options.low_size) {
              if (*options.low_size >= size) {
                throw UsageError(fmt::format("--low-size {} leaves nothing of the total size {} for "
                                             "the high-level cache",
                                             *options.low_size, size));
              }
              high = size - *options.low_size;
            } else {
              high = size / 2;
            }
            std::uint64_t low = 0;
            if (options.low_size) {
              low = *options.low_size;
            } else if (high < size) {
              low = size - high;
            } else {
              throw UsageError(fmt::format("--high-size {} leaves nothing of the total size {} for "
                                           "the low-level cache",
                                           high, size));
            }
            base.high_size = high;
            base.low_size = low;
            base.size = high + low;
            base.assoc = resolve_ways(assoc, low, block);
            const std::uint32_t high_assoc = options.high_assoc.value_or(assoc);
            base.high_assoc = resolve_ways(high_assoc, high, block);
            validate_geometry({low, block, base.assoc, policy},
                              fmt::format("low-level cache of {} bytes", low));
            for (const auto& split_level : options.split_levels) {
              for (const HighPolicy high_policy : options.high_policies) {
                Configuration config = base;
                config.split_level = split_level;
                config.high_policy = high_policy;
                const std::string what = fmt::format("high-level cache of {} bytes", high);
                if (high_policy == HighPolicy::Cache) {
                  validate_geometry({high, block, config.high_assoc, policy}, what);
                } else {
                  validate_geometry({high, block, 1, policy}, what);
                }
                configs.push_back(config);
              }
            }
          }
        }
      }
    }
  }
  if (options.prefetches.size() == 1 && options.prefetches.front().kind == TreeletPrefetch::None) return configs;
  std::vector<Configuration> prefetching;
  for (const Configuration& config : configs) {
    for (const PrefetchSpec& spec : options.prefetches) {
      prefetching.push_back(config);
      prefetching.back().prefetch = spec;
    }
  }
  return prefetching;
}

bool has_treelet_prefetch(const std::vector<Configuration>& configs) {
  return std::any_of(configs.begin(), configs.end(),
                     [](const Configuration& config) { return config.prefetch.kind != TreeletPrefetch::None; });
}

TraceContext trace_context(const formats::TraceReader& reader, std::string trace_column) {
  TraceContext context;
  context.trace = std::move(trace_column);
  context.source_name = reader.source_name();
  context.form = reader.form();
  context.tags_are_levels = reader.tags_are_levels();
  context.layout = reader.header().layout();
  return context;
}

bool has_split(const std::vector<Configuration>& configs) {
  return std::any_of(configs.begin(), configs.end(),
                     [](const auto& config) { return config.scheme == Scheme::Split; });
}

std::optional<std::string> merge_repeated_configurations(std::vector<Configuration>& configs) {
  std::vector<Configuration> distinct;
  for (const Configuration& config : configs) {
    if (std::find(distinct.begin(), distinct.end(), config) == distinct.end()) distinct.push_back(config);
  }
  const std::size_t repeated = configs.size() - distinct.size();
  configs = std::move(distinct);
  if (repeated == 0) return std::nullopt;
  return fmt::format("{} configuration{} repeated an earlier one (a value listed twice, or `full` and the "
                     "number of ways of a one-set cache): each cache is simulated and reported once",
                     repeated, repeated == 1 ? "" : "s");
}

void throw_untagged_trace(const TraceContext& context, std::string_view what) {
  if (context.form == formats::RecordForm::Binary) {
    // --tags-are-levels cannot help: the form has no field for a tag.
    throw UsageError(fmt::format(
        "{}: {} needs the node level of every record, but Dinero binary records carry no tag; "
        "use a din or extended din trace of the same records (a trace converted to binary lost its levels)",
        context.source_name, what));
  }
  throw UsageError(fmt::format(
      "{}: {} needs the node level of every record, but this trace's records are untagged "
      "(no container header says \"tag\": \"node-level\"); if the field after the address "
      "holds node levels, pass --tags-are-levels",
      context.source_name, what));
}

void throw_untagged_record(const TraceContext& context, std::uint64_t record_number,
                           std::string_view what) {
  throw FormatError(fmt::format(
      "{}: record {}: no node-level tag, but {} every record by its level (expected `LABEL "
      "ADDRESS LEVEL`)",
      context.source_name, record_number, what));
}

void throw_high_levels_do_not_fit(const TraceContext& context, const Configuration& config,
                                  std::uint64_t record_number, std::uint32_t split_level,
                                  std::uint64_t animation_frame, std::uint64_t capacity) {
  throw UsageError(fmt::format(
      "{}: record {}: the high-level nodes (levels < {}) touched in animation frame {} do not "
      "fit the high-level cache: more than {} distinct {}-byte blocks, but the {}-byte high "
      "cache (of a {}-byte total, low cache {} bytes) holds {}; give a smaller --split-level "
      "or a larger --high-size",
      context.source_name, record_number, split_level, animation_frame, capacity, config.block,
      config.high_size, config.size, config.low_size, capacity));
}

std::string other_streams_note(const std::string& trace, std::uint64_t records) {
  return fmt::format(
      "{}: {} records tagged p or t (primitive lists, triangles) counted apart, not simulated "
      "by the node caches",
      trace, records);
}

std::uint32_t simulated_split_level(const Configuration& config, const formats::AnimationFrameMarker* marker,
                                  const TraceContext& context) {
  if (config.split_level) return *config.split_level;
  if (marker == nullptr || marker->nodes_per_level.empty()) {
    throw UsageError(fmt::format(
        "{}: --split-level auto needs the nodes_per_level of animation-frame markers, which this "
        "trace does not have; give an explicit split level, e.g. --split-level 8",
        context.source_name));
  }
  const base::LevelPlacement placement =
      formats::level_placement(context.layout, marker->layout_split_level(), config.block);
  return base::split_level_for_capacity(marker->nodes_per_level, placement, config.high_size);
}

SplitLevelPlan::SplitLevelPlan(const std::vector<Configuration>& configs,
                               const TraceContext& context)
    : configs_(configs),
      context_(context),
      current_(configs.size(), 0),
      first_(configs.size(), 0),
      lowest_(configs.size(), 0),
      highest_(configs.size(), 0) {}

void SplitLevelPlan::begin_animation_frame(const formats::AnimationFrameMarker* marker) {
  // The layout's K of this frame: the marker's (the tracer sizes it per
  // frame), else the header's.
  std::optional<std::uint32_t> layout_level = context_.layout.split_level;
  const char* where = "in the trace header";
  if (marker != nullptr && marker->layout_split_level() &&
      marker->layout_split_level() != layout_level) {
    layout_level = marker->layout_split_level();
    where = "in the animation-frame markers";
  }
  const std::string& layout_name = context_.layout.name;
  // DFL scatters every level but the root's through the tree's memory (BFL
  // and the hybrid layout's top keep the high levels together).
  if (!started_ && layout_name == "dfl") {
    for (const Configuration& config : configs_) {
      if (config.scheme != Scheme::Split) continue;
      layout_notes_.push_back(fmt::format(
          "{}: layout {}: the split scheme routes levels < K to the high cache, but this layout scatters "
          "those levels through the tree's memory, so the high cache holds them among other nodes' bytes; for "
          "the split the paper measures, render with tracer render --layout hybrid --high-size SIZE",
          context_.trace, layout_name));
      break;
    }
  }
  for (std::size_t i = 0; i < configs_.size(); ++i) {
    const Configuration& config = configs_[i];
    if (config.scheme != Scheme::Split) continue;
    const std::uint32_t k = simulated_split_level(config, marker, context_);
    current_[i] = k;
    if (!started_) {
      first_[i] = lowest_[i] = highest_[i] = k;
    } else {
      lowest_[i] = std::min(lowest_[i], k);
      highest_[i] = std::max(highest_[i], k);
    }
    if (layout_level && *layout_level != k) {
      std::string note = fmt::format(
          "{}: {}-byte high cache: split level {} ({}) differs from the layout's split_level {} {}: "
          "the high-level nodes are not where this layout put them together, so the split is not the "
          "scheme the layout was made for; render one trace per high-cache size (tracer render --layout "
          "hybrid --high-size SIZE, as scripts/table1.mk does)",
          context_.trace, config.high_size, k, config.split_level ? "given" : "auto",
          *layout_level, where);
      if (std::find(layout_notes_.begin(), layout_notes_.end(), note) == layout_notes_.end()) {
        layout_notes_.push_back(std::move(note));
      }
    }
  }
  started_ = true;
  ++frames_;
}

std::vector<std::string> SplitLevelPlan::notes() const {
  std::vector<std::string> notes = layout_notes_;
  for (std::size_t i = 0; i < configs_.size(); ++i) {
    if (lowest_[i] == highest_[i]) continue;
    std::string note = fmt::format(
        "{}: {}-byte high cache: split level (auto) from {} to {} over {} animation frames, each "
        "frame's from its own tree; the split_level column is the first frame's (--per-frame FILE "
        "writes each)",
        context_.trace, configs_[i].high_size, lowest_[i], highest_[i], frames_);
    if (std::find(notes.begin(), notes.end(), note) == notes.end()) notes.push_back(std::move(note));
  }
  return notes;
}

}  // namespace nodetrace::cachesim
