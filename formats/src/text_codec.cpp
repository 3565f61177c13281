#include "text_codec.hpp"

#include <fmt/format.h>

#include <array>
#include <cstring>

#include "nodetrace/formats/error.hpp"

namespace nodetrace::formats::detail {
namespace {

// Hex digit values; 0xFF marks a non-hex byte (OR-ing values and testing the
// high bits validates a whole field at once in the fast path).
constexpr std::array<std::uint8_t, 256> make_hex_table() {
  std::array<std::uint8_t, 256> table{};
  for (auto& value : table) value = 0xFF;
  for (int c = '0'; c <= '9'; ++c) table[c] = static_cast<std::uint8_t>(c - '0');
  for (int c = 'a'; c <= 'f'; ++c) table[c] = static_cast<std::uint8_t>(c - 'a' + 10);
  for (int c = 'A'; c <= 'F'; ++c) table[c] = static_cast<std::uint8_t>(c - 'A' + 10);
  return table;
}
constexpr auto kHex = make_hex_table();

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
constexpr auto kTypeLetter = make_type_table();
constexpr char kTypeLetters[] = {'r', 'w', 'i', 'm', 'c', 'v'};
constexpr char kHexDigits[] = "0123456789abcdef";

bool is_blank(char c) { return c == ' ' || c == '\t'; }

const char* skip_blanks(const char* p, const char* end) {
  while (p < end && is_blank(*p)) ++p;
  return p;
}

const char* token_end(const char* p, const char* end) {
  while (p < end && !is_blank(*p)) ++p;
  return p;
}

enum class HexStatus { Ok, Empty, BadDigit, TooWide };

// A hexadecimal field (optional 0x) running to the next blank or the end.
HexStatus read_hex(const char*& p, const char* end, std::uint64_t& value, unsigned char& bad) {
  if (end - p >= 2 && p[0] == '0' && (p[1] == 'x' || p[1] == 'X')) p += 2;
  const char* digits = p;
  std::uint64_t result = 0;
  int significant = 0;
  for (; p < end && !is_blank(*p); ++p) {
    const std::uint8_t digit = kHex[static_cast<unsigned char>(*p)];
    if (digit == 0xFF) {
      bad = static_cast<unsigned char>(*p);
      return HexStatus::BadDigit;
    }
    if (significant > 0 || digit != 0) ++significant;
    result = (result << 4) | digit;
  }
  if (p == digits) return HexStatus::Empty;
  if (significant > 16) return HexStatus::TooWide;
  value = result;
  return HexStatus::Ok;
}

// A token as an error message shows it: at most 32 bytes, control bytes and
// bytes above 0x7e escaped (a raw CR would move the terminal's cursor).
std::string shown_token(std::string_view token) {
  std::string shown;
  for (const char c : token.substr(0, 32)) {
    const auto byte = static_cast<unsigned char>(c);
    if (c == '\r') shown += "\\r";
    else if (c == '\t') shown += "\\t";
    else if (byte < 0x20 || byte > 0x7e) shown += fmt::format("\\x{:02x}", byte);
    else shown += c;
  }
  return shown;
}

std::string bad_digit(unsigned char c, const char* field) {
  return fmt::format("non hex digit (code {:#x}) in {}", static_cast<unsigned>(c), field);
}

// The tag field as a node level, `p` or `t`.
bool read_tag(const char* p, const char* end, Tag& tag, std::string& message) {
  p = skip_blanks(p, end);
  if (p == end) {
    message = "missing tag (the trace's tags are node levels)";
    return false;
  }
  const char* stop = token_end(p, end);
  const std::string_view token(p, static_cast<std::size_t>(stop - p));
  if (token == "p") {
    tag = kTagPrimitiveList;
    return true;
  }
  if (token == "t") {
    tag = kTagTriangle;
    return true;
  }
  std::uint64_t level = 0;
  bool decimal = true;
  for (const char c : token) {
    if (c < '0' || c > '9') {
      decimal = false;
      break;
    }
    level = level * 10 + static_cast<unsigned>(c - '0');
    if (level > kMaxLevel) break;
  }
  if (!decimal || level > kMaxLevel) {
    const std::string shown = shown_token(token);
    message = decimal ? fmt::format("tag {} is above the largest node level {}", shown, kMaxLevel)
                      : fmt::format("tag '{}' is neither a decimal node level nor p or t", shown);
    return false;
  }
  tag = static_cast<Tag>(level);
  return true;
}

// General parser for one line (without its newline), any layout Dinero IV
// accepts.
bool parse_line(const char* p, const char* end, const ParseSettings& settings, Record& record,
                std::string& message, bool& ignored_fields) {
  p = skip_blanks(p, end);
  if (p == end) {
    message = "short line";
    return false;
  }
  unsigned char bad = 0;
  if (settings.form == RecordForm::Din) {
    const char* label_begin = p;
    std::uint64_t label = 0;
    switch (read_hex(p, end, label, bad)) {
      case HexStatus::BadDigit: message = bad_digit(bad, "label"); return false;
      case HexStatus::Empty: message = "no hex digits in label"; return false;
      case HexStatus::TooWide: label = ~std::uint64_t{0}; break;
      case HexStatus::Ok: break;
    }
    if (label >= static_cast<std::uint64_t>(kAccessTypeCount)) {
      message = fmt::format("label {} is not a Dinero IV access type (0-5)",
                            shown_token(std::string_view(label_begin, static_cast<std::size_t>(p - label_begin))));
      return false;
    }
    record.type = static_cast<AccessType>(label);
    record.size = 4;
  } else {
    const char* stop = token_end(p, end);
    const std::uint8_t type = stop - p == 1 ? kTypeLetter[static_cast<unsigned char>(*p)] : 0xFF;
    if (type == 0xFF) {
      message = fmt::format("unknown access type '{}'",
                            shown_token(std::string_view(p, static_cast<std::size_t>(stop - p))));
      return false;
    }
    record.type = static_cast<AccessType>(type);
    p = stop;
  }
  p = skip_blanks(p, end);
  if (p == end) {
    message = "short line";
    return false;
  }
  switch (read_hex(p, end, record.address, bad)) {
    case HexStatus::BadDigit: message = bad_digit(bad, "address"); return false;
    case HexStatus::Empty: message = "no hex digits in address"; return false;
    case HexStatus::TooWide: message = "address wider than 64 bits"; return false;
    case HexStatus::Ok: break;
  }
  if (settings.form == RecordForm::ExtendedDin) {
    p = skip_blanks(p, end);
    if (p == end) {
      message = "missing size";
      return false;
    }
    std::uint64_t size = 0;
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
      // DESIGN.md: Dinero IV keeps the low 16 bits of a size and simulates
      // another reference than the line says.
      message = fmt::format("size {:#x} is 0x10000 or more: Dinero IV truncates sizes to 16 bits", size);
      return false;
    }
    record.size = static_cast<std::uint32_t>(size);
  }
  record.tag = kTagNone;
  if (settings.tags_are_levels) return read_tag(p, end, record.tag, message);
  ignored_fields = skip_blanks(p, end) != end;
  return true;  // whatever follows is ignored, as Dinero IV ignores it
}

// Fast path: a run of lines that all have the layout of the first one, as our
// writers produce (`0 00001a38 07`, `r 00001a38 8 07`). D address digits; a
// one-digit size for extended din; a two-digit tag when kTagged. Stops at the
// first line of another layout and returns the bytes consumed.
template <int D, bool kExtended, bool kTagged>
std::size_t fast_lines(const char* begin, const char* end, bool tags_are_levels,
                       std::vector<Record>& out) {
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

using FastParser = std::size_t (*)(const char*, const char*, bool, std::vector<Record>&);

// Picks the fast parser for the layout of the line at `p`, or nullptr;
// `tagged` tells whether its lines carry a tag field.
FastParser choose_fast_parser(const char* p, const char* end, const ParseSettings& settings, bool& tagged) {
  const void* newline = std::memchr(p, '\n', static_cast<std::size_t>(std::min<std::ptrdiff_t>(end - p, 64)));
  if (!newline) return nullptr;
  const auto length = static_cast<const char*>(newline) - p + 1;
  const bool extended = settings.form == RecordForm::ExtendedDin;
  for (const int digits : {8, 16}) {
    const int untagged = digits + (extended ? 5 : 3);
    const int tagged_length = untagged + 3;
    if (length == untagged && !settings.tags_are_levels) {
      if (digits == 8) return extended ? &fast_lines<8, true, false> : &fast_lines<8, false, false>;
      return extended ? &fast_lines<16, true, false> : &fast_lines<16, false, false>;
    }
    if (length == tagged_length) {
      tagged = true;
      if (digits == 8) return extended ? &fast_lines<8, true, true> : &fast_lines<8, false, true>;
      return extended ? &fast_lines<16, true, true> : &fast_lines<16, false, true>;
    }
  }
  return nullptr;
}

bool parse_binary(std::string_view bytes, std::vector<Record>& out, RecordError& error) {
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
    out.push_back(Record{address, size, static_cast<AccessType>(type), kTagNone});
  }
  if (bytes.size() % 8 != 0) {
    error = {whole, fmt::format("truncated record: {} bytes of 8", bytes.size() % 8)};
    return false;
  }
  return true;
}

}  // namespace

bool parse_records(std::string_view bytes, const ParseSettings& settings, std::vector<Record>& out,
                   RecordError& error, std::uint64_t& ignored_fields) {
  if (settings.form == RecordForm::Binary) return parse_binary(bytes, out, error);
  const char* p = bytes.data();
  const char* const end = p + bytes.size();
  const std::size_t first = out.size();
  bool fast_tagged = false;
  FastParser fast = p < end ? choose_fast_parser(p, end, settings, fast_tagged) : nullptr;
  const bool fast_ignores_tags = fast_tagged && !settings.tags_are_levels;
  if (fast) {
    out.reserve(out.size() + bytes.size() / 11 + 1);
  }
  while (p < end) {
    if (fast) {
      const std::size_t before = out.size();
      p += fast(p, end, settings.tags_are_levels, out);
      if (fast_ignores_tags) ignored_fields += out.size() - before;
      if (p == end) break;
    }
    // One line the fast path did not take.
    const char* newline = static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(end - p)));
    const char* line_end = newline ? newline : end;
    Record record;
    bool ignored = false;
    if (!parse_line(p, line_end, settings, record, error.message, ignored)) {
      error.record_in_chunk = out.size() - first;
      return false;
    }
    ignored_fields += ignored;
    out.push_back(record);
    p = newline ? newline + 1 : end;
  }
  return true;
}

RecordForm detect_text_form(std::string_view first_bytes) {
  for (const char c : first_bytes) {
    if (is_blank(c)) continue;
    return kTypeLetter[static_cast<unsigned char>(c)] != 0xFF ? RecordForm::ExtendedDin : RecordForm::Din;
  }
  return RecordForm::Din;
}

namespace {

char* put_hex(char* out, std::uint64_t value, unsigned min_digits) {
  unsigned digits = min_digits;
  while (digits < 16 && (value >> (4 * digits)) != 0) ++digits;
  for (unsigned i = digits; i-- > 0;) {
    *out++ = kHexDigits[(value >> (4 * i)) & 0xF];
  }
  return out;
}

char* put_tag(char* out, Tag tag) {
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

// Eight lower-case hex digits of a 32-bit value as they appear in memory
// (most significant first), without a loop: spread the nibbles one per byte,
// put them in text order, then add '0' or 'a' - 10 to every byte at once.
std::uint64_t hex8(std::uint32_t value) {
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
constexpr auto kDecimalPairs = make_decimal_pairs();

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

enum class BinaryFit { Fits, AddressTooWide, SizeTooWide };

// Writes an 8-byte binary record when its fields fit (nothing otherwise).
BinaryFit put_binary_record(unsigned char* r, const Record& record) {
  if (record.address > 0xFFFFFFFFu) return BinaryFit::AddressTooWide;
  if (record.size > 0xFFFFu) return BinaryFit::SizeTooWide;
  for (int b = 0; b < 4; ++b) r[b] = static_cast<unsigned char>(record.address >> (8 * b));
  r[4] = static_cast<unsigned char>(record.size);
  r[5] = static_cast<unsigned char>(record.size >> 8);
  r[6] = static_cast<unsigned char>(record.type);
  r[7] = 0;
  return BinaryFit::Fits;
}

std::string binary_misfit(BinaryFit fit, const Record& record) {
  if (fit == BinaryFit::AddressTooWide) {
    return fmt::format("address {:#x} does not fit the 32 bits of a binary record", record.address);
  }
  return fmt::format("size {} does not fit the 16 bits of a binary record", record.size);
}

// The general text line (any address, size and tag).
char* put_text_line(char* p, const Record& record, bool extended, const TextLayout& layout) {
  const auto type = static_cast<unsigned>(record.type);
  *p++ = extended ? kTypeLetters[type] : static_cast<char>('0' + type);
  *p++ = ' ';
  p = put_hex(p, record.address, layout.address_digits);
  if (extended) {
    *p++ = ' ';
    p = put_hex(p, record.size, 1);
  }
  if (layout.tags) p = put_tag(p, record.tag);
  *p++ = '\n';
  return p;
}

}  // namespace

void format_records(std::span<const Record> records, RecordForm form, unsigned address_digits,
                    std::uint64_t first_record, ByteBuffer& out) {
  if (form == RecordForm::Binary) {
    const std::size_t start = out.size();
    out.resize(start + records.size() * 8);
    auto* bytes = reinterpret_cast<unsigned char*>(out.data() + start);
    for (std::size_t i = 0; i < records.size(); ++i) {
      const BinaryFit fit = put_binary_record(bytes + i * 8, records[i]);
      if (fit != BinaryFit::Fits) {
        throw FormatError(fmt::format("record {}: {}", first_record + i + 1, binary_misfit(fit, records[i])));
      }
    }
    return;
  }
  const bool extended = form == RecordForm::ExtendedDin;
  const std::size_t start = out.size();
  out.reserve(start + records.size() * kMaxTextLine);
  char* p = out.data() + start;
  const TextLayout layout{address_digits, true};
  auto put_line = [&](const Record& record) { p = put_text_line(p, record, extended, layout); };
  if (address_digits != 8) {
    for (const Record& record : records) put_line(record);
  } else if (extended) {
    for (const Record& record : records) {
      if (!put_common_line<true>(p, record)) put_line(record);
    }
  } else {
    for (const Record& record : records) {
      if (!put_common_line<false>(p, record)) put_line(record);
    }
  }
  out.resize(static_cast<std::size_t>(p - out.data()));
}

}  // namespace nodetrace::formats::detail

namespace nodetrace::formats {

std::size_t format_record(const Record& record, RecordForm form, const TextLayout& layout, char* out) {
  if (form == RecordForm::Binary) {
    const detail::BinaryFit fit = detail::put_binary_record(reinterpret_cast<unsigned char*>(out), record);
    if (fit != detail::BinaryFit::Fits) throw FormatError(detail::binary_misfit(fit, record));
    return 8;
  }
  return static_cast<std::size_t>(detail::put_text_line(out, record, form == RecordForm::ExtendedDin, layout) - out);
}

}  // namespace nodetrace::formats
