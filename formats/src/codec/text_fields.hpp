// Dinero IV's text fields (internal), shared by the din and extended din
// codecs: what readers accept (FORMAT.md 1.4: blanks, hexadecimal fields,
// node-level tags, the error texts) and how writers put fields.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "codec/record_codec.hpp"

namespace nodetrace::formats::detail {

// Hex digit values; 0xFF marks a non-hex byte (OR-ing values and testing the
// high bits validates a whole field at once in the fast paths).
constexpr std::array<std::uint8_t, 256> make_hex_table() {
  std::array<std::uint8_t, 256> table{};
  for (auto& value : table) value = 0xFF;
  for (int c = '0'; c <= '9'; ++c) table[c] = static_cast<std::uint8_t>(c - '0');
  for (int c = 'a'; c <= 'f'; ++c) table[c] = static_cast<std::uint8_t>(c - 'a' + 10);
  for (int c = 'A'; c <= 'F'; ++c) table[c] = static_cast<std::uint8_t>(c - 'A' + 10);
  return table;
}
inline constexpr auto kHex = make_hex_table();

// Extended din access-type letters; 0xFF for anything else.
constexpr std::array<std::uint8_t, 256> make_type_table() {
  std::array<std::uint8_t, 256> table{};
  for (auto& value : table) value = 0xFF;
  table['r'] = 0;
  table['w'] = 1;
  table['i'] = 2;
  table['m'] = 3;
  table['c'] = 4;
  table['v'] = 5;
  return table;
}
inline constexpr auto kTypeLetter = make_type_table();
inline constexpr char kTypeLetters[] = {'r', 'w', 'i', 'm', 'c', 'v'};
inline constexpr char kHexDigits[] = "0123456789abcdef";

inline bool is_blank(char c) { return c == ' ' || c == '\t'; }

inline const char* skip_blanks(const char* p, const char* end) {
  while (p < end && is_blank(*p)) ++p;
  return p;
}

inline const char* token_end(const char* p, const char* end) {
  while (p < end && !is_blank(*p)) ++p;
  return p;
}

enum class HexStatus { Ok, Empty, BadDigit, TooWide };

// A hexadecimal field (optional 0x) running to the next blank or the end.
HexStatus read_hex(const char*& p, const char* end, std::uint64_t& value, unsigned char& bad);

// A token as an error message shows it: at most 32 bytes, control bytes and
// bytes above 0x7e escaped (a raw CR would move the terminal's cursor).
std::string shown_token(std::string_view token);

// `non hex digit (code 0x..) in FIELD`.
std::string bad_digit(unsigned char c, const char* field);

// The address field after the type (blanks first); false with `message` set
// when it is missing or bad.
bool read_address(const char*& p, const char* end, std::uint64_t& address, std::string& message);

// The rest of a line after its significant fields: the tag as a node level
// when the trace's tags are levels (it must be there) and then the unit when
// the trace's records carry units (it must be there too), else ignored (as
// Dinero IV ignores it), counting in `ignored_fields` that something was there.
bool read_line_rest(const char* p, const char* end, const ParseSettings& settings, Record& record,
                    std::string& message, bool& ignored_fields);

// A fast parser of a run of lines of one layout (fixed_width_lines.hpp): returns
// the bytes of the whole lines it took, stopping at the first other line.
// Takes tags_are_levels and ParseSettings::units.
using FastParser = std::size_t (*)(const char*, const char*, bool, unsigned, std::vector<Record>&);
// The fast parser of lines with fields of any width (variable_width_lines.hpp):
// returns the bytes of the whole lines it took and counts the lines whose
// ignored fields it dropped.
using VariableParser = std::size_t (*)(const char*, const char*, bool, std::vector<Record>&, std::uint64_t&);
// The general parser of one line (without its newline).
using LineParser = bool (*)(const char*, const char*, const ParseSettings&, Record&, std::string&, bool&);

// Parses text records: runs of lines through `fast` (when not nullptr; its
// lines carry a tag field when `fast_tagged`), then through `variable`,
// every other line through `line`. The contract of parse_records
// (record_codec.hpp).
bool parse_text_lines(std::string_view bytes, const ParseSettings& settings, FastParser fast, bool fast_tagged,
                      VariableParser variable, LineParser line, std::vector<Record>& out, RecordError& error,
                      std::uint64_t& ignored_fields);

inline char* put_hex(char* out, std::uint64_t value, unsigned min_digits) {
  unsigned digits = min_digits;
  while (digits < 16 && (value >> (4 * digits)) != 0) ++digits;
  for (unsigned i = digits; i-- > 0;) {
    *out++ = kHexDigits[(value >> (4 * i)) & 0xF];
  }
  return out;
}

// A blank and the tag (levels at least 2 digits), nothing for kTagNone.
inline char* put_tag(char* out, Tag tag) {
  if (tag == kTagNone) return out;
  *out++ = ' ';
  if (tag == kTagPrimitiveList) {
    *out++ = 'p';
  } else if (tag == kTagTriangle) {
    *out++ = 't';
  } else if (tag < 100) {
    *out++ = static_cast<char>('0' + tag / 10);
    *out++ = static_cast<char>('0' + tag % 10);
  } else {
    char digits[8];
    int count = 0;
    for (unsigned value = tag; value != 0; value /= 10) digits[count++] = static_cast<char>('0' + value % 10);
    while (count > 0) *out++ = digits[--count];
  }
  return out;
}

// A blank and the unit, zero-padded to `digits` (1 to 3).
inline char* put_unit(char* out, TraversalUnit unit, unsigned digits) {
  unsigned value = unit_index(unit);
  *out = ' ';
  for (unsigned i = digits; i > 0; --i) {
    out[i] = static_cast<char>('0' + value % 10);
    value /= 10;
  }
  return out + digits + 1;
}

// The general text line (any address, size and tag): din `LABEL ADDRESS
// [TAG [UNIT]]`, extended din `TYPE ADDRESS SIZE [TAG [UNIT]]`, then the
// newline.
inline char* put_text_line(char* p, const Record& record, bool extended, const TextLayout& layout) {
  const auto type = static_cast<unsigned>(record.type);
  *p++ = extended ? kTypeLetters[type] : static_cast<char>('0' + type);
  *p++ = ' ';
  p = put_hex(p, record.address, layout.address_digits);
  if (extended) {
    *p++ = ' ';
    p = put_hex(p, record.size, 1);
  }
  if (layout.tags) {
    p = put_tag(p, record.tag);
    if (layout.unit_digits != 0 && record.tag != kTagNone) p = put_unit(p, record.unit, layout.unit_digits);
  }
  *p++ = '\n';
  return p;
}

}  // namespace nodetrace::formats::detail
