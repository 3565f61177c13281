// Internal: block number -> a 32-bit value (a cache slot, a dense block id),
// an open-addressing table with linear probing and backward-shift erase, so
// that a set of a thousand ways is found with one probe or two instead of a
// search way by way. It grows to keep at most half of its slots in use.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <vector>

namespace nodetrace::cachesim {

class BlockIndex {
 public:
  static constexpr std::uint32_t kAbsent = ~std::uint32_t{0};

  explicit BlockIndex(std::uint64_t expected = 16) { rehash(std::bit_ceil(std::max<std::uint64_t>(16, 2 * expected))); }

  std::uint32_t find(std::uint64_t block) const {
    for (std::uint64_t at = home(block);; at = (at + 1) & mask_) {
      const Entry& entry = entries_[at];
      if (entry.value == kAbsent) return kAbsent;
      if (entry.block == block) return entry.value;
    }
  }

  // Sets the value of `block` (which must not be kAbsent).
  void insert(std::uint64_t block, std::uint32_t value) {
    if (2 * (used_ + 1) > entries_.size()) rehash(2 * entries_.size());
    for (std::uint64_t at = home(block);; at = (at + 1) & mask_) {
      Entry& entry = entries_[at];
      if (entry.value == kAbsent) {
        entry = Entry{block, value};
        ++used_;
        return;
      }
      if (entry.block == block) {
        entry.value = value;
        return;
      }
    }
  }

  void erase(std::uint64_t block) {
    std::uint64_t at = home(block);
    for (;; at = (at + 1) & mask_) {
      if (entries_[at].value == kAbsent) return;
      if (entries_[at].block == block) break;
    }
    // Backward shift: move up every later entry of the run that may sit here.
    std::uint64_t hole = at;
    for (std::uint64_t next = (at + 1) & mask_; entries_[next].value != kAbsent; next = (next + 1) & mask_) {
      const std::uint64_t want = home(entries_[next].block);
      // `next` may move to `hole` when its home is not in (hole, next].
      if (((next - want) & mask_) >= ((next - hole) & mask_)) {
        entries_[hole] = entries_[next];
        hole = next;
      }
    }
    entries_[hole].value = kAbsent;
    --used_;
  }

  void clear() {
    for (Entry& entry : entries_) entry.value = kAbsent;
    used_ = 0;
  }
  std::uint64_t size() const { return used_; }

 private:
  struct Entry {
    std::uint64_t block = 0;
    std::uint32_t value = kAbsent;
  };

  std::uint64_t home(std::uint64_t block) const {
    // Fibonacci hashing: consecutive blocks land apart.
    return (block * 0x9E3779B97F4A7C15ull) >> shift_;
  }

  void rehash(std::uint64_t slots) {
    std::vector<Entry> old = std::move(entries_);
    entries_.assign(slots, Entry{});
    mask_ = slots - 1;
    shift_ = static_cast<unsigned>(64 - std::countr_zero(slots));
    used_ = 0;
    for (const Entry& entry : old) {
      if (entry.value != kAbsent) insert(entry.block, entry.value);
    }
  }

  std::vector<Entry> entries_;
  std::uint64_t mask_ = 0;
  unsigned shift_ = 64;
  std::uint64_t used_ = 0;
};

}  // namespace nodetrace::cachesim
