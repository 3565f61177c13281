#include "accel/task_pool.hpp"

#include <algorithm>

namespace nodetrace::tracer {

TaskPool::Task::~Task() {
  if (pool_ == nullptr) return;
  if (!pool_->take_back(*this)) {
    // Unwinding: the taker still uses the task; its error has nowhere to go.
    std::unique_lock lock(pool_->mutex_);
    ++pool_->sleeping_;
    pool_->changed_.wait(lock, [this] { return done_; });
    --pool_->sleeping_;
  }
}

TaskPool::TaskPool(unsigned threads) {
  for (unsigned thread = 1; thread < threads; ++thread) workers_.emplace_back([this, thread] { work(thread); });
}

TaskPool::~TaskPool() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  for (auto& worker : workers_) worker.join();
}

void TaskPool::offer(Task& task) {
  task.pool_ = this;
  task.done_ = false;
  bool wake;
  {
    std::lock_guard lock(mutex_);
    offered_.push_back(&task);
    wake = sleeping_ > 0;
  }
  if (wake) changed_.notify_one();
}

bool TaskPool::take_back(Task& task) {
  std::lock_guard lock(mutex_);
  // The owner's latest offer still waiting is near the back.
  const auto it = std::find(offered_.rbegin(), offered_.rend(), &task);
  if (it == offered_.rend()) return false;
  offered_.erase(std::next(it).base());
  task.pool_ = nullptr;
  return true;
}

void TaskPool::wait(Task& task, unsigned thread) {
  std::unique_lock lock(mutex_);
  serve(lock, thread, [&] { return task.done_; });
  task.pool_ = nullptr;
  if (task.error_) std::rethrow_exception(task.error_);
}

void TaskPool::work(unsigned thread) {
  std::unique_lock lock(mutex_);
  serve(lock, thread, [&] { return stopping_; });
}

template <typename Finished>
void TaskPool::serve(std::unique_lock<std::mutex>& lock, unsigned thread, const Finished& finished) {
  while (!finished()) {
    if (!offered_.empty()) {
      run_oldest(lock, thread);
      continue;
    }
    ++sleeping_;
    changed_.wait(lock);
    --sleeping_;
  }
}

void TaskPool::run_oldest(std::unique_lock<std::mutex>& lock, unsigned thread) {
  Task& task = *offered_.front();
  offered_.pop_front();
  lock.unlock();
  std::exception_ptr error;
  try {
    task.work_(thread);
  } catch (...) {
    error = std::current_exception();
  }
  lock.lock();
  task.error_ = error;
  task.done_ = true;
  // The owner may be asleep; so may idle threads, which wake to nothing.
  if (sleeping_ > 0) changed_.notify_all();
}

}  // namespace nodetrace::tracer
