// What the render summary's rays per core-second rest on: the traversal time
// of one ray of each kind in kTimeEvery, and the render workers' CPU time.
// Timings only: they go to RenderStats for the human-readable summary, never
// into a trace, and which rays are timed changes nothing they record.
// Internal header.
#pragma once

#include <array>
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <ctime>

#include "nodetrace/tracer/render/render_stats.hpp"

namespace nodetrace::tracer::detail {

// CPU time of the calling thread (time other processes hold the core is not
// counted). A system call: read it per chunk of pixels, not per ray.
inline double thread_cpu_seconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return double(now.tv_sec) + double(now.tv_nsec) * 1e-9;
}

// Times one traversal in kTimeEvery of each kind, on the steady clock (about
// 40 ns a reading here, against some 300-1000 ns a ray: timing every ray
// would cost 5-10%, one in 32 is within noise). A reading is wall time, so
// an interval in which the thread lost its core (a time slice is
// milliseconds) is dropped rather than counted: no traversal of the scenes
// here comes near kInterrupted. The thread's CPU clock would need no such
// rule but costs a system call, some 2 us a reading on this machine.
class RayKindTimer {
 public:
  static constexpr std::uint32_t kTimeEvery = 32;
  static constexpr double kInterrupted = 200e-6;

  // Starts timing when this ray of `kind` is one to time.
  RayKindTimer(std::array<std::uint32_t, kRayKindCount>& countdown, RenderStats& stats, RayKind kind)
      : stats_(stats), kind_(static_cast<int>(kind)) {
    std::uint32_t& left = countdown[kind_];
    if (left-- != 0) return;
    left = kTimeEvery - 1;
    timing_ = true;
    start_ = Clock::now();
  }
  ~RayKindTimer() {
    if (!timing_) return;
    const double seconds = std::chrono::duration<double>(Clock::now() - start_).count() - clock_overhead();
    if (seconds >= kInterrupted) return;
    ++stats_.timed_rays[kind_];
    stats_.timed_seconds[kind_] += seconds > 0 ? seconds : 0;
  }
  RayKindTimer(const RayKindTimer&) = delete;
  RayKindTimer& operator=(const RayKindTimer&) = delete;

 private:
  using Clock = std::chrono::steady_clock;
  // What two readings with nothing between them measure, taken off each
  // interval: the smallest of a few tries, once per process.
  static double clock_overhead() {
    static const double overhead = [] {
      double least = 1;
      for (int i = 0; i < 64; ++i) {
        const auto a = Clock::now();
        const auto b = Clock::now();
        least = std::min(least, std::chrono::duration<double>(b - a).count());
      }
      return least;
    }();
    return overhead;
  }

  RenderStats& stats_;
  int kind_;
  bool timing_ = false;
  Clock::time_point start_;
};

}  // namespace nodetrace::tracer::detail
