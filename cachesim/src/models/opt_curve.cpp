#include "models/opt_curve.hpp"

#include <algorithm>

namespace nodetrace::cachesim {

namespace {

struct Entry {
  std::uint32_t next_use;
  std::uint32_t id;
  bool operator<(const Entry& other) const { return next_use < other.next_use; }
};

}  // namespace

std::vector<std::uint64_t> opt_size_curve(const OptStream& stream, const ChunkedArray& next_uses,
                                          unsigned layers) {
  const auto outside = static_cast<std::uint8_t>(layers);  // beyond the largest cache, or never fetched
  std::vector<std::uint8_t> layer_of(stream.distinct_blocks(), outside);
  std::vector<std::uint32_t> next_use(stream.distinct_blocks(), 0);
  std::vector<std::vector<Entry>> heaps(layers);
  std::vector<std::uint64_t> count(layers, 0);
  std::vector<std::uint64_t> capacity(layers, 1);
  for (unsigned k = 2; k < layers; ++k) capacity[k] = std::uint64_t{1} << (k - 1);
  std::vector<std::uint64_t> found_in(layers + 1, 0);  // fetches by the layer their block was in
  auto current = [&](unsigned k, const Entry& entry) {
    return layer_of[entry.id] == k && next_use[entry.id] == entry.next_use;
  };
  for (std::uint64_t event = 0; event < stream.events(); ++event) {
    const std::uint32_t id = stream.id(event);
    const std::uint8_t from = layer_of[id];
    if (from != outside) {
      --count[from];
      layer_of[id] = outside;  // its heap entry is stale from now on
    }
    if (stream.is_invalidate(event)) continue;
    ++found_in[from];
    std::uint32_t carried = id;
    std::uint32_t carried_next = next_uses[event];
    for (unsigned k = 0; k < layers; ++k) {
      std::vector<Entry>& heap = heaps[k];
      layer_of[carried] = static_cast<std::uint8_t>(k);
      next_use[carried] = carried_next;
      heap.push_back({carried_next, carried});
      std::push_heap(heap.begin(), heap.end());
      ++count[k];
      if (heap.size() > 2 * count[k] + 64) {  // drop the stale entries
        std::erase_if(heap, [&](const Entry& entry) { return !current(k, entry); });
        std::make_heap(heap.begin(), heap.end());
      }
      if (k == from || count[k] <= capacity[k]) break;
      while (!current(k, heap.front())) {
        std::pop_heap(heap.begin(), heap.end());
        heap.pop_back();
      }
      carried = heap.front().id;
      carried_next = heap.front().next_use;
      std::pop_heap(heap.begin(), heap.end());
      heap.pop_back();
      --count[k];
      layer_of[carried] = outside;  // unless the next layer takes it
    }
  }
  // A fetch found in layer j (or outside: j = layers) misses below 2^j blocks.
  std::vector<std::uint64_t> misses(layers, 0);
  std::uint64_t above = found_in[layers];
  for (unsigned k = layers; k-- > 0;) {
    misses[k] = above;
    above += found_in[k];
  }
  return misses;
}

}  // namespace nodetrace::cachesim
