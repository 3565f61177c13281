// A list that grows by blocks of fixed size, never by copying the whole of
// it, for the kd-tree builders' output.
#pragma once

#include <cstddef>
#include <vector>

namespace nodetrace::tracer::kd_build {

// A std::vector grown by doubling holds its old and its new copy at each
// step, and the allocator keeps the old ones resident after: for the lists
// a build makes (several per triangle) that was as much memory again. Here
// only the last block grows, and blocks are never moved.
template <typename T>
class BlockList {
 public:
  static constexpr std::size_t kBlockShift = 14;
  static constexpr std::size_t kBlockSize = std::size_t{1} << kBlockShift;

  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  T& operator[](std::size_t i) { return blocks_[i >> kBlockShift][i & (kBlockSize - 1)]; }
  const T& operator[](std::size_t i) const { return blocks_[i >> kBlockShift][i & (kBlockSize - 1)]; }

  T& emplace_back() {
    if (blocks_.empty()) {
      blocks_.emplace_back();  // grows as a vector: a short list stays short
    } else if (blocks_.back().size() == kBlockSize) {
      blocks_.emplace_back().reserve(kBlockSize);
    }
    ++size_;
    return blocks_.back().emplace_back();
  }
  void push_back(const T& value) { emplace_back() = value; }
  template <typename Iterator>
  void append(Iterator first, Iterator last) {
    for (; first != last; ++first) push_back(*first);
  }

 private:
  std::vector<std::vector<T>> blocks_;
  std::size_t size_ = 0;
};

}  // namespace nodetrace::tracer::kd_build
