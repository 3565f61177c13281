// Parallel work, results in order: the one helper for every "do these jobs
// on worker threads, hand their results back in the order they were given"
// loop in nodetrace (the trace writer's compression, the trace reader's
// decoding, cachesim's simulation of one batch while the next is read).
//
//   OrderedPipeline<Frame> pipeline(threads);   // 0 threads: one per core
//   pipeline.submit([text] { return compress(text); });
//   pipeline.push_ready(marker_bytes);          // a result with no work, in its place
//   while (!pipeline.empty()) write(pipeline.pop());
//
// - Deterministic: pop() returns results in submission order whatever the
//   thread count and whatever order the jobs finish in.
// - Bounded: the pipeline never blocks submit(); callers keep at most
//   threads() + a few jobs in flight (size(), front_ready()) to bound memory.
// - Exception-safe: a job's exception is rethrown by the pop() that reaches
//   its place in the order (earlier results come out first). The destructor
//   waits for the jobs in flight (which may refer to the caller's data), then
//   stops and joins the threads; a thread that cannot be started is an error
//   from the constructor, after the ones started are joined.
//
// Jobs start in submission order (one FIFO queue) and finish in any order on
// any worker. A job may therefore wait for an earlier job (it has started;
// the render loop's mid-chunk hand-over of deep ray trees relies on this),
// never for a later one. Work that must stay sequential (one cache's state
// across batches) waits for the previous results before the next submit.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <system_error>
#include <thread>
#include <utility>
#include <vector>

namespace nodetrace::base {

// Threads to use when the caller says 0: one per core.
inline unsigned threads_or_cores(unsigned requested) {
  if (requested != 0) return requested;
  const unsigned cores = std::thread::hardware_concurrency();
  return cores == 0 ? 1 : cores;
}

// A fixed set of threads running queued tasks, oldest first (the pipeline
// below, and readers that schedule their own tasks).
class WorkerThreads {
 public:
  explicit WorkerThreads(unsigned threads) {
    if (threads == 0) threads = 1;
    try {
      for (unsigned i = 0; i < threads; ++i) workers_.emplace_back([this] { work(); });
    } catch (const std::system_error& error) {
      // A joinable std::thread left to its destructor would end the program.
      const std::size_t started = workers_.size();
      stop();
      throw std::runtime_error("cannot start " + std::to_string(threads) + " threads (" + std::to_string(started) +
                               " started): " + error.what());
    }
  }
  ~WorkerThreads() { stop(); }
  WorkerThreads(const WorkerThreads&) = delete;
  WorkerThreads& operator=(const WorkerThreads&) = delete;

  unsigned size() const { return static_cast<unsigned>(workers_.size()); }

  void post(std::function<void()> task) {
    {
      std::lock_guard lock(mutex_);
      tasks_.push_back(std::move(task));
    }
    wake_.notify_one();
  }

 private:
  void stop() {
    {
      std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    wake_.notify_all();
    for (auto& worker : workers_) worker.join();
    workers_.clear();
  }

  void work() {
    for (;;) {
      std::function<void()> task;
      {
        std::unique_lock lock(mutex_);
        wake_.wait(lock, [this] { return stopping_ || !tasks_.empty(); });
        if (tasks_.empty()) return;
        task = std::move(tasks_.front());
        tasks_.pop_front();
      }
      task();  // a packaged_task: it keeps its exception for the future
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::function<void()>> tasks_;
  std::vector<std::thread> workers_;
  bool stopping_ = false;
};

template <typename Result>
class OrderedPipeline {
 public:
  // `threads` workers; 0 means one per core.
  explicit OrderedPipeline(unsigned threads) : workers_(threads_or_cores(threads)) {}
  ~OrderedPipeline() { clear(); }
  OrderedPipeline(const OrderedPipeline&) = delete;
  OrderedPipeline& operator=(const OrderedPipeline&) = delete;

  unsigned threads() const { return workers_.size(); }
  // Results not yet popped (jobs in flight or done, and ready results).
  std::size_t size() const { return slots_.size(); }
  bool empty() const { return slots_.empty(); }

  // Runs `job` on a worker; its result (or exception) takes the next place.
  template <typename Job>
  void submit(Job job) {
    auto task = std::make_shared<std::packaged_task<Result()>>(std::move(job));
    slots_.push_back(task->get_future());
    workers_.post([task] { (*task)(); });
  }

  // A result made without work, in the next place.
  template <typename Value>
  void push_ready(Value&& value) {
    std::promise<Result> promise;
    promise.set_value(std::forward<Value>(value));
    slots_.push_back(promise.get_future());
  }

  // True when the oldest result is there (pop() would not wait).
  bool front_ready() const {
    return !slots_.empty() && slots_.front().wait_for(std::chrono::seconds(0)) == std::future_status::ready;
  }

  // The oldest result, waiting for it; rethrows its job's exception.
  // Precondition: !empty().
  Result pop() {
    std::future<Result> front = std::move(slots_.front());
    slots_.pop_front();
    return front.get();
  }

  // Waits for every job in flight and forgets all results.
  void clear() {
    for (auto& slot : slots_) {
      if (slot.valid()) slot.wait();
    }
    slots_.clear();
  }

 private:
  WorkerThreads workers_;
  std::deque<std::future<Result>> slots_;
};

}  // namespace nodetrace::base
