// The memory a configuration's caches keep: allocated (and written) before
// the first record, so a run of large caches costs it even on an empty trace.
// `cachesim run` states and checks the total before it starts.
#pragma once

#include <cstdint>
#include <vector>

#include "nodetrace/cachesim/models/cache_geometry.hpp"
#include "nodetrace/cachesim/sweep/config.hpp"

namespace nodetrace::cachesim {

// About the bytes of state of one cache of `geometry`: 8 per block for sets
// of up to 16 ways (a block number a way, the policy's bits beside), about 48
// for sets of more (recency links and a hash index of the blocks besides);
// measured at 256m of 8-byte blocks: 268 MB at 1, 4 and 16 ways, 1.58 GB at
// 64 ways and fully associative.
std::uint64_t cache_state_bytes(const CacheGeometry& geometry);

// Of every cache of `configs` (single, or high and low), plus `l2` for each
// when given; opt's kept fetches, which grow with the trace, are not counted.
std::uint64_t state_bytes(const std::vector<Configuration>& configs, const CacheGeometry* l2 = nullptr);

}  // namespace nodetrace::cachesim
