#include "models/record_blocks.hpp"

#include <fmt/format.h>

#include "nodetrace/base/error.hpp"
#include "nodetrace/cachesim/sweep/config.hpp"

namespace nodetrace::cachesim {

void refuse_last_block(const formats::Record* records, std::size_t count, formats::RecordForm form,
                       std::uint64_t first_record, const std::string& source_name) {
  constexpr std::uint64_t kLastAddress = ~std::uint64_t{0};
  for (std::size_t i = 0; i < count; ++i) {
    const formats::Record& record = records[i];
    if (is_other_stream(record.tag)) continue;
    if (record.type > formats::AccessType::Misc && record.type != formats::AccessType::Invalidate) continue;
    const formats::Record view = formats::dinero_view(record, form);
    const std::uint64_t span = record.type == formats::AccessType::Invalidate ? 0 : span_of(view);
    if (kLastAddress - view.address > span) continue;  // ends before the last address
    throw base::FormatError(fmt::format(
        "{}: record {}: address 0x{:x} of {} bytes reaches address 0xffffffffffffffff, whose 1-byte "
        "block (block number 2^64 - 1) is the caches' mark of a free way and is not simulated; "
        "use --block 2 or more",
        source_name, first_record + i + 1, view.address, view.size));
  }
}

}  // namespace nodetrace::cachesim
