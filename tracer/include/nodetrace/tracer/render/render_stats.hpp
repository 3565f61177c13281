// What a render counts: rays by kind, node fetches, leaves, triangle tests,
// records, dropped samples.
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
  // Path tracing: samples dropped (counted as black) because their
  // throughput or radiance became NaN or infinite.
  std::uint64_t nonfinite_samples = 0;
  double seconds = 0;                // wall time of render()
  std::uint64_t total_rays() const {
    std::uint64_t total = 0;
    for (const std::uint64_t count : rays) total += count;
    return total;
  }
  RenderStats& operator+=(const RenderStats& other) {
    for (int k = 0; k < kRayKindCount; ++k) rays[k] += other.rays[k];
    node_fetches += other.node_fetches;
    leaf_visits += other.leaf_visits;
    triangle_tests += other.triangle_tests;
    records += other.records;
    nonfinite_samples += other.nonfinite_samples;
    return *this;
  }
};

}  // namespace nodetrace::tracer
