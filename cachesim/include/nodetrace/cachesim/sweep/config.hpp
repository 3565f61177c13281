// The configuration layer shared by `cachesim run` and `dinero-wrap run`:
// the names of schemes and policies, the expansion of the command-line lists
// into configurations, what a run knows of its trace, and K per animation
// frame with the notes about it (docs/ARCHITECTURE.md "Cache model").
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "nodetrace/cachesim/dinero/engine.hpp"
#include "nodetrace/cachesim/models/set_associative_cache.hpp"
#include "nodetrace/cachesim/sweep/treelet_prefetch.hpp"
#include "nodetrace/formats/container/metadata.hpp"
#include "nodetrace/base/split_level.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"
#include "nodetrace/formats/record/record.hpp"

namespace nodetrace::cachesim {

enum class Scheme : std::uint8_t { Single, Split };
enum class HighPolicy : std::uint8_t { Retain, Cache };

std::string_view scheme_name(Scheme scheme);           // single, split
std::optional<Scheme> parse_scheme_name(std::string_view name);
std::string_view high_policy_name(HighPolicy policy);  // retain, cache
std::optional<HighPolicy> parse_high_policy_name(std::string_view name);

// Associativity: a number, or "full" (returned as 0: all blocks of the cache).
std::uint32_t parse_assoc(std::string_view text);

// One configuration of the report, before K = auto is resolved.
struct Configuration {
  Scheme scheme = Scheme::Single;
  std::uint64_t size = 8192;  // total: single cache, or high + low
  std::uint32_t block = 8;
  std::uint32_t assoc = 1;  // single / low cache ways (resolved, never 0)
  ReplacementPolicy policy = ReplacementPolicy::Lru;
  // Split scheme only.
  HighPolicy high_policy = HighPolicy::Retain;
  std::uint64_t high_size = 0;
  std::uint64_t low_size = 0;
  std::uint32_t high_assoc = 1;          // ways of the high cache under `cache`
  std::optional<std::uint32_t> split_level;  // nullopt: auto
  bool count_loads = false;              // retain: loads count as misses
  // Dinero IV's fetch policy (single scheme only; misses stay demand misses)
  // and its prefetch distance in blocks.
  FetchPolicy fetch = FetchPolicy::Demand;
  std::uint32_t prefetch_distance = 1;
  // The treelet prefetcher (--prefetch; demand fetch only).
  PrefetchSpec prefetch;

  friend bool operator==(const Configuration&, const Configuration&) = default;
};

// Whether some configuration prefetches treelets (the report then has the
// prefetch columns).
bool has_treelet_prefetch(const std::vector<Configuration>& configs);

// The command-line lists of `cachesim run` / `dinero-wrap run`.
struct SweepOptions {
  std::vector<std::uint64_t> sizes{8192};
  std::vector<std::uint32_t> blocks{8};
  std::vector<std::uint32_t> assocs{1};  // 0 = full
  std::vector<ReplacementPolicy> policies{ReplacementPolicy::Lru};
  std::vector<Scheme> schemes{Scheme::Single};
  std::vector<std::optional<std::uint32_t>> split_levels{std::nullopt};  // nullopt = auto
  std::vector<HighPolicy> high_policies{HighPolicy::Retain};
  std::optional<std::uint64_t> high_size;
  std::optional<std::uint64_t> low_size;
  std::optional<std::uint32_t> high_assoc;  // 0 = full; default: assoc
  bool count_loads = false;
  FetchPolicy fetch = FetchPolicy::Demand;  // other than demand: --scheme single only
  std::uint32_t prefetch_distance = 1;
  // --prefetch (list, innermost of the expansion): none, or a treelet prefetcher.
  std::vector<PrefetchSpec> prefetches{PrefetchSpec{}};
  bool per_level = false;
  bool per_animation_frame = false;
};

// Every combination, in report order (size, block, assoc, policy, scheme,
// split level, high policy, prefetch; innermost last). Validates each geometry; throws
// base::UsageError.
std::vector<Configuration> expand_configurations(const SweepOptions& options);

// Removes every configuration equal to an earlier one (a value listed twice,
// `--size 8k,8192`, or `--assoc full,1024` on a cache of 1024 blocks), so
// that each row of a report is one cache; the note says how many were merged
// (nullopt: none).
std::optional<std::string> merge_repeated_configurations(std::vector<Configuration>& configs);

// What a run needs to know about its trace.
struct TraceContext {
  std::string trace;        // the report's `trace` column (argument as given)
  std::string source_name;  // for error messages
  formats::RecordForm form = formats::RecordForm::Din;
  bool tags_are_levels = false;
  formats::LayoutInfo layout;  // the header's "layout"
};

// Fills a TraceContext from an opened reader.
TraceContext trace_context(const formats::TraceReader& reader, std::string trace_column);

// Records of the other streams (tags p, t): counted apart, never simulated.
constexpr bool is_other_stream(formats::Tag tag) {
  return tag == formats::kTagPrimitiveList || tag == formats::kTagTriangle;
}

// Whether a configuration list routes records by level (has a split one).
bool has_split(const std::vector<Configuration>& configs);

// The error for a trace without node levels where `what` needs them.
[[noreturn]] void throw_untagged_trace(const TraceContext& context, std::string_view what);
// The error for an untagged record (1-based `record_number`) in a level-tagged run.
[[noreturn]] void throw_untagged_record(const TraceContext& context, std::uint64_t record_number,
                                        std::string_view what);

// The error for a `retain` high cache that the high levels of an animation
// frame do not fit: more than `capacity` distinct blocks at record
// `record_number` (1-based) with K `split_level`.
[[noreturn]] void throw_high_levels_do_not_fit(const TraceContext& context,
                                               const Configuration& config,
                                               std::uint64_t record_number,
                                               std::uint32_t split_level,
                                               std::uint64_t animation_frame,
                                               std::uint64_t capacity);

// The note for records of other streams (p, t), counted apart.
std::string other_streams_note(const std::string& trace, std::uint64_t records);

// K of a split configuration in the animation frame of `marker` (nullptr: a
// trace without markers): the one given, or auto, the largest K whose levels
// occupy no more blocks than the high cache holds (formats::
// split_level_for_capacity, from the frame's nodes_per_level and the
// header's layout). Throws base::UsageError for auto without
// nodes_per_level.
std::uint32_t simulated_split_level(const Configuration& config, const formats::AnimationFrameMarker* marker,
                                  const TraceContext& context);

// K of every configuration, animation frame by animation frame, and the
// notes about it (K other than the layout's; K changing between frames).
class SplitLevelPlan {
 public:
  SplitLevelPlan(const std::vector<Configuration>& configs, const TraceContext& context);

  // At the trace's first batch (its marker, or nullptr) and at every later
  // marker. Throws as simulated_split_level.
  void begin_animation_frame(const formats::AnimationFrameMarker* marker);
  // This frame's K (0 for single configurations).
  std::uint32_t current(std::size_t config) const { return current_.at(config); }
  // The first frame's K: the totals row's split_level.
  std::uint32_t first(std::size_t config) const { return first_.at(config); }
  std::vector<std::string> notes() const;

 private:
  const std::vector<Configuration>& configs_;
  const TraceContext& context_;
  bool started_ = false;
  std::uint64_t frames_ = 0;
  std::vector<std::uint32_t> current_;
  std::vector<std::uint32_t> first_;
  std::vector<std::uint32_t> lowest_;
  std::vector<std::uint32_t> highest_;
  std::vector<std::string> layout_notes_;
};

}  // namespace nodetrace::cachesim
