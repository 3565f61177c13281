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
  const std::uint64_t span = view.size == 0 ? 0 : view.size - 1;
  range.last = (view.address + span) >> shift;
  if (range.last < range.first) range.last = range.first;  // wraps past 2^64
  return range;
}

// Is every record's block (address >> shift) below 2^32 - 1, so that it
// fits 32 bits with all ones left free (narrow tags and stack places)? One
// OR of block + 1, which reaches bit 32 exactly when a block does not fit:
// a loop the compiler vectorises.
inline bool record_blocks_fit_32_bits(const formats::Record* records, std::size_t count, unsigned shift) {
  std::uint64_t any = 0;
  for (std::size_t i = 0; i < count; ++i) any |= (records[i].address >> shift) + 1;
  return (any >> 32) == 0;
}

}  // namespace nodetrace::cachesim
