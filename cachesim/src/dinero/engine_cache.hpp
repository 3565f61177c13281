// Internal: one simulated cache, organised the way Dinero IV (d4-7) organises
// it so that every statistic comes out the same. Each set is a priority stack
// of assoc + 1 nodes (the extra one is the spare that a miss fills), kept as a
// circular doubly linked list in a flat node array; valid nodes always come
// first from the top (most recently used / most recently inserted).
// References a cache passes on (miss fetches, write-throughs, write-backs,
// the remainder of a reference that crosses a block boundary) go through a
// per-cache LIFO of pending references, drained in Dinero's order, because
// that order decides the state of the caches below.
#pragma once

#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "libc_random.hpp"
#include "nodetrace/cachesim/dinero/engine.hpp"
#include "nodetrace/formats/record/record.hpp"

namespace nodetrace::cachesim::detail {

// formats::AccessType as the small integers the engine indexes its counters by.
constexpr std::uint8_t access_index(formats::AccessType type) {
  return static_cast<std::uint8_t>(type);
}
inline constexpr std::uint8_t kRead = access_index(formats::AccessType::Read);
inline constexpr std::uint8_t kWrite = access_index(formats::AccessType::Write);
inline constexpr std::uint8_t kInstructionFetch =
    access_index(formats::AccessType::InstructionFetch);
inline constexpr std::uint8_t kMisc = access_index(formats::AccessType::Misc);
inline constexpr std::uint8_t kCopyBack = access_index(formats::AccessType::CopyBack);
inline constexpr std::uint8_t kInvalidate = access_index(formats::AccessType::Invalidate);

// Dinero IV's d4addr as its configure script makes it on LP64 hosts:
// `unsigned int`, since the script defines SIZEOF_INT but never SIZEOF_VOIDP.
// Addresses, and all arithmetic on them, are kept to 32 bits, as there.
inline constexpr std::uint64_t kAddressMask = 0xFFFFFFFFu;

// A memory reference as Dinero IV's d4memref: its size is 16 bits wide.
struct Ref {
  std::uint64_t address = 0;
  std::uint16_t size = 0;  // 0 with copy-back / invalidate: the whole cache
  std::uint8_t type = kRead;
  bool multi_block_rest = false;  // the remainder of a split reference
  bool prefetch = false;          // made by this cache's fetch policy
};

class Cache {
 public:
  // `random`: the hierarchy's one generator (random replacement, -pfabort).
  Cache(const CacheConfig& config, LibcRandom& random);

  void ref(const Ref& m) {
    if (m.type < kCopyBack) {
      demand_ref(m);
    } else if (m.type == kCopyBack) {
      copy_back(m);
    } else {
      invalidate(m);
    }
  }

  Cache* downstream = nullptr;  // nullptr: memory
  Stats stats;

 private:
  static constexpr std::uint32_t kNone = 0xFFFFFFFFu;
  static constexpr int kHashThreshold = 8;  // stacks of more nodes use a hash index

  struct Node {
    std::uint64_t block = 0;
    std::uint32_t valid = 0;  // one bit per sub-block
    std::uint32_t dirty = 0;
    std::uint32_t referenced = 0;  // sub-blocks a demand reference touched (tagged prefetch)
    std::uint32_t up = 0;    // towards the top (more recent); top->up is the bottom
    std::uint32_t down = 0;  // towards the bottom
  };

  struct Stack {
    std::uint32_t top = 0;
    std::uint32_t size = 0;  // nodes, assoc + 1
    bool hashed = false;
  };

  void demand_ref(Ref m);
  // The fetch policy's prefetch for demand reference `m` (queued, unless
  // -pfabort throws it away); `node` is where m's block was found, if it was.
  void prefetch_for(const Ref& m, bool miss, std::uint32_t node);
  void copy_back(const Ref& m);
  void invalidate(const Ref& m);
  void drain_pending();

  std::uint32_t find(std::uint32_t stack, std::uint64_t block) const;
  void move_to_top(std::uint32_t stack, std::uint32_t node);
  void move_to_bottom(std::uint32_t stack, std::uint32_t node);
  // Unlinks `node` and puts it between the bottom of the ring and `top`
  // (i.e. at the bottom); the caller decides whether it becomes the top.
  void relink_above_top(std::uint32_t top, std::uint32_t node);
  std::uint32_t nth_from_top(std::uint32_t stack, std::uint32_t n) const;
  std::uint32_t replace(std::uint32_t stack, std::uint64_t block, std::uint32_t hit);
  void index_node(std::uint32_t stack, std::uint32_t node);
  void unindex_node(std::uint32_t stack, std::uint32_t node);
  void invalidate_node(std::uint32_t stack, std::uint32_t node);
  void write_back_block(std::uint32_t node);
  int infinite_cache(const Ref& m);
  void invalidate_infinite_cache(const Ref& m);

  std::uint64_t block_of(std::uint64_t address) const { return address & kAddressMask & ~block_mask_; }
  std::uint64_t sub_block_of(std::uint64_t address) const {
    return address & kAddressMask & ~sub_block_mask_;
  }
  std::uint32_t set_of(std::uint64_t address) const {
    return static_cast<std::uint32_t>((address >> lg2_block_) & set_mask_);
  }
  std::uint64_t sub_blocks_touched(const Ref& m) const {
    return ((m.address + m.size - 1) >> lg2_sub_block_) - (m.address >> lg2_sub_block_) + 1;
  }
  // Dinero's D4ADDR2SBMASK, with its 32-bit shift: touching all 32
  // sub-blocks of a block gives no bits at all.
  std::uint32_t sub_block_bits(const Ref& m) const;
  // The bits of the sub-blocks touched, for the infinite cache (which
  // counts them one by one in Dinero IV, without that mask).
  std::uint32_t touched_bits(const Ref& m) const;

  CacheConfig config_;
  int lg2_block_;
  int lg2_sub_block_;
  std::uint64_t block_mask_;
  std::uint64_t sub_block_mask_;
  bool whole_blocks_;  // no sub-blocks: a reference within a block touches bit 0 only
  std::uint64_t set_mask_;
  std::uint32_t sets_;
  std::uint32_t full_set_;  // the fully associative shadow's stack (== sets_), if classifying

  std::vector<Node> nodes_;
  std::vector<Stack> stacks_;
  std::unordered_map<std::uint64_t, std::uint32_t> index_;         // block -> node, hashed sets
  std::unordered_map<std::uint64_t, std::uint32_t> shadow_index_;  // same for the shadow
  std::unordered_map<std::uint64_t, std::uint32_t> seen_;  // infinite cache: block -> sub-block bits
  std::vector<Ref> pending_;
  bool draining_ = false;
  LibcRandom& random_;
};

}  // namespace nodetrace::cachesim::detail
