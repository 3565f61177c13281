#include "nodetrace/cachesim/dinero/address_width.hpp"

#include <fmt/format.h>

#include "models/record_blocks.hpp"

namespace nodetrace::cachesim {

std::uint64_t records_beyond_32_bits(std::span<const formats::Record> records, formats::RecordForm form) {
  std::uint64_t count = 0;
  for (const formats::Record& record : records) {
    const formats::Record view = formats::dinero_view(record, form);
    const std::uint64_t last_byte = view.address + span_of(view);
    count += (view.address >> 32) != 0 || (last_byte >> 32) != 0 || last_byte < view.address;
  }
  return count;
}

std::string beyond_32_bits_note(const std::string& trace, std::uint64_t count) {
  return fmt::format(
      "{}: {} {} addresses at or above 2^32; Dinero IV (d4-7) keeps addresses in 32 bits, so they wrap at "
      "2^32 here as in Dinero IV, where cachesim run keeps 64 bits: the two may count them differently",
      trace, count, count == 1 ? "record reaches" : "records reach");
}

}  // namespace nodetrace::cachesim
