#include "accel/kdtree_events.hpp"

#include <algorithm>
#include <bit>
#include <utility>

#include "nodetrace/base/huge_pages.hpp"

namespace nodetrace::tracer::kd_build {

namespace {

// The event order as one integer: the position's bits made to sort as the
// float does (-0 and +0 as one), then type and triangle.
std::uint64_t sort_key(const Event& e) {
  const float position = e.position == 0.0f ? 0.0f : e.position;
  std::uint32_t bits = std::bit_cast<std::uint32_t>(position);
  bits = (bits & 0x80000000u) != 0 ? ~bits : bits | 0x80000000u;
  return std::uint64_t{bits} << 32 | e.type_and_triangle;
}

// LSD radix sort on sort_key, a byte per pass, through `buffer`; passes
// where every event has the same byte are skipped.
void radix_sort(std::span<Event> events, EventList& buffer) {
  constexpr int kPasses = 8;
  std::array<std::array<std::uint32_t, 256>, kPasses> counts{};
  for (const Event& e : events) {
    const std::uint64_t key = sort_key(e);
    for (int pass = 0; pass < kPasses; ++pass) ++counts[pass][(key >> (8 * pass)) & 0xff];
  }
  base::reserve_on_huge_pages(buffer, events.size());
  buffer.resize(events.size());
  Event* from = events.data();
  Event* to = buffer.data();
  for (int pass = 0; pass < kPasses; ++pass) {
    auto& count = counts[pass];
    if (std::find(count.begin(), count.end(), events.size()) != count.end()) continue;
    std::uint32_t offset = 0;
    for (auto& c : count) offset += std::exchange(c, offset);
    for (const Event* e = from; e != from + events.size(); ++e) to[count[(sort_key(*e) >> (8 * pass)) & 0xff]++] = *e;
    std::swap(from, to);
  }
  if (from != events.data()) std::copy(from, from + events.size(), events.data());
}

}  // namespace

void sort_events(std::span<Event> events, EventList& buffer) {
  // Radix sorting pays off for long lists only.
  if (events.size() >= 4096) {
    radix_sort(events, buffer);
  } else {
    std::sort(events.begin(), events.end(), event_less);
  }
}

}  // namespace nodetrace::tracer::kd_build
