// Record codecs (internal): parsing din / extended din / binary records from
// bytes, and formatting records as the fixed-width text our writers produce.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "buffers.hpp"
#include "nodetrace/formats/record.hpp"
#include "nodetrace/formats/record_format.hpp"

namespace nodetrace::formats::detail {

// A bad record inside a chunk: `record_in_chunk` is 0-based within the chunk;
// the caller knows where the chunk starts and names the source.
struct RecordError {
  std::uint64_t record_in_chunk = 0;
  std::string message;
};

struct ParseSettings {
  RecordForm form = RecordForm::Din;
  bool tags_are_levels = false;
};

// Parses the records in `bytes`, appending to `out`. Text: every line is a
// record, the last one may lack its newline when `final`; when not `final`
// the bytes must end with a newline (callers cut chunks there). Binary: the
// size must be a multiple of 8 unless `final` reports the short record.
// Returns false and fills `error` on the first bad record. When tags are not
// levels, adds to `ignored_fields` the records whose line went on after its
// significant fields (a tag, a comment: ignored, as Dinero IV ignores them).
bool parse_records(std::string_view bytes, const ParseSettings& settings,
                   std::vector<Record>& out, RecordError& error, std::uint64_t& ignored_fields);

// Guesses din or extended din from the first record's first character.
RecordForm detect_text_form(std::string_view first_bytes);

// The longest line format_records writes.
inline constexpr std::size_t kMaxTextLine = kMaxFormattedRecord;

// Appends the records in `form`: text lines with fixed-width fields, or
// 8-byte binary records (what format_record writes with address_digits and
// tags, faster). Throws FormatError when a record cannot be written
// in that form (e.g. an address above 32 bits in binary); `first_record` is
// its 0-based number in the trace, for the message.
void format_records(std::span<const Record> records, RecordForm form, unsigned address_digits,
                    std::uint64_t first_record, ByteBuffer& out);

}  // namespace nodetrace::formats::detail
