// Long calls (decoding, simulating, rendering) run in C++ with the GIL
// released, and call a SignalCheck between their steps (each batch of
// records, each block of pixels). At most every 50 ms it takes the GIL and
// runs Python's signal handlers, which run on the main thread only: a handler
// that raises (Ctrl-C: KeyboardInterrupt) stops the call with its exception.
// The work stays on the calling thread: the reader keeps per-thread decoding
// state, so one reader is never driven from several threads.
#pragma once

#include <pybind11/pybind11.h>

#include <atomic>
#include <chrono>
#include <cstdint>

namespace nodetrace::python {

class SignalCheck {
 public:
  void operator()() const {
    const std::int64_t now = std::chrono::duration_cast<std::chrono::milliseconds>(
                                 std::chrono::steady_clock::now().time_since_epoch())
                                 .count();
    if (now - last_.load(std::memory_order_relaxed) < 50) return;
    last_.store(now, std::memory_order_relaxed);
    pybind11::gil_scoped_acquire acquire;
    if (PyErr_CheckSignals() != 0) throw pybind11::error_already_set();
  }

 private:
  mutable std::atomic<std::int64_t> last_{0};
};

// Calls `work(const SignalCheck&)` with the GIL released and returns its
// result. `work` must not touch Python objects.
template <typename Work>
auto run_interruptibly(Work work) -> decltype(work(std::declval<const SignalCheck&>())) {
  const SignalCheck check;
  pybind11::gil_scoped_release release;
  return work(check);
}

}  // namespace nodetrace::python
