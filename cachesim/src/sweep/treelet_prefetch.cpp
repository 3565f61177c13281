#include "nodetrace/cachesim/sweep/treelet_prefetch.hpp"

#include <fmt/format.h>

#include <bit>

#include "nodetrace/base/byte_size.hpp"
#include "nodetrace/base/error.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"

namespace nodetrace::cachesim {

PrefetchSpec parse_prefetch(std::string_view text, const char* option) {
  const std::size_t colon = text.find(':');
  const std::string_view kind = text.substr(0, colon);
  PrefetchSpec spec;
  if (kind == "none" && colon == std::string_view::npos) return spec;
  if (kind == "treelet") {
    spec.kind = TreeletPrefetch::Treelet;
  } else if (kind == "treelet-low") {
    spec.kind = TreeletPrefetch::TreeletLow;
  } else {
    throw base::UsageError(fmt::format("{}: '{}' is not a prefetcher: expected none, treelet[:BYTES] or "
                                       "treelet-low[:BYTES]",
                                       option, text));
  }
  if (colon == std::string_view::npos) return spec;
  const std::string_view bytes_text = text.substr(colon + 1);
  const std::uint64_t bytes = base::parse_byte_size(bytes_text, option);
  if (bytes == 0 || !std::has_single_bit(bytes)) {
    throw base::UsageError(fmt::format("{} {}: {} bytes is not a positive power of two (the most bytes of a "
                                       "treelet one miss prefetches)",
                                       option, text, bytes));
  }
  spec.bytes = bytes;
  return spec;
}

std::string prefetch_name(const PrefetchSpec& spec) {
  const char* kind = spec.kind == TreeletPrefetch::None      ? "none"
                     : spec.kind == TreeletPrefetch::Treelet ? "treelet"
                                                             : "treelet-low";
  return spec.bytes == 0 ? std::string(kind) : fmt::format("{}:{}", kind, spec.bytes);
}

void check_treelet_map(const formats::TreeletMap& map, std::uint64_t animation_frame, const std::string& source) {
  std::uint64_t end = 0;
  for (std::size_t t = 0; t < map.treelets.size(); ++t) {
    const formats::TreeletRange& treelet = map.treelets[t];
    if (treelet.bytes == 0 || treelet.first + treelet.bytes < treelet.first || (t > 0 && treelet.first < end)) {
      throw base::FormatError(fmt::format(
          "{}: animation frame {}: treelet {} (bytes 0x{:x} + {}) is empty, wraps, or overlaps the one before it: "
          "a treelet map holds non-empty ranges in increasing address order, none overlapping",
          source, animation_frame, t, treelet.first, treelet.bytes));
    }
    end = treelet.first + treelet.bytes;
  }
}

std::optional<std::uint64_t> trace_rays(const formats::TraceReader& reader) {
  const std::optional<formats::TraceTrailer>& trailer = reader.trailer();
  if (!trailer) return std::nullopt;
  const auto rays = trailer->totals.find("rays");
  if (rays == trailer->totals.end() || !rays->is_object()) return std::nullopt;
  std::uint64_t sum = 0;
  for (const auto& [kind, count] : rays->items()) {
    if (!count.is_number_unsigned()) return std::nullopt;
    sum += count.get<std::uint64_t>();
  }
  return sum;
}

std::string treelet_prefetch_note() {
  return "--prefetch: timing is not modelled: every prefetch arrives in time (an upper bound on what a treelet "
         "prefetcher gains); a prefetched block enters as the policy inserts a missed one (LRU: most recent) and a "
         "resident one is left as it is; prefetches are counted apart: fetches and misses are demand ones; "
         "useful_prefetches were used by a demand fetch before leaving the cache, the others (evicted, "
         "invalidated, or unused at the end) are useless; prefetch_coverage = (misses_without_prefetch - "
         "misses) / misses_without_prefetch, negative where prefetches evict blocks that are then missed; "
         "bytes_per_ray = (blocks fetched on demand + prefetches) * block / the rays of the trace's trailer";
}

}  // namespace nodetrace::cachesim
