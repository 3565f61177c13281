// Internal: Belady's MIN needs the future, so the `opt` cache records the
// fetches it is given (4 bytes each, as a dense block id) and counts its
// misses when asked, after a backward pass that finds each fetch's next use
// (4 bytes more each): 8 bytes per fetch at the peak, plus about 50 per
// distinct block. No second read of the trace, standard input included.
//
// The rule (docs/guide/replacement-policies.md): on a miss in a full set, of the
// resident blocks and the incoming one, the one whose next use is farthest
// (never used again counts as farthest) is kept out; if that is the incoming
// block, it is not placed (bypass). A miss in a set with a free way fills it.
// A set-associative cache is MIN within each set. An invalidate removes the
// block; it is not a use.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <memory>
#include <optional>
#include <vector>

#include "models/block_index.hpp"
#include "models/chunked_array.hpp"
#include "nodetrace/cachesim/models/cache_geometry.hpp"

namespace nodetrace::cachesim {

// A cache's fetches and invalidations in order, blocks as dense ids.
class OptStream {
 public:
  static constexpr std::uint32_t kNever = ~std::uint32_t{0};

  void fetch(std::uint64_t block) { append(id_of(block)); }
  void invalidate(std::uint64_t block) { append(id_of(block) | kInvalidateBit); }

  std::uint64_t events() const { return events_.size(); }
  // An event: a fetch or an invalidation of the block with id id(event).
  bool is_invalidate(std::uint64_t event) const { return (events_[event] & kInvalidateBit) != 0; }
  std::uint32_t id(std::uint64_t event) const { return events_[event] & ~kInvalidateBit; }
  std::uint64_t block(std::uint32_t id) const { return blocks_[id]; }
  std::uint32_t distinct_blocks() const { return static_cast<std::uint32_t>(blocks_.size()); }
  // Per event: the event number of the block's next fetch, or kNever.
  ChunkedArray next_uses() const;

 private:
  static constexpr std::uint32_t kInvalidateBit = std::uint32_t{1} << 31;

  std::uint32_t id_of(std::uint64_t block) {
    if (block - window_first_ < kWindow && window_) {
      std::uint32_t& slot = window_[block - window_first_];
      if (slot == 0) slot = new_id(block) + 1;
      return slot - 1;
    }
    return id_outside_window(block);
  }
  std::uint32_t new_id(std::uint64_t block);
  std::uint32_t id_outside_window(std::uint64_t block);
  void append(std::uint32_t event);

  ChunkedArray events_;
  std::vector<std::uint64_t> blocks_;  // per id
  // Ids of the blocks in a window from the first block fetched (a tree's
  // nodes lie above its root), by index: id + 1, 0 for none yet (pages of
  // the window are zeroed by the system when first touched). Other blocks'
  // ids are in the hash index.
  static constexpr std::uint64_t kWindow = std::uint64_t{1} << 22;
  struct Free {
    void operator()(std::uint32_t* window) const { std::free(window); }
  };
  std::unique_ptr<std::uint32_t[], Free> window_;
  std::uint64_t window_first_ = 0;
  BlockIndex ids_;
};

// MIN's misses on `stream` in a cache of `sets` sets of `assoc` ways.
std::uint64_t opt_misses(const OptStream& stream, const ChunkedArray& next_uses,
                         std::uint64_t sets, std::uint32_t assoc);

// A stream shared by the opt caches that see the same fetches (one block
// size, one routing): the first records it, every one counts its own misses
// from it. Its next uses are found once, at the first count, when the
// stream is complete; counting is for one thread at a time.
class SharedOptStream {
 public:
  OptStream& stream() { return stream_; }
  const OptStream& stream() const { return stream_; }
  const ChunkedArray& next_uses() const {
    if (!next_uses_) next_uses_ = stream_.next_uses();
    return *next_uses_;
  }

 private:
  OptStream stream_;
  mutable std::optional<ChunkedArray> next_uses_;
};

// The cache model (cache_models.hpp's interface): access() records (when
// this cache is the stream's recorder) and answers "hit" (false); misses()
// is MIN's count once the stream is done.
class OptCache {
 public:
  // `shared` null: a stream of its own.
  explicit OptCache(const CacheGeometry& geometry, std::shared_ptr<SharedOptStream> shared = nullptr,
                    bool records = true);
  bool access(std::uint64_t block) {
    if (records_) shared_->stream().fetch(block);
    return false;
  }
  void invalidate(std::uint64_t block) {
    if (records_) shared_->stream().invalidate(block);
  }
  // Computed at the first call: the stream must be complete then.
  std::uint64_t misses() const;

 private:
  std::uint64_t sets_;
  std::uint32_t assoc_;
  std::shared_ptr<SharedOptStream> shared_;
  bool records_;
  mutable std::optional<std::uint64_t> misses_;
};

}  // namespace nodetrace::cachesim
