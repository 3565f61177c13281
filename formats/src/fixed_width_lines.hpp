// The fixed-width lines our writers produce (internal; FORMAT.md 1.1:
// `0 00001a38 07`, `r 00001a38 8 07`): a parser for runs of such lines and a
// writer of the common one, both without per-field loops. They are the fast
// paths of the din and extended din codecs; the general code of
// text_fields.hpp handles every other line and must agree with them
// (tests/formats/test_fixed_width_lines.cpp).
#pragma once

#include <array>
#include <cstring>

#include "nodetrace/formats/record_summary.hpp"
#include "text_fields.hpp"

namespace nodetrace::formats::detail {

// A run of lines that all have the layout of the first one: D address digits;
// a one-digit size for extended din; a two-digit tag when kTagged. Stops at
// the first line of another layout and returns the bytes consumed.
template <int D, bool kExtended, bool kTagged>
std::size_t fast_lines(const char* begin, const char* end, bool tags_are_levels, std::vector<Record>& out) {
  constexpr int kAddress = 2;
  constexpr int kAfterAddress = kAddress + D;
  constexpr int kSize = kAfterAddress + 1;
  constexpr int kTagPos = (kExtended ? kSize + 1 : kAfterAddress) + 1;
  constexpr int kLength = (kTagged ? kTagPos + 2 : kTagPos - 1) + 1;
  const char* p = begin;
  while (end - p >= kLength) {
    if (p[kLength - 1] != '\n' || p[1] != ' ' || p[kAfterAddress] != (kExtended || kTagged ? ' ' : '\n'))
      break;
    std::uint8_t type;
    if constexpr (kExtended) {
      type = kTypeLetter[static_cast<unsigned char>(p[0])];
    } else {
      type = static_cast<std::uint8_t>(static_cast<unsigned char>(p[0]) - '0');
      if (type >= kAccessTypeCount) type = 0xFF;
    }
    std::uint64_t address = 0;
    std::uint8_t bad = type;
    for (int i = 0; i < D; ++i) {
      const std::uint8_t digit = kHex[static_cast<unsigned char>(p[kAddress + i])];
      bad |= digit;
      address = (address << 4) | digit;
    }
    std::uint32_t size = 4;
    if constexpr (kExtended) {
      const std::uint8_t digit = kHex[static_cast<unsigned char>(p[kSize])];
      bad |= digit;
      size = digit;
      if (size == 0) break;
      if (p[kSize + 1] != (kTagged ? ' ' : '\n')) break;
    }
    Tag tag = kTagNone;
    if constexpr (kTagged) {
      const unsigned tens = static_cast<unsigned char>(p[kTagPos]) - '0';
      const unsigned ones = static_cast<unsigned char>(p[kTagPos + 1]) - '0';
      if (tens > 9 || ones > 9) break;
      if (tags_are_levels) tag = static_cast<Tag>(tens * 10 + ones);
    }
    if (bad & 0xF0) break;
    out.push_back(Record{address, size, static_cast<AccessType>(type), tag});
    p += kLength;
  }
  return static_cast<std::size_t>(p - begin);
}

// The fast parser for the layout of the line at `p`, or nullptr; `tagged`
// tells whether its lines carry a tag field.
template <bool kExtended>
FastParser choose_fast_parser(const char* p, const char* end, const ParseSettings& settings, bool& tagged) {
  const void* newline = std::memchr(p, '\n', static_cast<std::size_t>(std::min<std::ptrdiff_t>(end - p, 64)));
  if (!newline) return nullptr;
  const auto length = static_cast<const char*>(newline) - p + 1;
  for (const int digits : {8, 16}) {
    const int untagged = digits + (kExtended ? 5 : 3);
    const int tagged_length = untagged + 3;
    if (length == untagged && !settings.tags_are_levels) {
      return digits == 8 ? &fast_lines<8, kExtended, false> : &fast_lines<16, kExtended, false>;
    }
    if (length == tagged_length) {
      tagged = true;
      return digits == 8 ? &fast_lines<8, kExtended, true> : &fast_lines<16, kExtended, true>;
    }
  }
  return nullptr;
}

// Eight lower-case hex digits of a 32-bit value as they appear in memory
// (most significant first), without a loop: spread the nibbles one per byte,
// put them in text order, then add '0' or 'a' - 10 to every byte at once.
inline std::uint64_t hex8(std::uint32_t value) {
  std::uint64_t x = value;
  x = (x | (x << 16)) & 0x0000FFFF0000FFFFull;
  x = (x | (x << 8)) & 0x00FF00FF00FF00FFull;
  x = (x | (x << 4)) & 0x0F0F0F0F0F0F0F0Full;  // byte i = nibble i
  x = __builtin_bswap64(x);                      // byte i = nibble 7 - i
  const std::uint64_t letters = ((x + 0x0606060606060606ull) >> 4) & 0x0101010101010101ull;
  return x + 0x3030303030303030ull + letters * ('a' - '0' - 10);
}

// "00".."99" as two bytes each: the node levels of a fixed-width line.
constexpr std::array<char, 200> make_decimal_pairs() {
  std::array<char, 200> pairs{};
  for (int i = 0; i < 100; ++i) {
    pairs[2 * i] = static_cast<char>('0' + i / 10);
    pairs[2 * i + 1] = static_cast<char>('0' + i % 10);
  }
  return pairs;
}
inline constexpr auto kDecimalPairs = make_decimal_pairs();

// The common line, written with a few stores and no loop: a level-tagged
// record with a 32-bit address (and for extended din a one-digit size), as
// `0 00001a38 07\n` or `r 00001a38 8 07\n`. Returns false, writing nothing
// useful, when the record needs the general path.
template <bool kExtended>
bool put_common_line(char*& out, const Record& record) {
  if ((record.address >> 32) != 0 || record.tag >= 100 || (kExtended && record.size >= 16)) return false;
  char* p = out;
  const auto type = static_cast<unsigned>(record.type);
  p[0] = kExtended ? kTypeLetters[type] : static_cast<char>('0' + type);
  p[1] = ' ';
  const std::uint64_t digits = hex8(static_cast<std::uint32_t>(record.address));
  std::memcpy(p + 2, &digits, 8);
  p += 10;
  if constexpr (kExtended) {
    p[0] = ' ';
    p[1] = kHexDigits[record.size];
    p += 2;
  }
  p[0] = ' ';
  std::memcpy(p + 1, &kDecimalPairs[2 * record.tag], 2);
  p[3] = '\n';
  out = p + 4;
  return true;
}

// format_records for din (kExtended false) and extended din: the common line
// where it applies (8 address digits), the general line elsewhere. Counts
// each record in `summary` in the same pass: a second pass over the records
// cost the writer about a third of what formatting them does.
template <bool kExtended>
void format_text_records(std::span<const Record> records, unsigned address_digits, ByteBuffer& out,
                         RecordSummary& summary) {
  const std::size_t start = out.size();
  out.reserve(start + records.size() * kMaxTextLine);
  char* p = out.data() + start;
  const TextLayout layout{address_digits, true};
  if (address_digits != 8) {
    for (const Record& record : records) {
      summary.add(record);
      p = put_text_line(p, record, kExtended, layout);
    }
  } else {
    for (const Record& record : records) {
      summary.add(record);
      if (!put_common_line<kExtended>(p, record)) p = put_text_line(p, record, kExtended, layout);
    }
  }
  out.resize(static_cast<std::size_t>(p - out.data()));
}

}  // namespace nodetrace::formats::detail
