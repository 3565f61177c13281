// The din codec (Dinero IV `-informat d`, FORMAT.md 1.1): `LABEL ADDRESS [TAG]`.
#include <fmt/format.h>

#include "codec/fixed_width_lines.hpp"
#include "codec/record_codec.hpp"
#include "codec/text_fields.hpp"
#include "codec/variable_width_lines.hpp"

namespace nodetrace::formats::detail {
namespace {

// What Dinero IV (d4-7) does with a din label that is no access type: it
// keeps the label's low 8 bits as the type, where 8 marks the end of the
// trace and 8, 16... are flags of its own; DESIGN.md makes every such label an
// error here, and the message says what Dinero IV would have done instead.
std::string dinero_label_fate(std::uint64_t label) {
  const std::uint64_t kept = label & 0xFF;
  if (kept < static_cast<std::uint64_t>(kAccessTypeCount)) {
    return fmt::format("Dinero IV would accept it silently as label {} (it keeps the low 8 bits)", kept);
  }
  if (kept == 8) return "Dinero IV would accept it silently as the end of the trace";
  if ((kept & 7) >= 6) return "Dinero IV would stop with an internal error (exit 9)";
  return "Dinero IV would accept it silently, simulating a reference no demand count shows";
}

// One line (without its newline), any layout Dinero IV accepts.
bool parse_din_line(const char* p, const char* end, const ParseSettings& settings, Record& record,
                    std::string& message, bool& ignored_fields) {
  p = skip_blanks(p, end);
  if (p == end) {
    message = "short line";
    return false;
  }
  unsigned char bad = 0;
  const char* label_begin = p;
  std::uint64_t label = 0;
  switch (read_hex(p, end, label, bad)) {
    case HexStatus::BadDigit: message = bad_digit(bad, "label"); return false;
    case HexStatus::Empty: message = "no hex digits in label"; return false;
    case HexStatus::TooWide: label = ~std::uint64_t{0}; break;
    case HexStatus::Ok: break;
  }
  if (label >= static_cast<std::uint64_t>(kAccessTypeCount)) {
    message = fmt::format("label {} is not a Dinero IV access type (0-5); {}",
                          shown_token(std::string_view(label_begin, static_cast<std::size_t>(p - label_begin))),
                          dinero_label_fate(label));
    return false;
  }
  record.type = static_cast<AccessType>(label);
  record.size = 4;
  if (!read_address(p, end, record.address, message)) return false;
  return read_line_rest(p, end, settings, record, message, ignored_fields);
}

}  // namespace

bool parse_din_records(std::string_view bytes, const ParseSettings& settings, std::vector<Record>& out,
                       RecordError& error, std::uint64_t& ignored_fields) {
  bool tagged = false;
  const FastParser fast =
      bytes.empty() ? nullptr : choose_fast_parser<false>(bytes.data(), bytes.data() + bytes.size(), settings, tagged);
  return parse_text_lines(bytes, settings, fast, tagged, &variable_width_lines<false>, &parse_din_line, out, error,
                          ignored_fields);
}

void format_din_records(std::span<const Record> records, unsigned address_digits, unsigned unit_digits,
                        ByteBuffer& out, RecordSummary& summary) {
  format_text_records<false>(records, address_digits, unit_digits, out, summary);
}

}  // namespace nodetrace::formats::detail
