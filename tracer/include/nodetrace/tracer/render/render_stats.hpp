// What a render counts: rays by kind, node fetches, leaves, triangle tests,
// records, dropped samples; and what it timed.
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
  // Timings for the summary only, never written to a trace: the render
  // workers' CPU time, and the traversal time of a sample of each kind's
  // rays (render/ray_timing.hpp).
  double cpu_seconds = 0;
  std::array<std::uint64_t, kRayKindCount> timed_rays{};
  std::array<double, kRayKindCount> timed_seconds{};
  // Rays of `kind` one core traverses per second: the timed rays over their
  // traversal time (records made included); 0 when none was timed.
  double traversal_rays_per_second(RayKind kind) const {
    const int k = static_cast<int>(kind);
    return timed_seconds[k] > 0 ? double(timed_rays[k]) / timed_seconds[k] : 0.0;
  }
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
    cpu_seconds += other.cpu_seconds;
    for (int k = 0; k < kRayKindCount; ++k) {
      timed_rays[k] += other.timed_rays[k];
      timed_seconds[k] += other.timed_seconds[k];
    }
    return *this;
  }
};

}  // namespace nodetrace::tracer
