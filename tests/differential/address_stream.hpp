// Address streams that caches find interesting, for the differential tests'
// generators: loops, strides, hot sets, random jumps, unaligned sequential
// runs, switched every few hundred records, each run from a base the caller
// draws.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "seeded_draw.hpp"

namespace nodetrace::testing {

struct StreamShape {
  std::uint64_t longest_run = 400;  // records of one kind, at most
  std::uint64_t length_shifts = 9;  // loops and hot sets span 64 << (0 .. length_shifts - 1) bytes
  std::uint64_t most_hot = 48;      // addresses of a hot set, at most
  std::uint64_t jump_bits_low = 8, jump_bits_high = 22;  // jumps reach 2^(low .. high) bytes
};

class AddressStream {
 public:
  // `next_base` draws each run's base address.
  AddressStream(StreamShape shape, std::function<std::uint64_t(Draw&)> next_base)
      : shape_(shape), next_base_(std::move(next_base)) {}

  std::uint64_t next(Draw& draw) {
    if (left_ == 0) {
      mode_ = static_cast<int>(draw.below(5));
      left_ = draw.between(10, shape_.longest_run);
      base_ = next_base_(draw);
      length_ = std::uint64_t{64} << draw.below(shape_.length_shifts);
      step_ = draw.chance(50) ? std::uint64_t{4} << draw.below(4) : draw.between(1, 64);
      at_ = 0;
      hot_.clear();
      const auto hot_count = draw.between(2, shape_.most_hot);
      for (std::uint64_t i = 0; i < hot_count; ++i) hot_.push_back(base_ + draw.below(length_ * 4));
    }
    --left_;
    std::uint64_t address = 0;
    switch (mode_) {
      case 0: address = base_ + (at_ * step_) % length_; break;     // loop
      case 1: address = base_ + at_ * step_; break;                // stride
      case 2: address = hot_[draw.below(hot_.size())]; break;      // hot set
      case 3:                                                      // jumps
        address = base_ + draw.below(std::uint64_t{1} << draw.between(shape_.jump_bits_low, shape_.jump_bits_high));
        break;
      default: address = base_ + at_ * draw.between(1, 12); break;  // unaligned runs
    }
    ++at_;
    return address;
  }

 private:
  StreamShape shape_;
  std::function<std::uint64_t(Draw&)> next_base_;
  int mode_ = 0;
  std::uint64_t left_ = 0, base_ = 0, length_ = 0, step_ = 0, at_ = 0;
  std::vector<std::uint64_t> hot_;
};

}  // namespace nodetrace::testing
