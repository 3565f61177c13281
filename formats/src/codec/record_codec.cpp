// The record codecs by form (record_codec.hpp), and format_record.
#include "codec/record_codec.hpp"

#include "codec/text_fields.hpp"

namespace nodetrace::formats {
namespace detail {

namespace {

// The line of record `record` (0-based) in `bytes`.
std::string_view line_of(std::string_view bytes, std::uint64_t record) {
  std::size_t begin = 0;
  for (std::uint64_t line = 0; line < record && begin < bytes.size(); ++line) {
    const std::size_t newline = bytes.find('\n', begin);
    if (newline == std::string_view::npos) return {};
    begin = newline + 1;
  }
  return bytes.substr(begin, bytes.find('\n', begin) - begin);
}

}  // namespace

bool parse_records(std::string_view bytes, const ParseSettings& settings, std::vector<Record>& out,
                   RecordError& error, std::uint64_t& ignored_fields) {
  bool parsed = false;
  switch (settings.form) {
    case RecordForm::Din: parsed = parse_din_records(bytes, settings, out, error, ignored_fields); break;
    case RecordForm::ExtendedDin: parsed = parse_xdin_records(bytes, settings, out, error, ignored_fields); break;
    case RecordForm::Binary: return parse_binary_records(bytes, out, error);
  }
  // Text never holds a NUL; Dinero binary records almost always do (the pad byte).
  if (!parsed) error.not_text = line_of(bytes, error.record_in_chunk).find('\0') != std::string_view::npos;
  return parsed;
}

RecordForm detect_text_form(std::string_view first_bytes) {
  for (const char c : first_bytes) {
    if (is_blank(c)) continue;
    return kTypeLetter[static_cast<unsigned char>(c)] != 0xFF ? RecordForm::ExtendedDin : RecordForm::Din;
  }
  return RecordForm::Din;
}

void format_records(std::span<const Record> records, RecordForm form, unsigned address_digits,
                    unsigned unit_digits, std::uint64_t first_record, ByteBuffer& out, RecordSummary& summary) {
  switch (form) {
    case RecordForm::Din: format_din_records(records, address_digits, unit_digits, out, summary); return;
    case RecordForm::ExtendedDin: format_xdin_records(records, address_digits, unit_digits, out, summary); return;
    case RecordForm::Binary: break;
  }
  format_binary_records(records, first_record, out);
  summary.add(records);
}

}  // namespace detail

std::size_t format_record(const Record& record, RecordForm form, const TextLayout& layout, char* out) {
  if (form == RecordForm::Binary) {
    detail::put_binary_record(record, reinterpret_cast<unsigned char*>(out));
    return 8;
  }
  return static_cast<std::size_t>(detail::put_text_line(out, record, form == RecordForm::ExtendedDin, layout) - out);
}

}  // namespace nodetrace::formats
