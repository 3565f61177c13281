#include "nodetrace/cachesim/node_cache.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>

#include "nodetrace/formats/error.hpp"

namespace nodetrace::cachesim {

std::string_view policy_name(ReplacementPolicy policy) {
  switch (policy) {
    case ReplacementPolicy::Lru: return "lru";
    case ReplacementPolicy::Fifo: return "fifo";
    case ReplacementPolicy::Random: return "random";
  }
  return "lru";
}

std::optional<ReplacementPolicy> parse_policy_name(std::string_view name) {
  if (name == "lru" || name == "l") return ReplacementPolicy::Lru;
  if (name == "fifo" || name == "f") return ReplacementPolicy::Fifo;
  if (name == "random" || name == "r") return ReplacementPolicy::Random;
  return std::nullopt;
}

char dinero_policy_letter(ReplacementPolicy policy) { return policy_name(policy)[0]; }

void validate_geometry(const NodeCacheGeometry& geometry, std::string_view what) {
  using formats::UsageError;
  if (geometry.size == 0 || !std::has_single_bit(geometry.size)) {
    throw UsageError(fmt::format("{}: size {} is not a power of two", what, geometry.size));
  }
  if (geometry.block == 0 || !std::has_single_bit(geometry.block)) {
    throw UsageError(fmt::format("{}: block size {} is not a power of two", what, geometry.block));
  }
  if (geometry.block > geometry.size) {
    throw UsageError(fmt::format("{}: block size {} is larger than the cache size {}", what,
                                 geometry.block, geometry.size));
  }
  const std::uint64_t blocks = geometry.size / geometry.block;
  if (geometry.assoc == 0 || geometry.assoc > blocks || blocks % geometry.assoc != 0 ||
      !std::has_single_bit(blocks / geometry.assoc)) {
    throw UsageError(fmt::format(
        "{}: associativity {} does not divide the {} blocks of {} bytes into a power-of-two "
        "number of sets",
        what, geometry.assoc, blocks, geometry.size));
  }
}

NodeCache::NodeCache(const NodeCacheGeometry& geometry, std::uint64_t seed)
    : geometry_(geometry), random_state_(seed | 1) {
  validate_geometry(geometry, "cache");
  block_shift_ = static_cast<unsigned>(std::countr_zero(geometry.block));
  assoc_ = geometry.assoc;
  const std::uint64_t blocks = geometry.size / geometry.block;
  set_mask_ = blocks / assoc_ - 1;
  tags_.assign(blocks, kInvalid);
}

void NodeCache::flush() { std::fill(tags_.begin(), tags_.end(), kInvalid); }

bool NodeCache::access_associative(std::uint64_t block) {
  std::uint64_t* const ways = tags_.data() + (block & set_mask_) * assoc_;
  const std::uint32_t assoc = assoc_;
  if (geometry_.policy == ReplacementPolicy::Random) {
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
      if (geometry_.policy == ReplacementPolicy::Lru) {
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

void NodeCache::invalidate(std::uint64_t block) {
  std::uint64_t* const ways = tags_.data() + (block & set_mask_) * assoc_;
  for (std::uint32_t way = 0; way < assoc_; ++way) {
    if (ways[way] != block) continue;
    if (geometry_.policy == ReplacementPolicy::Random) {
      ways[way] = kInvalid;
    } else {
      std::move(ways + way + 1, ways + assoc_, ways + way);
      ways[assoc_ - 1] = kInvalid;
    }
    return;
  }
}

}  // namespace nodetrace::cachesim
