// Threads that run the tasks working threads offer (work stealing with one
// shared queue): an owner offers a task it would otherwise run later, works
// on something else, then takes the task back to run it itself if nobody
// took it, or waits for the thread that did, running other offered tasks in
// the meantime. Idle threads take the oldest task (the largest, for a
// depth-first owner) and otherwise sleep on a condition variable, so they
// burn no CPU.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace nodetrace::tracer {

class TaskPool {
 public:
  // Work offered by one thread. It must outlive its resolution: the owner
  // calls take_back() and, when that fails, wait(); a task still pending
  // when destroyed (an exception unwinding the owner) is resolved first.
  class Task {
   public:
    // `work` gets the index of the thread running it (0: the pool's owner).
    explicit Task(std::function<void(unsigned thread)> work) : work_(std::move(work)) {}
    Task(const Task&) = delete;
    Task& operator=(const Task&) = delete;
    ~Task();
    // Runs the work on the calling thread, e.g. the owner's after take_back().
    void run(unsigned thread) { work_(thread); }

   private:
    friend class TaskPool;
    std::function<void(unsigned)> work_;
    TaskPool* pool_ = nullptr;  // while offered and not yet resolved
    bool done_ = false;         // the taker finished it (guarded by the pool's mutex)
    std::exception_ptr error_;
  };

  // `threads` counts the calling thread (index 0): threads - 1 are started.
  explicit TaskPool(unsigned threads);
  TaskPool(const TaskPool&) = delete;
  TaskPool& operator=(const TaskPool&) = delete;
  ~TaskPool();

  unsigned threads() const { return static_cast<unsigned>(workers_.size()) + 1; }

  void offer(Task& task);
  // True when nobody took the task: it is the owner's to run, now.
  bool take_back(Task& task);
  // Waits until the thread that took the task has run it, running other
  // offered tasks meanwhile as thread `thread`; rethrows what the task threw.
  void wait(Task& task, unsigned thread);

 private:
  void work(unsigned thread);
  // Runs offered tasks as thread `thread`, sleeping while there are none,
  // until finished() (called with the lock held).
  template <typename Finished>
  void serve(std::unique_lock<std::mutex>& lock, unsigned thread, const Finished& finished);
  // Runs the oldest offered task, the lock held on entry and exit.
  void run_oldest(std::unique_lock<std::mutex>& lock, unsigned thread);

  std::mutex mutex_;
  std::condition_variable changed_;  // a task was offered or finished, or the pool stops
  std::deque<Task*> offered_;
  std::size_t sleeping_ = 0;  // threads waiting on changed_
  bool stopping_ = false;
  std::vector<std::thread> workers_;
};

}  // namespace nodetrace::tracer
