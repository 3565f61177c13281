// Record codecs (internal): parsing din / extended din / binary records from
// bytes and formatting them as our writers do, one codec per record form (as
// Dinero IV keeps dinfmt.c, xdinfmt.c, binaryfmt.c): din_codec.cpp,
// xdin_codec.cpp, binary_codec.cpp. The two text forms share the field rules
// of text_fields.hpp and the fast paths of fixed_width_lines.hpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "read/buffers.hpp"
#include "nodetrace/formats/record/record.hpp"
#include "nodetrace/formats/record/record_format.hpp"
#include "nodetrace/formats/record/record_summary.hpp"

namespace nodetrace::formats::detail {

// A bad record inside a chunk: `record_in_chunk` is 0-based within the chunk;
// the caller knows where the chunk starts and names the source.
struct RecordError {
  std::uint64_t record_in_chunk = 0;
  std::string message;
  bool not_text = false;  // a text record holding a NUL byte: binary records read as text
};

struct ParseSettings {
  RecordForm form = RecordForm::Din;
  bool tags_are_levels = false;
  // More than 1 (and tags_are_levels): each record's tag is followed by its
  // traversal unit, which must be below `units` (the header says how many).
  // Otherwise a unit field is ignored, as Dinero IV ignores it.
  unsigned units = 1;
  bool reads_units() const { return tags_are_levels && units > 1; }
};

// Parses the records in `bytes`, appending to `out`. Text: every line is a
// record, the last one may lack its newline; callers cut chunks after a
// newline. Binary: a size that is not a multiple of 8 reports the short
// record. Returns false and fills `error` on the first bad record. When tags
// are not levels, adds to `ignored_fields` the records whose line went on
// after its significant fields (a tag, a comment: ignored, as Dinero IV
// ignores them).
bool parse_records(std::string_view bytes, const ParseSettings& settings,
                   std::vector<Record>& out, RecordError& error, std::uint64_t& ignored_fields);

// Guesses din or extended din from the first record's first character.
RecordForm detect_text_form(std::string_view first_bytes);

// The longest line format_records writes.
inline constexpr std::size_t kMaxTextLine = kMaxFormattedRecord;

// Appends the records in `form`: text lines with fixed-width fields, or
// 8-byte binary records (what format_record writes with address_digits,
// tags and unit_digits, faster), and counts them in `summary`. Throws base::FormatError when a
// record cannot be written in that form (e.g. an address above 32 bits in
// binary); `first_record` is its 0-based number in the trace, for the message.
void format_records(std::span<const Record> records, RecordForm form, unsigned address_digits,
                    unsigned unit_digits, std::uint64_t first_record, ByteBuffer& out, RecordSummary& summary);

// The codecs behind parse_records / format_records / format_record.
bool parse_din_records(std::string_view bytes, const ParseSettings& settings, std::vector<Record>& out,
                       RecordError& error, std::uint64_t& ignored_fields);
void format_din_records(std::span<const Record> records, unsigned address_digits, unsigned unit_digits,
                        ByteBuffer& out, RecordSummary& summary);
bool parse_xdin_records(std::string_view bytes, const ParseSettings& settings, std::vector<Record>& out,
                        RecordError& error, std::uint64_t& ignored_fields);
void format_xdin_records(std::span<const Record> records, unsigned address_digits, unsigned unit_digits,
                         ByteBuffer& out, RecordSummary& summary);
bool parse_binary_records(std::string_view bytes, std::vector<Record>& out, RecordError& error);
void format_binary_records(std::span<const Record> records, std::uint64_t first_record, ByteBuffer& out);
// One binary record (8 bytes at `out`); throws base::FormatError, naming no record,
// when its address or size does not fit.
void put_binary_record(const Record& record, unsigned char* out);

}  // namespace nodetrace::formats::detail
