// Internal: what a policy grid hands the set stacks of its block size.
#pragma once

#include <cstddef>
#include <vector>

#include "nodetrace/cachesim/models/set_stacks.hpp"
#include "nodetrace/formats/record/record.hpp"

namespace nodetrace::cachesim {

// What a policy grid's filters kept of the chunk it was fed last, set count
// by set count, for the set stacks of its block size (the grid's LRU and
// direct-mapped members), fed the same chunk next on the same thread: they
// walk these lists rather than find again which fetches are on top
// (SetStacks::access_records_filtered). Lists only when every record of the
// chunk was one demand fetch (no invalidation among them).
struct GridFilterOutput {
  const formats::Record* records = nullptr;  // the chunk the lists are of; null: no lists
  std::size_t count = 0;
  bool blocks_fit_32_bits = true;
  std::vector<SetStacks::Filtered> lists;  // fewest sets first
};

}  // namespace nodetrace::cachesim
