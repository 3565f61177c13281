// A specialised node cache: one cache level, flat tag arrays, demand fetch,
// write-allocate (so reads and writes miss alike, as in Dinero IV's default
// write-allocate / write-back caches). Miss counts equal Dinero IV's for LRU
// and FIFO; random replacement is deterministic (seeded) but its choices are
// not Dinero IV's.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

namespace nodetrace::cachesim {

enum class ReplacementPolicy : std::uint8_t { Lru, Fifo, Random };

std::string_view policy_name(ReplacementPolicy policy);  // lru, fifo, random
std::optional<ReplacementPolicy> parse_policy_name(std::string_view name);
// Dinero IV's -l1-urepl letter: l, f, r.
char dinero_policy_letter(ReplacementPolicy policy);

struct NodeCacheGeometry {
  std::uint64_t size = 8192;  // bytes, a power of two
  std::uint32_t block = 8;    // bytes, a power of two
  std::uint32_t assoc = 1;    // ways; size / block is fully associative
  ReplacementPolicy policy = ReplacementPolicy::Lru;
};

// Throws formats::UsageError naming `what` (e.g. "low-level cache") when the
// geometry cannot be built: sizes not powers of two, block larger than the
// cache, associativity not dividing the blocks into a power-of-two of sets.
void validate_geometry(const NodeCacheGeometry& geometry, std::string_view what);

class NodeCache {
 public:
  static constexpr std::uint64_t kInvalid = ~std::uint64_t{0};

  explicit NodeCache(const NodeCacheGeometry& geometry, std::uint64_t seed = 0x5eed);

  const NodeCacheGeometry& geometry() const { return geometry_; }
  unsigned block_shift() const { return block_shift_; }
  std::uint64_t blocks() const { return tags_.size(); }

  // References block number `block` (address >> block_shift()); returns true
  // on a miss, after which the block is resident.
  bool access(std::uint64_t block) {
    if (assoc_ == 1) {
      std::uint64_t& slot = tags_[block & set_mask_];
      if (slot == block) return false;
      slot = block;
      return true;
    }
    return access_associative(block);
  }

  // For callers' own direct-mapped fast loops: the tag of set s is
  // direct_tags()[s & set_mask()] (one way per set only).
  bool direct_mapped() const { return assoc_ == 1; }
  std::uint64_t* direct_tags() { return tags_.data(); }
  std::uint64_t set_mask() const { return set_mask_; }

  // Removes `block` if resident (Dinero IV's invalidate records).
  void invalidate(std::uint64_t block);
  void flush();

 private:
  bool access_associative(std::uint64_t block);

  NodeCacheGeometry geometry_;
  unsigned block_shift_ = 0;
  std::uint32_t assoc_ = 1;
  std::uint64_t set_mask_ = 0;
  // sets * assoc block numbers. For LRU and FIFO each set is ordered most
  // recent (LRU: used, FIFO: filled) first, invalid entries last; for random
  // the order is the fill order of the ways.
  std::vector<std::uint64_t> tags_;
  std::uint64_t random_state_;
};

}  // namespace nodetrace::cachesim
