// The kd-tree build's events: where each triangle's extent starts, ends or
// lies flat on an axis, in the total order the SAH sweep reads them.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <span>
#include <utility>
#include <vector>

#include "nodetrace/tracer/accel/kdtree.hpp"

namespace nodetrace::tracer::kd_build {

// Event order at one position: ends before planars before starts, so a sweep
// sees a plane with the triangles ending on it already counted left.
enum EventType : std::uint32_t { kEnd = 0, kPlanar = 1, kStart = 2 };

// Triangle indices take the low 30 bits of an event, its type the top two.
constexpr unsigned kTriangleBits = 30;
constexpr std::uint32_t kTriangleMask = (std::uint32_t{1} << kTriangleBits) - 1;

// Where a triangle's (clipped) extent starts, ends, or lies flat on one axis.
struct Event {
  float position;
  std::uint32_t type_and_triangle;
  std::uint32_t triangle() const { return type_and_triangle & kTriangleMask; }
  std::uint32_t type() const { return type_and_triangle >> kTriangleBits; }
};

// Total order (position, type, triangle) within an axis; ties are broken by
// triangle, so sorting is deterministic.
inline bool event_less(const Event& a, const Event& b) {
  return a.position < b.position || (a.position == b.position && a.type_and_triangle < b.type_and_triangle);
}

// Leaves a list's new elements unwritten (a resize does not zero them): a
// node's split writes each child's events into a list sized for the most it
// can hold, and zeroing that first would double the writes.
template <typename T>
struct UninitializedAllocator : std::allocator<T> {
  template <typename U>
  void construct(U* place) noexcept {
    ::new (static_cast<void*>(place)) U;
  }
  template <typename U, typename... Args>
  void construct(U* place, Args&&... args) {
    ::new (static_cast<void*>(place)) U(std::forward<Args>(args)...);
  }
};

// A node's list of events.
using EventList = std::vector<Event, UninitializedAllocator<Event>>;

// A node's events: those of axis a, sorted, are [begin[a], begin[a + 1]).
struct NodeEvents {
  EventList events;
  std::array<std::size_t, 4> begin{};
  std::span<const Event> axis(int a) const { return {events.data() + begin[a], events.data() + begin[a + 1]}; }
};

// Events of triangles clipped in one node, one list per axis.
using AxisEvents = std::array<std::vector<Event>, 3>;

enum Side : std::uint8_t { kBoth = 0, kLeftOnly = 1, kRightOnly = 2 };

inline double surface_area(const Bounds& box) {
  const double dx = double(box.hi.x) - box.lo.x, dy = double(box.hi.y) - box.lo.y,
               dz = double(box.hi.z) - box.lo.z;
  return 2.0 * (dx * dy + dy * dz + dz * dx);
}

inline void add_events(AxisEvents& events, std::uint32_t triangle, const Bounds& box) {
  for (int axis = 0; axis < 3; ++axis) {
    auto& list = events[axis];
    if (box.lo[axis] == box.hi[axis]) {
      list.push_back({box.lo[axis], kPlanar << kTriangleBits | triangle});
    } else {
      list.push_back({box.lo[axis], kStart << kTriangleBits | triangle});
      list.push_back({box.hi[axis], kEnd << kTriangleBits | triangle});
    }
  }
}

// Sorts one axis's events in event_less order, through `buffer`.
void sort_events(std::span<Event> events, EventList& buffer);

}  // namespace nodetrace::tracer::kd_build
