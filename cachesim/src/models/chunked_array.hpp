// Internal: an array of 32-bit values in chunks of 16 MiB, allocated as they
// are needed and never moved (a growing std::vector copies what it holds and
// faults in every page twice), each advised to the kernel as huge pages, and
// left uninitialised until written: MIN keeps 8 bytes per fetch of a whole
// trace here (opt_cache.hpp), where page faults and copies cost more than
// the simulation.
#pragma once

#include <sys/mman.h>

#include <cstdint>
#include <cstdlib>
#include <memory>
#include <new>
#include <vector>

namespace nodetrace::cachesim {

class ChunkedArray {
 public:
  static constexpr unsigned kChunkBits = 22;
  static constexpr std::uint64_t kChunk = std::uint64_t{1} << kChunkBits;  // values per chunk

  ChunkedArray() = default;
  // `size` values, unwritten.
  explicit ChunkedArray(std::uint64_t size) {
    while (capacity() < size) add_chunk();
    size_ = size;
  }

  void push_back(std::uint32_t value) {
    if (size_ == capacity()) add_chunk();
    chunks_.back()[size_ & (kChunk - 1)] = value;
    ++size_;
  }
  std::uint32_t operator[](std::uint64_t at) const { return chunks_[at >> kChunkBits][at & (kChunk - 1)]; }
  std::uint32_t& operator[](std::uint64_t at) { return chunks_[at >> kChunkBits][at & (kChunk - 1)]; }
  std::uint64_t size() const { return size_; }

 private:
  struct Free {
    void operator()(std::uint32_t* chunk) const { std::free(chunk); }
  };

  std::uint64_t capacity() const { return chunks_.size() * kChunk; }
  void add_chunk() {
    constexpr std::size_t kBytes = kChunk * sizeof(std::uint32_t);
    void* memory = std::aligned_alloc(std::size_t{2} << 20, kBytes);
    if (memory == nullptr) throw std::bad_alloc();
    madvise(memory, kBytes, MADV_HUGEPAGE);  // advice only: its failure changes nothing
    chunks_.emplace_back(static_cast<std::uint32_t*>(memory));
  }

  std::vector<std::unique_ptr<std::uint32_t[], Free>> chunks_;
  std::uint64_t size_ = 0;
};

}  // namespace nodetrace::cachesim
