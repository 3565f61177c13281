#include "nodetrace/cachesim/models/set_associative_cache.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>

#include "dinero/libc_random.hpp"
#include "nodetrace/base/error.hpp"

namespace nodetrace::cachesim {

SetAssociativeCache::SetAssociativeCache(const CacheGeometry& geometry) : geometry_(geometry) {
  validate_geometry(geometry, "cache");
  if (!dinero_has_policy(geometry.replacement)) {
    throw base::UsageError(fmt::format("--policy {}: not simulated here (lru, fifo or random)",
                                       policy_name(geometry.replacement)));
  }
  if (geometry.replacement == ReplacementPolicy::Random) random_ = std::make_unique<detail::LibcRandom>();
  assoc_ = geometry.assoc;
  const std::uint64_t blocks = geometry.size / geometry.block_size;
  set_mask_ = blocks / assoc_ - 1;
  tags_.assign(blocks, kInvalid);
}

SetAssociativeCache::SetAssociativeCache(SetAssociativeCache&&) noexcept = default;
SetAssociativeCache& SetAssociativeCache::operator=(SetAssociativeCache&&) noexcept = default;
SetAssociativeCache::~SetAssociativeCache() = default;

bool SetAssociativeCache::access_associative(std::uint64_t block) {
  std::uint64_t* const ways = tags_.data() + (block & set_mask_) * assoc_;
  const std::uint32_t assoc = assoc_;
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
  // Miss: the last way is invalid or the least recently used / filled;
  // random evicts the k-th filled, k = random() % ways, when the set is full.
  std::uint32_t victim = assoc - 1;
  if (random_ && ways[assoc - 1] != kInvalid) victim = random_->next() % assoc;
  std::move_backward(ways, ways + victim, ways + victim + 1);
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
    std::move(ways + way + 1, ways + assoc_, ways + way);
    ways[assoc_ - 1] = kInvalid;
    return;
  }
}

}  // namespace nodetrace::cachesim
