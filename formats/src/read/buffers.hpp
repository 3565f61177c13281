// Reusable buffers (internal). Frames are megabytes each: allocating and
// zero-filling fresh memory per frame costs more than parsing it, so byte
// buffers are left uninitialised and both kinds of buffer are recycled.
#pragma once

#include <cstring>
#include <memory>
#include <mutex>
#include <string_view>
#include <utility>
#include <vector>

namespace nodetrace::formats::detail {

class ByteBuffer {
 public:
  char* data() { return data_.get(); }
  const char* data() const { return data_.get(); }
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  std::string_view view() const { return {data_.get(), size_}; }
  void clear() { size_ = 0; }

  void reserve(std::size_t capacity) {
    if (capacity <= capacity_) return;
    capacity = std::max(capacity, capacity_ + capacity_ / 2);
    auto grown = std::make_unique_for_overwrite<char[]>(capacity);
    if (size_ > 0) std::memcpy(grown.get(), data_.get(), size_);
    data_ = std::move(grown);
    capacity_ = capacity;
  }
  // Sets the size; new bytes are left for the caller to overwrite.
  void resize(std::size_t size) {
    reserve(size);
    size_ = size;
  }
  void append(const char* bytes, std::size_t count) {
    if (count == 0) return;  // an empty buffer has no data pointer to copy to
    reserve(size_ + count);
    std::memcpy(data_.get() + size_, bytes, count);
    size_ += count;
  }

 private:
  std::unique_ptr<char[]> data_;
  std::size_t size_ = 0;
  std::size_t capacity_ = 0;
};

// A bounded stock of spare buffers shared by the pipeline's threads.
template <typename Buffer>
class Recycler {
 public:
  explicit Recycler(std::size_t keep) : keep_(keep) {}
  void keep_at_most(std::size_t keep) {
    std::lock_guard lock(mutex_);
    keep_ = keep;
  }
  Buffer take() {
    std::lock_guard lock(mutex_);
    if (spare_.empty()) return Buffer{};
    Buffer buffer = std::move(spare_.back());
    spare_.pop_back();
    buffer.clear();
    return buffer;
  }
  void give(Buffer&& buffer) {
    std::lock_guard lock(mutex_);
    if (spare_.size() < keep_) spare_.push_back(std::move(buffer));
  }

 private:
  std::mutex mutex_;
  std::vector<Buffer> spare_;
  std::size_t keep_;
};

}  // namespace nodetrace::formats::detail
