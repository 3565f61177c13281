// Mattson's LRU stack: one pass gives the miss count of every fully
// associative LRU cache size at once. A reference's stack position is the
// number of distinct blocks referenced since its previous reference, plus
// one; it misses in a cache of C blocks exactly when that exceeds C (or on
// its first reference).
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

namespace nodetrace::cachesim {

class LruStack {
 public:
  // References `block`; returns its stack position (1 = most recent), 0 for
  // a block never referenced before.
  std::uint64_t access(std::uint64_t block);

 private:
  void renumber();
  void add(std::uint64_t time, int delta);
  std::uint64_t prefix(std::uint64_t time) const;  // live stamps <= time

  std::unordered_map<std::uint64_t, std::uint64_t> last_;  // block -> time of last reference
  std::vector<std::int32_t> tree_;  // Fenwick tree over times 1..size()-1: 1 where a block's last reference is
  std::uint64_t now_ = 0;
};

// Misses of every power-of-two fully associative LRU size, from positions.
class LruSizeCurve {
 public:
  void count(std::uint64_t position);
  // Misses of a cache of 2^log2_blocks blocks.
  std::uint64_t misses(unsigned log2_blocks) const;
  std::uint64_t references() const { return references_; }

 private:
  std::uint64_t references_ = 0;
  std::uint64_t first_ = 0;                   // position 0
  std::vector<std::uint64_t> by_bucket_ = std::vector<std::uint64_t>(65, 0);  // smallest i with 2^i >= position
};

}  // namespace nodetrace::cachesim
