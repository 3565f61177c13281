// The blocks one record references, as Dinero IV simulates it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "nodetrace/formats/record/record.hpp"

namespace nodetrace::cachesim {

// A reference past address 2^64 - 1 continues at address 0, as Dinero IV's
// past its 2^32 - 1 does: its blocks run from `first` up to the last block
// number and on from block 0 to `last`. Walk them with after().
struct BlockRange {
  std::uint64_t first = 0;
  std::uint64_t last = 0;
  std::uint64_t last_block = ~std::uint64_t{0};  // the largest block number: 2^(64 - shift) - 1

  std::uint64_t after(std::uint64_t block) const { return (block + 1) & last_block; }
  std::uint64_t count() const { return ((last - first) & last_block) + 1; }
};

// The bytes past its first that a reference (as Dinero IV reads it) spans:
// its last byte is at address + span, modulo 2^64.
inline std::uint64_t span_of(const formats::Record& view) { return view.size == 0 ? 0 : view.size - 1; }

// Blocks of 2^shift bytes; `aligned_din`: din records (4 bytes at a multiple
// of 4) with blocks of at least 4 bytes, so the record is one block.
inline BlockRange blocks_of(const formats::Record& record, formats::RecordForm form,
                            unsigned shift, bool aligned_din) {
  const std::uint64_t last_block = ~std::uint64_t{0} >> shift;
  if (aligned_din) return {record.address >> shift, record.address >> shift, last_block};
  const formats::Record view = formats::dinero_view(record, form);
  const std::uint64_t first = view.address >> shift;
  // Dinero IV invalidates the block of the address alone, whatever the size
  // (d4invalidate); the other types reference every block they span.
  if (record.type == formats::AccessType::Invalidate) return {first, first, last_block};
  return {first, (view.address + span_of(view)) >> shift, last_block};
}

// Block number 2^64 - 1, a 1-byte block at the last address, is the mark of
// a free way in every cache model (with 1-byte blocks every 64-bit value is
// a block, so no mark is free of them): a reference that fetches or
// invalidates it is refused, naming the record, rather than miscounted.
// Throws base::FormatError; `first_record` is the 0-based number of
// records[0].
void refuse_last_block(const formats::Record* records, std::size_t count, formats::RecordForm form,
                       std::uint64_t first_record, const std::string& source_name);

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
