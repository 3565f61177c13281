// Dinero IV d4-7, as its configure builds it on a 64-bit Linux, keeps
// addresses in 32 bits: a reference at or past 2^32 wraps there. `cachesim
// dinero` does the same and `cachesim run` keeps 64 bits, so on such records
// the two simulators differ by design; the programs that stand for Dinero IV
// (`cachesim dinero`, `dinero-wrap`) say so and count the records.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "nodetrace/formats/record/record.hpp"

namespace nodetrace::cachesim {

// Records whose bytes (as Dinero IV reads them in `form`) reach 2^32 or above.
std::uint64_t records_beyond_32_bits(std::span<const formats::Record> records, formats::RecordForm form);

// The note for `count` (> 0) such records of `trace`.
std::string beyond_32_bits_note(const std::string& trace, std::uint64_t count);

}  // namespace nodetrace::cachesim
