// The fast path for text records of other tools (internal): fields of any
// width, as `printf("%d %x\n")` writes them, where fixed_width_lines.hpp
// takes only our own zero-padded lines. It takes the common shapes
//   din:           LABEL ADDRESS [TAG]      LABEL one digit 0-5
//   extended din:  TYPE ADDRESS SIZE [TAG]  TYPE one of r w i m c v
// with one blank (space or tab) between fields, addresses and sizes of 1 to
// 16 hex digits after an optional 0x, and a newline ending each line. Any
// other line, and every line the general parser would reject, stops it: that
// line goes to the general parser, so records and errors are the general
// parser's whatever the input.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "codec/text_fields.hpp"
#include "nodetrace/formats/record/record.hpp"

namespace nodetrace::formats::detail {

// 1 to 16 hex digits (optional 0x) up to a blank or a newline.
inline bool read_variable_hex(const char*& p, const char* end, std::uint64_t& value) {
  if (end - p >= 2 && p[0] == '0' && (p[1] == 'x' || p[1] == 'X')) p += 2;
  const char* const digits = p;
  std::uint64_t result = 0;
  const char* const stop = end - p > 16 ? p + 16 : end;
  for (; p < stop; ++p) {
    const std::uint8_t digit = kHex[static_cast<unsigned char>(*p)];
    if (digit == 0xFF) break;
    result = (result << 4) | digit;
  }
  if (p == digits || p == end || (*p != ' ' && *p != '\t' && *p != '\n')) return false;
  value = result;
  return true;
}

// A node level (decimal, at most kMaxLevel), `p` or `t`, up to a newline.
inline bool read_variable_tag(const char*& p, const char* end, Tag& tag) {
  if (p < end && (*p == 'p' || *p == 't')) {
    tag = *p == 'p' ? kTagPrimitiveList : kTagTriangle;
    ++p;
    return p < end && *p == '\n';
  }
  const char* const digits = p;
  std::uint32_t level = 0;
  for (; p < end && p - digits < 6 && *p >= '0' && *p <= '9'; ++p) level = level * 10 + static_cast<unsigned>(*p - '0');
  if (p == digits || p == end || *p != '\n' || level > kMaxLevel) return false;
  tag = static_cast<Tag>(level);
  return true;
}

// Parses lines of the shapes above from `begin`, appending their records to
// `out`; returns the bytes of the whole lines taken (0 when the first is of
// another shape). Counts in `ignored_fields` the lines with a field after the
// significant ones when tags are not levels (one token: more goes to the
// general parser).
template <bool kExtended>
std::size_t variable_width_lines(const char* const begin, const char* const end, bool tags_are_levels,
                                 std::vector<Record>& out, std::uint64_t& ignored_fields) {
  const char* p = begin;
  while (p < end) {
    const char* q = p;
    Record record;
    const std::uint8_t type = kExtended ? kTypeLetter[static_cast<unsigned char>(*q)]
                                        : static_cast<std::uint8_t>(static_cast<unsigned char>(*q) - '0');
    if (type >= kAccessTypeCount) break;
    ++q;
    if (q == end || !is_blank(*q)) break;
    ++q;
    if (!read_variable_hex(q, end, record.address)) break;
    if constexpr (kExtended) {
      if (!is_blank(*q)) break;
      ++q;
      std::uint64_t size = 0;
      if (!read_variable_hex(q, end, size) || size == 0 || size > 0xFFFF) break;
      record.size = static_cast<std::uint32_t>(size);
    } else {
      record.size = 4;
    }
    record.type = static_cast<AccessType>(type);
    bool ignored = false;
    if (*q == '\n') {
      if (tags_are_levels) break;  // the tag is missing: the general parser says so
    } else {
      ++q;  // the blank after the significant fields
      if (tags_are_levels) {
        if (!read_variable_tag(q, end, record.tag)) break;
      } else {
        const char* const token = q;
        while (q < end && !is_blank(*q) && *q != '\n') ++q;
        if (q == token || q == end || *q != '\n') break;
        ignored = true;
      }
    }
    out.push_back(record);
    ignored_fields += ignored;
    p = q + 1;
  }
  return static_cast<std::size_t>(p - begin);
}

}  // namespace nodetrace::formats::detail
