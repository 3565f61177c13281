#include "models/opt_cache.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <new>

#include "nodetrace/base/error.hpp"

namespace nodetrace::cachesim {

std::uint32_t OptStream::new_id(std::uint64_t block) {
  const auto id = static_cast<std::uint32_t>(blocks_.size());
  if (id == kInvalidateBit) {
    throw base::UsageError("--policy opt: more than 2^31 distinct blocks in one cache's stream");
  }
  blocks_.push_back(block);
  return id;
}

std::uint32_t OptStream::id_outside_window(std::uint64_t block) {
  if (!window_) {  // the first block: the window starts here
    window_.reset(static_cast<std::uint32_t*>(std::calloc(kWindow, sizeof(std::uint32_t))));
    if (!window_) throw std::bad_alloc();
    window_first_ = block;
    return id_of(block);
  }
  std::uint32_t id = ids_.find(block);
  if (id == BlockIndex::kAbsent) {
    id = new_id(block);
    ids_.insert(block, id);
  }
  return id;
}

void OptStream::append(std::uint32_t event) {
  // Event numbers, and kNever after them, must fit 32 bits.
  if (events_.size() >= kNever - 1) {
    throw base::UsageError(fmt::format(
        "--policy opt: more than {} fetches in one cache's stream (MIN keeps 8 bytes per fetch); "
        "simulate a part of the trace (tracetool cat) or sample it",
        kNever - 2));
  }
  events_.push_back(event);
}

ChunkedArray OptStream::next_uses() const {
  ChunkedArray next(events_.size());
  std::vector<std::uint32_t> following(blocks_.size(), kNever);
  for (std::uint64_t event = events_.size(); event-- > 0;) {
    if (is_invalidate(event)) {
      // The fetches before an invalidation are never used again: the block
      // leaves the cache first, and its next fetch is a miss whatever MIN
      // kept.
      next[event] = kNever;
      following[id(event)] = kNever;
      continue;
    }
    const std::uint32_t block = id(event);
    next[event] = following[block];
    following[block] = static_cast<std::uint32_t>(event);
  }
  return next;
}

namespace {

constexpr std::uint32_t kNone = ~std::uint32_t{0};
// Sets of more ways keep a heap of (next use, way) to find the farthest;
// smaller ones are scanned.
constexpr std::uint32_t kScanWays = 16;

struct Entry {
  std::uint32_t next_use;
  std::uint32_t slot;
  bool operator<(const Entry& other) const { return next_use < other.next_use; }
};

}  // namespace

std::uint64_t opt_misses(const OptStream& stream, const ChunkedArray& next_uses,
                         std::uint64_t sets, std::uint32_t assoc) {
  const std::uint64_t set_mask = sets - 1;
  std::vector<std::uint32_t> slot_of(stream.distinct_blocks(), kNone);  // per id
  std::vector<std::uint32_t> holder(sets * assoc, kNone);               // per slot: the id
  std::vector<std::uint32_t> next_use(sets * assoc, 0);                 // per slot
  std::vector<std::uint32_t> resident(sets, 0);
  const bool heaped = assoc > kScanWays;
  std::vector<std::vector<Entry>> heaps(heaped ? sets : 0);
  // A heap entry is current when its slot still holds a block with that next use.
  auto current = [&](const Entry& entry) {
    return holder[entry.slot] != kNone && next_use[entry.slot] == entry.next_use;
  };
  auto push = [&](std::uint64_t set, std::uint32_t slot) {
    std::vector<Entry>& heap = heaps[set];
    heap.push_back({next_use[slot], slot});
    std::push_heap(heap.begin(), heap.end());
    if (heap.size() > 4 * std::size_t{assoc} + 64) {  // drop the stale entries
      std::erase_if(heap, [&](const Entry& entry) { return !current(entry); });
      std::make_heap(heap.begin(), heap.end());
    }
  };
  std::uint64_t misses = 0;
  for (std::uint64_t event = 0; event < stream.events(); ++event) {
    const std::uint32_t id = stream.id(event);
    const std::uint64_t set = stream.block(id) & set_mask;
    std::uint32_t slot = slot_of[id];
    if (stream.is_invalidate(event)) {
      if (slot != kNone) {
        holder[slot] = kNone;
        slot_of[id] = kNone;
        --resident[set];
      }
      continue;
    }
    const std::uint32_t next = next_uses[event];
    if (slot == kNone) {
      ++misses;
      const auto first = static_cast<std::uint32_t>(set * assoc);
      if (resident[set] < assoc) {
        slot = first;
        while (holder[slot] != kNone) ++slot;
        ++resident[set];
      } else if (heaped) {
        std::vector<Entry>& heap = heaps[set];
        while (!current(heap.front())) {
          std::pop_heap(heap.begin(), heap.end());
          heap.pop_back();
        }
        if (heap.front().next_use <= next) continue;  // the incoming block is farthest: bypass
        slot = heap.front().slot;
        std::pop_heap(heap.begin(), heap.end());
        heap.pop_back();
        slot_of[holder[slot]] = kNone;
      } else {
        slot = first;
        for (std::uint32_t way = first + 1; way < first + assoc; ++way) {
          if (next_use[way] > next_use[slot]) slot = way;
        }
        if (next_use[slot] <= next) continue;  // bypass
        slot_of[holder[slot]] = kNone;
      }
      holder[slot] = id;
      slot_of[id] = slot;
    }
    next_use[slot] = next;
    if (heaped) push(set, slot);
  }
  return misses;
}

OptCache::OptCache(const CacheGeometry& geometry, std::shared_ptr<SharedOptStream> shared, bool records)
    : shared_(shared ? std::move(shared) : std::make_shared<SharedOptStream>()), records_(records) {
  validate_geometry(geometry, "cache");
  assoc_ = geometry.assoc;
  sets_ = geometry.size / geometry.block_size / geometry.assoc;
}

std::uint64_t OptCache::misses() const {
  if (!misses_) misses_ = opt_misses(shared_->stream(), shared_->next_uses(), sets_, assoc_);
  return *misses_;
}

}  // namespace nodetrace::cachesim
