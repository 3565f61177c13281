// The record codecs by form (record_codec.hpp), and format_record.
#include "codec/record_codec.hpp"

#include "codec/text_fields.hpp"

namespace nodetrace::formats {
namespace detail {

bool parse_records(std::string_view bytes, const ParseSettings& settings, std::vector<Record>& out,
                   RecordError& error, std::uint64_t& ignored_fields) {
  switch (settings.form) {
    case RecordForm::Din: return parse_din_records(bytes, settings, out, error, ignored_fields);
    case RecordForm::ExtendedDin: return parse_xdin_records(bytes, settings, out, error, ignored_fields);
    case RecordForm::Binary: break;
  }
  return parse_binary_records(bytes, out, error);
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
