// run_sweep: the reader decodes on the calling thread while worker threads
// simulate, each its own part of the configurations, so decoding and
// simulation overlap.
#include <algorithm>
#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>

#include "nodetrace/cachesim/sweep.hpp"

namespace nodetrace::cachesim {

TraceResult run_sweep(formats::TraceReader& reader, const std::vector<NodeCacheConfig>& configs,
                      const std::string& trace_column, bool per_level,
                      const SweepProgress& progress, bool per_frame) {
  Sweep sweep(configs, trace_context(reader, trace_column), per_level, per_frame);
  const std::size_t cores = std::max(1u, std::thread::hardware_concurrency());
  // The reader decodes on one thread per core too: half the cores simulate
  // (measured on 2 cores: a second simulating thread was no faster).
  sweep.set_parts(std::min(std::max<std::size_t>(1, cores / 2), configs.size()));

  // Batches circulate between the reader (fills free ones) and the workers
  // (each simulates its part of every full batch; the last one done frees it).
  constexpr std::size_t kBatches = 2;  // one simulated while the next is read
  std::vector<formats::RecordBatch> batches(kBatches);
  std::vector<std::size_t> parts_pending(kBatches, 0);
  std::deque<std::size_t> free_batches;
  for (std::size_t i = 0; i < kBatches; ++i) free_batches.push_back(i);
  std::vector<std::deque<std::size_t>> full_batches;  // per part, set once started
  std::mutex mutex;
  std::condition_variable changed;
  bool reading_done = false;
  bool stop = false;
  std::exception_ptr worker_error;
  std::vector<std::thread> workers;

  auto work = [&](std::size_t part) {
    try {
      while (true) {
        std::size_t index;
        {
          std::unique_lock lock(mutex);
          changed.wait(lock, [&] { return !full_batches[part].empty() || reading_done || stop; });
          if (stop) return;
          if (full_batches[part].empty()) return;  // reading done, all simulated
          index = full_batches[part].front();
          full_batches[part].pop_front();
        }
        sweep.feed_part(batches[index], part);
        {
          std::lock_guard lock(mutex);
          if (--parts_pending[index] == 0) free_batches.push_back(index);
        }
        changed.notify_all();
      }
    } catch (...) {
      std::lock_guard lock(mutex);
      if (!worker_error) worker_error = std::current_exception();
      stop = true;
      changed.notify_all();
    }
  };

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
      if (!more) break;
      const std::uint64_t records_read =
          batches[index].first_record + batches[index].records.size();
      // The first batch starts the sweep before any worker runs; every batch
      // advances K per animation frame here, in trace order.
      sweep.begin_batch(batches[index]);
      if (workers.empty()) {
        full_batches.resize(sweep.part_count());
        for (std::size_t part = 0; part < sweep.part_count(); ++part) {
          workers.emplace_back(work, part);
        }
      }
      {
        std::lock_guard lock(mutex);
        parts_pending[index] = full_batches.size();
        for (auto& queue : full_batches) queue.push_back(index);
      }
      changed.notify_all();
      if (progress) progress(records_read);
    }
  } catch (...) {
    reader_error = std::current_exception();
    std::lock_guard lock(mutex);
    stop = true;
  }
  {
    std::lock_guard lock(mutex);
    reading_done = true;
  }
  changed.notify_all();
  for (auto& worker : workers) worker.join();
  // A worker's error concerns earlier records than the reader's.
  if (worker_error) std::rethrow_exception(worker_error);
  if (reader_error) std::rethrow_exception(reader_error);
  return sweep.finish();
}

}  // namespace nodetrace::cachesim
