// A container's record hash (FORMAT.md: XXH64 of all record text, in order),
// fed by the workers as they decode, data frame after data frame in file
// order (internal). A worker hashes its text where zstd put it when every
// earlier frame is hashed, and holds a copy only while an earlier frame is
// still being decoded: with one worker nothing is copied, and the reader's
// thread never touches the text.
#pragma once

#include <xxhash.h>

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>

#include "read/buffers.hpp"

namespace nodetrace::formats::detail {

class RecordHashChain {
 public:
  RecordHashChain() { XXH64_reset(state_.get(), 0); }

  // Text of data frame `frame` (0-based among the frames hashed), in order;
  // `held` keeps what must wait for earlier frames.
  void add(std::uint64_t frame, const char* text, std::size_t size, ByteBuffer& held) {
    if (next_.load(std::memory_order_acquire) != frame) {
      held.append(text, size);
      return;
    }
    if (!held.empty()) {
      XXH64_update(state_.get(), held.data(), held.size());
      held.clear();
    }
    XXH64_update(state_.get(), text, size);
  }

  // Frame `frame` is whole: waits for the earlier frames, hashes what was
  // held and passes the turn on.
  void end_frame(std::uint64_t frame, ByteBuffer& held) {
    std::unique_lock lock(mutex_);
    turn_.wait(lock, [&] { return abandoned_ || next_.load(std::memory_order_acquire) == frame; });
    if (!abandoned_) XXH64_update(state_.get(), held.data(), held.size());
    held.clear();
    next_.store(frame + 1, std::memory_order_release);
    turn_.notify_all();
  }

  // A frame will not end (damage, a reader that stopped reading): nobody
  // waits for a turn any more, and the hash means nothing.
  void abandon() {
    std::lock_guard lock(mutex_);
    abandoned_ = true;
    turn_.notify_all();
  }

  // Once every frame has ended.
  std::uint64_t digest() const { return XXH64_digest(state_.get()); }

 private:
  struct StateDeleter {
    void operator()(XXH64_state_t* state) const { XXH64_freeState(state); }
  };

  std::unique_ptr<XXH64_state_t, StateDeleter> state_{XXH64_createState()};
  std::atomic<std::uint64_t> next_{0};  // the frame whose text is hashed now
  std::mutex mutex_;
  std::condition_variable turn_;
  bool abandoned_ = false;
};

}  // namespace nodetrace::formats::detail
