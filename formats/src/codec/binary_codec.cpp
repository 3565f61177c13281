// The Dinero binary codec (`-informat b`, FORMAT.md 1.3): 8 bytes per record,
// u32 address, u16 size, u8 type, u8 padding; no tag.
#include <fmt/format.h>

#include "nodetrace/base/error.hpp"
#include "codec/record_codec.hpp"

namespace nodetrace::formats::detail {

bool parse_binary_records(std::string_view bytes, std::vector<Record>& out, RecordError& error) {
  const std::size_t whole = bytes.size() / 8;
  out.reserve(out.size() + whole);
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const std::size_t first = out.size();
  for (std::size_t i = 0; i < whole; ++i) {
    const unsigned char* r = data + i * 8;
    const std::uint32_t address = r[0] | (r[1] << 8) | (r[2] << 16) | (std::uint32_t{r[3]} << 24);
    const std::uint32_t size = r[4] | (r[5] << 8);
    const unsigned type = r[6];
    if (type >= static_cast<unsigned>(kAccessTypeCount)) {
      error = {out.size() - first, fmt::format("type {} is not a Dinero IV access type (0-5)", type)};
      return false;
    }
    if (size == 0) {
      error = {out.size() - first, "size 0 (a reference is at least 1 byte)"};
      return false;
    }
    out.push_back(Record{address, size, static_cast<AccessType>(type), TraversalUnit{}, kTagNone});
  }
  if (bytes.size() % 8 != 0) {
    error = {whole, fmt::format("truncated record: {} bytes of 8", bytes.size() % 8)};
    return false;
  }
  return true;
}

void put_binary_record(const Record& record, unsigned char* r) {
  if (record.address > 0xFFFFFFFFu) {
    throw base::FormatError(fmt::format("address {:#x} does not fit the 32 bits of a binary record", record.address));
  }
  if (record.size > 0xFFFFu) {
    throw base::FormatError(fmt::format("size {} does not fit the 16 bits of a binary record", record.size));
  }
  for (int b = 0; b < 4; ++b) r[b] = static_cast<unsigned char>(record.address >> (8 * b));
  r[4] = static_cast<unsigned char>(record.size);
  r[5] = static_cast<unsigned char>(record.size >> 8);
  r[6] = static_cast<unsigned char>(record.type);
  r[7] = 0;
}

void format_binary_records(std::span<const Record> records, std::uint64_t first_record, ByteBuffer& out) {
  const std::size_t start = out.size();
  out.resize(start + records.size() * 8);
  auto* bytes = reinterpret_cast<unsigned char*>(out.data() + start);
  for (std::size_t i = 0; i < records.size(); ++i) {
    try {
      put_binary_record(records[i], bytes + i * 8);
    } catch (const base::FormatError& error) {
      throw base::FormatError(fmt::format("record {}: {}", first_record + i + 1, error.what()));
    }
  }
}

}  // namespace nodetrace::formats::detail
