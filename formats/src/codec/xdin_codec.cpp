// The extended din codec (Dinero IV `-informat D`, FORMAT.md 1.2):
// `TYPE ADDRESS SIZE [TAG]`.
#include <fmt/format.h>

#include "codec/fixed_width_lines.hpp"
#include "codec/record_codec.hpp"
#include "codec/text_fields.hpp"
#include "codec/variable_width_lines.hpp"

namespace nodetrace::formats::detail {
namespace {

// One line (without its newline), any layout Dinero IV accepts.
bool parse_xdin_line(const char* p, const char* end, const ParseSettings& settings, Record& record,
                     std::string& message, bool& ignored_fields) {
  p = skip_blanks(p, end);
  if (p == end) {
    message = "short line";
    return false;
  }
  const char* stop = token_end(p, end);
  const std::uint8_t type = stop - p == 1 ? kTypeLetter[static_cast<unsigned char>(*p)] : 0xFF;
  if (type == 0xFF) {
    message = fmt::format("unknown access type '{}'", shown_token(std::string_view(p, static_cast<std::size_t>(stop - p))));
    return false;
  }
  record.type = static_cast<AccessType>(type);
  p = stop;
  if (!read_address(p, end, record.address, message)) return false;
  p = skip_blanks(p, end);
  if (p == end) {
    message = "missing size";
    return false;
  }
  std::uint64_t size = 0;
  unsigned char bad = 0;
  switch (read_hex(p, end, size, bad)) {
    case HexStatus::BadDigit: message = bad_digit(bad, "size"); return false;
    case HexStatus::Empty: message = "missing size"; return false;
    case HexStatus::TooWide: size = ~std::uint64_t{0}; break;
    case HexStatus::Ok: break;
  }
  if (size == 0) {
    message = "size 0 (a reference is at least 1 byte)";
    return false;
  }
  if (size > 0xFFFFFFFFu) {
    message = "size wider than 32 bits";
    return false;
  }
  if (size > 0xFFFFu) {
    // docs/ARCHITECTURE.md: Dinero IV keeps the low 16 bits of a size and simulates
    // another reference than the line says.
    message = fmt::format("size {:#x} is 0x10000 or more: Dinero IV truncates sizes to 16 bits", size);
    return false;
  }
  record.size = static_cast<std::uint32_t>(size);
  return read_line_rest(p, end, settings, record, message, ignored_fields);
}

}  // namespace

bool parse_xdin_records(std::string_view bytes, const ParseSettings& settings, std::vector<Record>& out,
                        RecordError& error, std::uint64_t& ignored_fields) {
  bool tagged = false;
  const FastParser fast =
      bytes.empty() ? nullptr : choose_fast_parser<true>(bytes.data(), bytes.data() + bytes.size(), settings, tagged);
  return parse_text_lines(bytes, settings, fast, tagged, &variable_width_lines<true>, &parse_xdin_line, out, error,
                          ignored_fields);
}

void format_xdin_records(std::span<const Record> records, unsigned address_digits, unsigned unit_digits,
                         ByteBuffer& out, RecordSummary& summary) {
  format_text_records<true>(records, address_digits, unit_digits, out, summary);
}

}  // namespace nodetrace::formats::detail
