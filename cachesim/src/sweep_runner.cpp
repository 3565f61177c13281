// run_sweep: the reader decodes on the calling thread while one worker feeds
// the batches to every configuration, so decoding and simulation overlap.
#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>

#include "nodetrace/cachesim/sweep.hpp"

namespace nodetrace::cachesim {

TraceResult run_sweep(formats::TraceReader& reader, const std::vector<NodeCacheConfig>& configs,
                      const std::string& trace_column, bool per_level,
                      const SweepProgress& progress) {
  Sweep sweep(configs, trace_context(reader, trace_column), per_level);

  // A few batches circulate between the reader (fills free ones) and the
  // worker (simulates full ones and hands them back).
  constexpr std::size_t kBatches = 3;
  std::vector<formats::RecordBatch> batches(kBatches);
  std::deque<std::size_t> free_batches;
  std::deque<std::size_t> full_batches;
  for (std::size_t i = 0; i < kBatches; ++i) free_batches.push_back(i);
  std::mutex mutex;
  std::condition_variable changed;
  bool reading_done = false;
  bool stop = false;
  std::exception_ptr worker_error;

  std::thread worker([&] {
    try {
      while (true) {
        std::size_t index;
        {
          std::unique_lock lock(mutex);
          changed.wait(lock, [&] { return !full_batches.empty() || reading_done || stop; });
          if (stop) return;
          if (full_batches.empty()) return;  // reading done, all simulated
          index = full_batches.front();
          full_batches.pop_front();
        }
        sweep.feed(batches[index]);
        {
          std::lock_guard lock(mutex);
          free_batches.push_back(index);
        }
        changed.notify_all();
      }
    } catch (...) {
      std::lock_guard lock(mutex);
      worker_error = std::current_exception();
      stop = true;
      changed.notify_all();
    }
  });

  std::exception_ptr reader_error;
  try {
    while (true) {
      std::size_t index;
      {
        std::unique_lock lock(mutex);
        changed.wait(lock, [&] { return !free_batches.empty() || stop; });
        if (stop) break;
        index = free_batches.front();
        free_batches.pop_front();
      }
      const bool more = reader.next(batches[index]);
      const std::uint64_t records_read =
          more ? batches[index].first_record + batches[index].records.size() : 0;
      {
        std::lock_guard lock(mutex);
        if (more) {
          full_batches.push_back(index);
        } else {
          reading_done = true;
        }
      }
      changed.notify_all();
      if (!more) break;
      if (progress) progress(records_read);
    }
  } catch (...) {
    reader_error = std::current_exception();
    std::lock_guard lock(mutex);
    stop = true;
  }
  changed.notify_all();
  worker.join();
  // The worker's error concerns earlier records than the reader's.
  if (worker_error) std::rethrow_exception(worker_error);
  if (reader_error) std::rethrow_exception(reader_error);
  return sweep.finish();
}

}  // namespace nodetrace::cachesim
