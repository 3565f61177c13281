// What a render counts: rays by kind, node fetches, leaves, triangle tests,
// records.
#pragma once

#include <array>
#include <cstdint>

#include "nodetrace/tracer/render/ray_kinds.hpp"

namespace nodetrace::tracer {

struct RenderStats {
  std::array<std::uint64_t, kRayKindCount> rays{};
  std::uint64_t node_fetches = 0;    // node visits
  std::uint64_t leaf_visits = 0;     // leaves among them
  std::uint64_t triangle_tests = 0;  // ray/triangle tests
  std::uint64_t records = 0;         // records handed to the sink
  double seconds = 0;                // wall time of render()
  std::uint64_t total_rays() const { return rays[0] + rays[1] + rays[2] + rays[3]; }
  RenderStats& operator+=(const RenderStats& other) {
    for (int k = 0; k < kRayKindCount; ++k) rays[k] += other.rays[k];
    node_fetches += other.node_fetches;
    leaf_visits += other.leaf_visits;
    triangle_tests += other.triangle_tests;
    records += other.records;
    return *this;
  }
};

}  // namespace nodetrace::tracer
