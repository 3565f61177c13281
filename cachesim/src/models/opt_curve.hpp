// Internal: MIN's misses at every power-of-two capacity of a fully
// associative cache in one pass over an OptStream. MIN is a stack algorithm
// (Mattson et al.): the cache of 2^k blocks holds the 2^(k-1) blocks of
// layer k and every layer below (layer 0 holds one). A fetch puts its block
// into layer 0; each full layer passes the block of its farthest next use
// (the one MIN keeps out at that size, the incoming included) to the layer
// above, until the layer the block came from, or one with room. A fetch
// found in layer j misses at every size below 2^j. Each layer's farthest
// block is found with a heap: O(log) per layer a fetch passes.
#pragma once

#include <cstdint>
#include <vector>

#include "models/opt_cache.hpp"

namespace nodetrace::cachesim {

// Misses of MIN with 2^k blocks, for k = 0 .. layers - 1.
std::vector<std::uint64_t> opt_size_curve(const OptStream& stream, const ChunkedArray& next_uses,
                                          unsigned layers);

}  // namespace nodetrace::cachesim
