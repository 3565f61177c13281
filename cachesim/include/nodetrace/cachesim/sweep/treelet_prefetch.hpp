// `cachesim run --prefetch`: the treelet prefetcher a configuration runs
// (issue 51). On a demand miss to a block of treelet T (the trace's treelet
// map of the current animation frame), the blocks of T from the missed one
// onward, at most `bytes` of them counted from the missed block's first byte
// (0: to T's end), are placed in the cache that missed as prefetches; a
// block already resident is left as it is. `treelet-low` prefetches only
// into the split scheme's low-level cache (into the single cache as
// `treelet` does). Timing is not modelled: every prefetch arrives in time.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "nodetrace/formats/container/treelet_map.hpp"

namespace nodetrace::cachesim {

enum class TreeletPrefetch : std::uint8_t { None, Treelet, TreeletLow };

struct PrefetchSpec {
  TreeletPrefetch kind = TreeletPrefetch::None;
  std::uint64_t bytes = 0;  // 0: the whole treelet from the missed block on
  friend bool operator==(const PrefetchSpec&, const PrefetchSpec&) = default;
};

// none, treelet, treelet:BYTES, treelet-low, treelet-low:BYTES (BYTES with
// optional k/m, a positive power of two). Throws base::UsageError naming
// `option`.
PrefetchSpec parse_prefetch(std::string_view text, const char* option = "--prefetch");
// The report's `prefetch` cell: none, treelet, treelet:4096, treelet-low:4096.
std::string prefetch_name(const PrefetchSpec& spec);

// What a prefetching cache counts: blocks placed as prefetches, and those of
// them a demand fetch used before they left the cache. The others (evicted,
// invalidated, or still resident unused at the end) are the useless ones.
struct PrefetchCounts {
  std::uint64_t prefetches = 0;
  std::uint64_t useful = 0;
  PrefetchCounts& operator+=(const PrefetchCounts& other) {
    prefetches += other.prefetches;
    useful += other.useful;
    return *this;
  }
};

// A row's prefetch columns (a run with --prefetch): the counts, the misses
// of the same configuration without prefetching (simulated alongside) and
// the rays of the trace (the trailer's totals "rays", summed over ray kinds;
// nullopt when the trace does not say).
struct PrefetchColumns {
  PrefetchSpec spec;
  PrefetchCounts counts;
  std::uint64_t misses_without_prefetch = 0;
  std::uint64_t fetched_blocks = 0;  // demand fetches from memory + prefetches
  std::optional<std::uint64_t> rays;
};

// A map that is not in increasing address order, has an empty treelet or
// overlaps itself: base::FormatError naming `source` and the animation frame
// (readers check it too; a simulator never runs on one).
void check_treelet_map(const formats::TreeletMap& map, std::uint64_t animation_frame, const std::string& source);

}  // namespace nodetrace::cachesim

namespace nodetrace::formats {
class TraceReader;
}

namespace nodetrace::cachesim {

// The rays a trace's trailer counts (totals "rays", summed over ray kinds);
// nullopt for a trace without that count (plain traces, other producers).
std::optional<std::uint64_t> trace_rays(const formats::TraceReader& reader);

// The report's note on what the prefetch columns mean.
std::string treelet_prefetch_note();

}  // namespace nodetrace::cachesim
