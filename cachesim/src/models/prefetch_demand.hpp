// Internal: what a demand fetch met in a treelet prefetcher's cache.
#pragma once

#include <cstdint>

namespace nodetrace::cachesim {

// UsefulHit: a block a prefetch placed and no demand fetch had used yet.
enum class PrefetchDemand : std::uint8_t { Hit, UsefulHit, Miss };

}  // namespace nodetrace::cachesim
