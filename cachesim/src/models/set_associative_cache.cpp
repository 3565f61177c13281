#include "nodetrace/cachesim/models/set_associative_cache.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>

#include "nodetrace/base/error.hpp"

namespace nodetrace::cachesim {

SetAssociativeCache::SetAssociativeCache(const CacheGeometry& geometry, std::uint64_t seed)
    : geometry_(geometry), random_state_(seed | 1) {
  validate_geometry(geometry, "cache");
  assoc_ = geometry.assoc;
  const std::uint64_t blocks = geometry.size / geometry.block_size;
  set_mask_ = blocks / assoc_ - 1;
  tags_.assign(blocks, kInvalid);
}


bool SetAssociativeCache::access_associative(std::uint64_t block) {
  std::uint64_t* const ways = tags_.data() + (block & set_mask_) * assoc_;
  const std::uint32_t assoc = assoc_;
  if (geometry_.replacement == ReplacementPolicy::Random) {
    std::uint32_t free_way = assoc;
    for (std::uint32_t way = 0; way < assoc; ++way) {
      if (ways[way] == block) return false;
      if (ways[way] == kInvalid && free_way == assoc) free_way = way;
    }
    if (free_way == assoc) {
      // xorshift64*: deterministic, seeded per cache.
      random_state_ ^= random_state_ >> 12;
      random_state_ ^= random_state_ << 25;
      random_state_ ^= random_state_ >> 27;
      free_way = static_cast<std::uint32_t>((random_state_ * 0x2545F4914F6CDD1Dull >> 32) % assoc);
    }
    ways[free_way] = block;
    return true;
  }
  if (ways[0] == block) return false;
  for (std::uint32_t way = 1; way < assoc; ++way) {
    if (ways[way] == block) {
      if (geometry_.replacement == ReplacementPolicy::Lru) {
        std::move_backward(ways, ways + way, ways + way + 1);
        ways[0] = block;
      }
      return false;
    }
  }
  // Miss: the last way is invalid or the least recently used / filled.
  std::move_backward(ways, ways + assoc - 1, ways + assoc);
  ways[0] = block;
  return true;
}

void SetAssociativeCache::assign_set(std::uint64_t set, const std::vector<std::uint64_t>& ways) {
  std::copy(ways.begin(), ways.begin() + assoc_, tags_.begin() + static_cast<std::ptrdiff_t>(set * assoc_));
}

void SetAssociativeCache::invalidate(std::uint64_t block) {
  std::uint64_t* const ways = tags_.data() + (block & set_mask_) * assoc_;
  for (std::uint32_t way = 0; way < assoc_; ++way) {
    if (ways[way] != block) continue;
    if (geometry_.replacement == ReplacementPolicy::Random) {
      ways[way] = kInvalid;
    } else {
      std::move(ways + way + 1, ways + assoc_, ways + way);
      ways[assoc_ - 1] = kInvalid;
    }
    return;
  }
}

}  // namespace nodetrace::cachesim
