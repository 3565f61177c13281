// The blocks one record references, as Dinero IV simulates it.
#pragma once

#include <cstddef>
#include <cstdint>

#include "nodetrace/formats/record/record.hpp"

namespace nodetrace::cachesim {

struct BlockRange {
  std::uint64_t first = 0;
  std::uint64_t last = 0;  // >= first; a reference spanning two blocks is two fetches
};

// Blocks of 2^shift bytes; `aligned_din`: din records (4 bytes at a multiple
// of 4) with blocks of at least 4 bytes, so the record is one block.
inline BlockRange blocks_of(const formats::Record& record, formats::RecordForm form,
                            unsigned shift, bool aligned_din) {
  if (aligned_din) return {record.address >> shift, record.address >> shift};
  const formats::Record view = formats::dinero_view(record, form);
  BlockRange range;
  range.first = view.address >> shift;
  // Dinero IV invalidates the block of the address alone, whatever the size
  // (d4invalidate); the other types reference every block they span.
  if (record.type == formats::AccessType::Invalidate) {
    range.last = range.first;
    return range;
  }
  const std::uint64_t span = view.size == 0 ? 0 : view.size - 1;
  range.last = (view.address + span) >> shift;
  if (range.last < range.first) range.last = range.first;  // wraps past 2^64
  return range;
}

// The blocks of records that are each one block (address >> shift): a
// view for the loops that take blocks by index.
struct RecordBlocks {
  const formats::Record* records;
  unsigned shift;
  std::uint64_t operator[](std::size_t i) const { return records[i].address >> shift; }
};

// Is every block (`blocks[i]`: a pointer or a view) below 2^32 - 1, so that
// it fits 32 bits with all ones left free (narrow tags and stack places)?
// One OR of block + 1, which reaches bit 32 exactly when a block does not
// fit: a loop the compiler vectorises.
template <typename Blocks>
bool blocks_fit_32_bits(Blocks blocks, std::size_t count) {
  std::uint64_t any = 0;
  for (std::size_t i = 0; i < count; ++i) any |= blocks[i] + 1;
  return (any >> 32) == 0;
}

}  // namespace nodetrace::cachesim
