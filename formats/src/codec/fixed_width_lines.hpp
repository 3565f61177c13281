// The fixed-width lines our writers produce (internal; FORMAT.md 1.1:
// `0 00001a38 07`, `r 00001a38 8 07`): a parser for runs of such lines and a
// writer of the common one, both without per-field loops. They are the fast
// paths of the din and extended din codecs; the general code of
// text_fields.hpp handles every other line and must agree with them
// (tests/formats/test_fixed_width_lines.cpp).
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstring>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include "nodetrace/formats/record/record_summary.hpp"
#include "codec/text_fields.hpp"

namespace nodetrace::formats::detail {

// Eight hex digits (most significant first) as a value, all at once (SWAR
// on a 64-bit word): false when a byte is not a hex digit. Little-endian
// hosts only (the caller falls back to the table otherwise).
inline bool parse_hex8(const char* p, std::uint32_t& value) {
  constexpr std::uint64_t kOnes = 0x0101010101010101ull;
  constexpr std::uint64_t kHigh = kOnes * 0x80;
  std::uint64_t x;
  std::memcpy(&x, p, 8);
  // With every byte below 0x80, adding (0x80 - lo) sets a byte's top bit iff
  // it is >= lo, adding (0x7f - hi) iff it is > hi, and nothing carries.
  const std::uint64_t lower = x | (kOnes * 0x20);  // 'A'-'F' -> 'a'-'f'
  const std::uint64_t digit = (x + kOnes * (0x80 - '0')) & ~(x + kOnes * (0x7f - '9'));
  const std::uint64_t letter = (lower + kOnes * (0x80 - 'a')) & ~(lower + kOnes * (0x7f - 'f'));
  if ((x & kHigh) != 0 || ((digit | letter) & kHigh) != kHigh) return false;
  // Digit values: the low nibble, plus 9 for letters (bit 6 set).
  std::uint64_t v = (x & (kOnes * 0x0F)) + ((x >> 6) & kOnes) * 9;
  v = __builtin_bswap64(v);  // byte i = the digit of weight 16^i
  v = (v | (v >> 4)) & 0x00FF00FF00FF00FFull;
  v = (v | (v >> 8)) & 0x0000FFFF0000FFFFull;
  v = (v | (v >> 16)) & 0x00000000FFFFFFFFull;
  value = static_cast<std::uint32_t>(v);
  return true;
}

// The vector units a fast path may use: the best the processor has, or a
// lesser one (tests run every one the processor has).
enum class VectorUnits { Scalar, Avx2, Avx512 };

inline VectorUnits best_vector_units() {
#if defined(__x86_64__)
  static const VectorUnits best = __builtin_cpu_supports("avx512vbmi") && __builtin_cpu_supports("avx512bw")
                                      ? VectorUnits::Avx512
                                  : __builtin_cpu_supports("avx2") ? VectorUnits::Avx2
                                                                   : VectorUnits::Scalar;
  return best;
#else
  return VectorUnits::Scalar;
#endif
}

// The commonest layout, `0 00001a38 07\n`: 14 bytes a line.
inline constexpr std::size_t kDin8TaggedLine = 14;

#if defined(__x86_64__)
// Several lines of the commonest layout at once, one per 128-bit lane:
// every byte checked by compares, the digits turned into the address, level
// and type by multiply-adds, and each lane shuffled into a Record written
// straight to `out` (room for `room` records). Both stop before the first
// group with a line they do not take (the caller reads that line) and
// return the bytes taken.
static_assert(sizeof(Record) == 16 && offsetof(Record, size) == 8 && offsetof(Record, type) == 12 &&
              offsetof(Record, tag) == 14);
// Per lane: digit values in place for the multiply-adds (address digits
// 0-7, tag tens and ones, type), their weights, and the bytes of a Record
// from the words packed from the sums (high address half, low half, level,
// type).
inline constexpr char kLaneZero = static_cast<char>(0x80);
inline constexpr char kGatherDigits[16] = {2, 3, 4, 5, 6, 7, 8, 9, 11, 12, kLaneZero, kLaneZero, 0, kLaneZero,
                                           kLaneZero, kLaneZero};
inline constexpr char kPairWeights[16] = {16, 1, 16, 1, 16, 1, 16, 1, 10, 1, 0, 0, 1, 0, 0, 0};
inline constexpr char kRecordBytes[16] = {2, 3, 0, 1, kLaneZero, kLaneZero, kLaneZero, kLaneZero, kLaneZero,
                                          kLaneZero, kLaneZero, kLaneZero, 6, kLaneZero, 4, 5};
// Word weights per dword: (256, 1) for the address halves, (1, 0) for level and type.
inline constexpr std::int32_t kQuadWeights[4] = {0x00010100, 0x00010100, 1, 1};

// 16 bytes repeated in both lanes.
__attribute__((target("avx2"))) inline __m256i both_lanes(const char* bytes) {
  return _mm256_broadcastsi128_si256(_mm_loadu_si128(reinterpret_cast<const __m128i*>(bytes)));
}

// Two lines at a time; needs 30 bytes from a pair's start.
__attribute__((target("avx2"))) inline std::size_t din8_tagged_pairs_avx2(const char* begin, const char* end,
                                                                          bool tags_are_levels, Record* out,
                                                                          std::size_t room) {
  constexpr char F = static_cast<char>(0xFF);
  static constexpr char kSeparators[16] = {0, ' ', 0, 0, 0, 0, 0, 0, 0, 0, ' ', 0, 0, '\n', 0, 0};
  static constexpr char kSeparatorAt[16] = {0, F, 0, 0, 0, 0, 0, 0, 0, 0, F, 0, 0, F, 0, 0};
  static constexpr char kHexAt[16] = {0, 0, F, F, F, F, F, F, F, F, 0, 0, 0, 0, 0, 0};
  static constexpr char kDigitAt[16] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, F, F, 0, 0, 0};
  static constexpr char kTypeAt[16] = {F, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  const char no_tag = tags_are_levels ? 0 : F;
  const char fixed[16] = {0, 0, 0, 0, 0, 0, 0, 0, 4, 0, 0, 0, 0, 0, no_tag, no_tag};
  const __m256i separators = both_lanes(kSeparators), separator_at = both_lanes(kSeparatorAt);
  const __m256i hex_at = both_lanes(kHexAt), digit_at = both_lanes(kDigitAt), type_at = both_lanes(kTypeAt);
  const __m256i gather = both_lanes(kGatherDigits), pair_weights = both_lanes(kPairWeights);
  const __m256i record = both_lanes(kRecordBytes), fixed_fields = both_lanes(fixed);
  const __m256i quad_weights = both_lanes(reinterpret_cast<const char*>(kQuadWeights));
  const char* p = begin;
  Record* const out_end = out + room - room % 2;
  for (; end - p >= 30 && out != out_end; out += 2) {
    const __m256i c = _mm256_loadu2_m128i(reinterpret_cast<const __m128i*>(p + 14), reinterpret_cast<const __m128i*>(p));
    const __m256i digit = _mm256_and_si256(_mm256_cmpgt_epi8(c, _mm256_set1_epi8('0' - 1)),
                                           _mm256_cmpgt_epi8(_mm256_set1_epi8('9' + 1), c));
    const __m256i lower = _mm256_or_si256(c, _mm256_set1_epi8(0x20));
    const __m256i letter = _mm256_and_si256(_mm256_cmpgt_epi8(lower, _mm256_set1_epi8('a' - 1)),
                                            _mm256_cmpgt_epi8(_mm256_set1_epi8('f' + 1), lower));
    const __m256i type_ok = _mm256_and_si256(digit, _mm256_cmpgt_epi8(_mm256_set1_epi8('6'), c));
    __m256i ok = _mm256_and_si256(_mm256_cmpeq_epi8(c, separators), separator_at);
    ok = _mm256_or_si256(ok, _mm256_and_si256(_mm256_or_si256(digit, letter), hex_at));
    ok = _mm256_or_si256(ok, _mm256_and_si256(digit, digit_at));
    ok = _mm256_or_si256(ok, _mm256_and_si256(type_ok, type_at));
    if ((static_cast<unsigned>(_mm256_movemask_epi8(ok)) & 0x3FFF3FFFu) != 0x3FFF3FFFu) break;
    const __m256i letters = _mm256_and_si256(_mm256_srli_epi16(c, 6), _mm256_set1_epi8(1));
    const __m256i value = _mm256_add_epi8(_mm256_and_si256(c, _mm256_set1_epi8(0x0F)),
                                          _mm256_add_epi8(_mm256_slli_epi16(letters, 3), letters));
    const __m256i pairs = _mm256_maddubs_epi16(_mm256_shuffle_epi8(value, gather), pair_weights);
    const __m256i quads = _mm256_madd_epi16(pairs, quad_weights);
    const __m256i records = _mm256_or_si256(_mm256_shuffle_epi8(_mm256_packus_epi32(quads, quads), record), fixed_fields);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out), records);
    p += 2 * kDin8TaggedLine;
  }
  return static_cast<std::size_t>(p - begin);
}

// 16 bytes repeated in all four lanes. (The masked forms of the AVX-512
// intrinsics here: GCC 12's unmasked ones warn of an uninitialised value.)
__attribute__((target("avx512f,avx512bw"))) inline __m512i all_lanes(const char* bytes) {
  return _mm512_maskz_broadcast_i32x4(0xFFFF, _mm_loadu_si128(reinterpret_cast<const __m128i*>(bytes)));
}

// Four lines at a time (AVX-512 with VBMI): one 64-byte load spread into
// the lanes, each byte checked against its position's range (the hex
// letters apart); needs 64 bytes from a group's start.
__attribute__((target("avx512f,avx512bw,avx512vbmi"))) inline std::size_t din8_tagged_quads_avx512(
    const char* begin, const char* end, bool tags_are_levels, Record* out, std::size_t room) {
  // Lane k, byte j: the line's byte j (bytes 14 and 15 repeat the newline).
  alignas(64) static constexpr auto kSpread = [] {
    std::array<char, 64> spread{};
    for (int k = 0; k < 4; ++k) {
      for (int j = 0; j < 16; ++j) spread[16 * k + j] = static_cast<char>(14 * k + std::min(j, 13));
    }
    return spread;
  }();
  // Accepted bytes per position: lowest value and the span above it
  // (type 0-5, blanks, hex digits 0-9, level digits, newline).
  static constexpr char kLowest[16] = {'0', ' ', '0', '0', '0', '0', '0', '0', '0', '0', ' ', '0', '0', '\n', 0, 0};
  static constexpr char kSpan[16] = {5, 0, 9, 9, 9, 9, 9, 9, 9, 9, 0, 9, 9, 0, static_cast<char>(0xFF),
                                     static_cast<char>(0xFF)};
  constexpr __mmask64 kHexAt = 0x03FC03FC03FC03FCull;  // bytes 2-9 of each lane: a-f and A-F too
  const char no_tag = tags_are_levels ? 0 : static_cast<char>(0xFF);
  const char fixed[16] = {0, 0, 0, 0, 0, 0, 0, 0, 4, 0, 0, 0, 0, 0, no_tag, no_tag};
  const __m512i spread = _mm512_load_si512(kSpread.data());
  const __m512i lowest = all_lanes(kLowest), span = all_lanes(kSpan);
  const __m512i gather = all_lanes(kGatherDigits), pair_weights = all_lanes(kPairWeights);
  const __m512i record = all_lanes(kRecordBytes), fixed_fields = all_lanes(fixed);
  const __m512i quad_weights = all_lanes(reinterpret_cast<const char*>(kQuadWeights));
  const __m512i case_bit = _mm512_set1_epi8(0x20), letter_a = _mm512_set1_epi8('a');
  const __m512i letter_span = _mm512_set1_epi8(5), low_nibble = _mm512_set1_epi8(0x0F);
  const __m512i nine = _mm512_set1_epi8(9);
  const char* p = begin;
  Record* const out_end = out + room - room % 4;
  for (; end - p >= 64 && out != out_end; out += 4) {
    const __m512i c = _mm512_maskz_permutexvar_epi8(~__mmask64{0}, spread, _mm512_loadu_si512(p));
    const __mmask64 in_range = _mm512_cmple_epu8_mask(_mm512_sub_epi8(c, lowest), span);
    const __mmask64 letter =
        _mm512_mask_cmple_epu8_mask(kHexAt, _mm512_sub_epi8(_mm512_or_si512(c, case_bit), letter_a), letter_span);
    if ((in_range | letter) != ~__mmask64{0}) break;
    __m512i value = _mm512_and_si512(c, low_nibble);
    value = _mm512_mask_add_epi8(value, letter, value, nine);
    const __m512i pairs = _mm512_maddubs_epi16(_mm512_shuffle_epi8(value, gather), pair_weights);
    const __m512i quads = _mm512_madd_epi16(pairs, quad_weights);
    const __m512i records = _mm512_or_si512(_mm512_shuffle_epi8(_mm512_packus_epi32(quads, quads), record), fixed_fields);
    _mm512_storeu_si512(out, records);
    p += 4 * kDin8TaggedLine;
  }
  return static_cast<std::size_t>(p - begin);
}
#endif

// One line of the commonest layout, without a loop per field; needs two
// bytes past the line (it reads 16). False when the line is of another
// layout. Little-endian hosts.
inline bool din8_tagged_line(const char* p, bool tags_are_levels, Record& record) {
  constexpr std::uint64_t kOnes = 0x0101010101010101ull;
  std::uint64_t a, b;
  std::memcpy(&a, p, 8);      // type, ' ', digits 1-6
  std::memcpy(&b, p + 8, 8);  // digits 7-8, ' ', tag, '\n', next line
  // Separators: bytes 1 (' '), 10 (' ') and 13 ('\n').
  if (((a >> 8) & 0xFF) != ' ' || ((b >> 16) & 0xFF) != ' ' || ((b >> 40) & 0xFF) != '\n') return false;
  // Type and the two tag digits as values 0-9 (type 0-5).
  const std::uint64_t type = (a & 0xFF) ^ '0';
  const std::uint64_t tag = ((b >> 24) & 0xFFFF) ^ 0x3030;
  if (type > 5 || (tag & 0xF0F0) != 0 || ((tag + 0x0606) & 0x1010) != 0) return false;
  const std::uint64_t x = (a >> 16) | (b << 48);
  const std::uint64_t lower = x | (kOnes * 0x20);
  const std::uint64_t digit = (x + kOnes * (0x80 - '0')) & ~(x + kOnes * (0x7f - '9'));
  const std::uint64_t letter = (lower + kOnes * (0x80 - 'a')) & ~(lower + kOnes * (0x7f - 'f'));
  if (((x & (kOnes * 0x80)) | (~(digit | letter) & (kOnes * 0x80))) != 0) return false;
  std::uint64_t v = (x & (kOnes * 0x0F)) + ((x >> 6) & kOnes) * 9;
  v = __builtin_bswap64(v);
  v = (v | (v >> 4)) & 0x00FF00FF00FF00FFull;
  v = (v | (v >> 8)) & 0x0000FFFF0000FFFFull;
  v = (v | (v >> 16)) & 0x00000000FFFFFFFFull;
  const Tag level = static_cast<Tag>((tag & 0xFF) * 10 + (tag >> 8));
  record = Record{v, 4, static_cast<AccessType>(type), TraversalUnit{}, tags_are_levels ? level : kTagNone};
  return true;
}

// fast_lines for the commonest layout, `0 00001a38 07\n` (din, 8 address
// digits, a level), with `units` (by default the best the processor has):
// lines in groups while a group's bytes are there, then one at a time.
// Records are written a block at a time into a buffer that stays in the
// processor's cache and appended to `out` in one copy (a push_back per
// record, or making room in `out` first, cost more than parsing). The last
// line is left to the caller. Little-endian hosts.
inline std::size_t din8_tagged_lines(const char* begin, const char* end, bool tags_are_levels,
                                     std::vector<Record>& out, VectorUnits units = best_vector_units()) {
  constexpr std::size_t kBlock = 256;  // records
  Record block[kBlock];
  const char* p = begin;
  for (;;) {
    const std::size_t lines = static_cast<std::size_t>(end - p) / kDin8TaggedLine;
    if (lines < 2) break;
    const std::size_t room = std::min(lines, kBlock);
    std::size_t taken = 0;  // records
#if defined(__x86_64__)
    if (units == VectorUnits::Avx512) {
      taken = din8_tagged_quads_avx512(p, end, tags_are_levels, block, room) / kDin8TaggedLine;
    } else if (units == VectorUnits::Avx2) {
      taken = din8_tagged_pairs_avx2(p, end, tags_are_levels, block, room) / kDin8TaggedLine;
    }
#else
    (void)units;
#endif
    // The rest of the block (where a group stopped, or what a group needs
    // more bytes for) a line at a time.
    while (taken < room && end - (p + taken * kDin8TaggedLine) >= 16 &&
           din8_tagged_line(p + taken * kDin8TaggedLine, tags_are_levels, block[taken])) {
      ++taken;
    }
    out.insert(out.end(), block, block + taken);
    p += taken * kDin8TaggedLine;
    if (taken < room) break;
  }
  return static_cast<std::size_t>(p - begin);
}

// A run of lines that all have the layout of the first one: D address digits;
// a one-digit size for extended din; a two-digit tag when kTagged, followed
// by a unit of kUnitDigits digits when that is not 0 (read when `units` is
// above 1, else skipped as Dinero IV skips it). Stops at the first line of
// another layout (or a unit not below `units`) and returns the bytes
// consumed.
template <int D, bool kExtended, bool kTagged, int kUnitDigits = 0>
std::size_t fast_lines(const char* begin, const char* end, bool tags_are_levels, unsigned units,
                       std::vector<Record>& out) {
  static_assert(kTagged || kUnitDigits == 0);
  constexpr int kAddress = 2;
  constexpr int kAfterAddress = kAddress + D;
  constexpr int kSize = kAfterAddress + 1;
  constexpr int kTagPos = (kExtended ? kSize + 1 : kAfterAddress) + 1;
  constexpr int kUnitPos = kTagPos + 3;
  constexpr int kLength = (kTagged ? kTagPos + 2 + (kUnitDigits ? 1 + kUnitDigits : 0) : kTagPos - 1) + 1;
  const bool read_units = kUnitDigits != 0 && tags_are_levels && units > 1;
  const char* p = begin;
  out.reserve(out.size() + static_cast<std::size_t>(end - begin) / kLength);
  if constexpr (std::endian::native == std::endian::little && D == 8 && !kExtended && kTagged && kUnitDigits == 0) {
    p += din8_tagged_lines(p, end, tags_are_levels, out);
  }
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
    if constexpr (std::endian::native == std::endian::little && D % 8 == 0) {
      for (int i = 0; i < D; i += 8) {
        std::uint32_t digits = 0;
        if (!parse_hex8(p + kAddress + i, digits)) bad = 0xFF;
        address = (address << 32) | digits;
      }
    } else {
      for (int i = 0; i < D; ++i) {
        const std::uint8_t digit = kHex[static_cast<unsigned char>(p[kAddress + i])];
        bad |= digit;
        address = (address << 4) | digit;
      }
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
    unsigned unit = 0;
    if constexpr (kUnitDigits != 0) {
      if (p[kUnitPos - 1] != ' ') break;
      bool digits = true;
      for (int i = 0; i < kUnitDigits; ++i) {
        const unsigned digit = static_cast<unsigned char>(p[kUnitPos + i]) - '0';
        digits = digits && digit <= 9;
        unit = unit * 10 + digit;
      }
      if (!digits) break;
      if (!read_units) {
        unit = 0;
      } else if (unit >= units) {
        break;  // the general parser names the record
      }
    }
    if (bad & 0xF0) break;
    out.push_back(Record{address, size, static_cast<AccessType>(type), traversal_unit(unit), tag});
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
    const bool wide = digits == 16;
    if (length == untagged && !settings.tags_are_levels) {
      return wide ? &fast_lines<16, kExtended, false> : &fast_lines<8, kExtended, false>;
    }
    // Lines without a unit in a trace whose records carry units go to the
    // general parser, which says the unit is missing.
    if (length == tagged_length && !settings.reads_units()) {
      tagged = true;
      return wide ? &fast_lines<16, kExtended, true> : &fast_lines<8, kExtended, true>;
    }
    if (length > tagged_length + 1 && length <= tagged_length + 4) {
      tagged = true;
      switch (length - tagged_length - 1) {
        case 1: return wide ? &fast_lines<16, kExtended, true, 1> : &fast_lines<8, kExtended, true, 1>;
        case 2: return wide ? &fast_lines<16, kExtended, true, 2> : &fast_lines<8, kExtended, true, 2>;
        default: return wide ? &fast_lines<16, kExtended, true, 3> : &fast_lines<8, kExtended, true, 3>;
      }
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
bool put_common_line(char*& out, const Record& record, unsigned unit_digits) {
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
  p += 3;
  if (unit_digits != 0) p = put_unit(p, record.unit, unit_digits);
  *p = '\n';
  out = p + 1;
  return true;
}

#if defined(__x86_64__)
// Four common din lines (`0 00001a38 07\n`, no unit) from four records, one
// per 128-bit lane (AVX-512 with VBMI): the address's nibbles spread one per
// byte and turned into hex digits, the level into two decimal digits, then
// one permutation lays the four lines out with their blanks and newlines.
// Writes 64 bytes at `out` (56 of them the lines); false, writing nothing,
// when a record needs another line (a wider address, a level of 100 or more,
// a `p`, `t` or no tag).
__attribute__((target("avx512f,avx512bw,avx512vbmi"))) inline bool put_common_din_quad(char* out,
                                                                                      const Record* records) {
  alignas(64) static constexpr auto kPermutations = [] {
    std::array<std::array<char, 64>, 2> table{};
    for (int lane = 0; lane < 4; ++lane) {
      for (int j = 0; j < 16; ++j) {
        // Nibble source: byte j < 8 of a lane takes the address byte holding digit j.
        table[0][16 * lane + j] = static_cast<char>(16 * lane + (j < 8 ? 3 - j / 2 : j));
      }
    }
    // The lines: type (lane byte 12), blank, 8 digits (bytes 0-7), blank,
    // level tens and ones (bytes 14, 15), newline; 64 and 65 index the
    // constant blank and newline.
    for (int line = 0; line < 4; ++line) {
      const int lane = 16 * line;
      const int layout[14] = {lane + 12, 64, lane, lane + 1, lane + 2, lane + 3, lane + 4, lane + 5,
                              lane + 6,  lane + 7, 64, lane + 14, lane + 15, 65};
      for (int pos = 0; pos < 14; ++pos) table[1][14 * line + pos] = static_cast<char>(layout[pos]);
    }
    for (int pos = 56; pos < 64; ++pos) table[1][pos] = 65;
    return table;
  }();
  const __m512i record = _mm512_loadu_si512(records);
  // Bytes 4-7 (the address's high half) zero, and the level (word 7) below 100.
  constexpr __mmask64 kHighAddress = 0x00F000F000F000F0ull;
  constexpr __mmask32 kLevelWords = 0x80808080u;
  if (_mm512_mask_test_epi8_mask(kHighAddress, record, record) != 0 ||
      _mm512_mask_cmpge_epu16_mask(kLevelWords, record, _mm512_set1_epi16(100)) != 0) {
    return false;
  }
  const __m512i spread =  // the masked form: the plain one reads an undefined vector (GCC warns)
      _mm512_maskz_permutexvar_epi8(~__mmask64{0}, _mm512_load_si512(kPermutations[0].data()), record);
  const __m512i low_nibble = _mm512_set1_epi8(0x0F);
  const __m512i high = _mm512_and_si512(_mm512_srli_epi16(spread, 4), low_nibble);
  constexpr __mmask64 kOddBytes = 0xAAAAAAAAAAAAAAAAull;
  const __m512i nibbles = _mm512_mask_blend_epi8(kOddBytes, high, _mm512_and_si512(spread, low_nibble));
  __m512i text = _mm512_add_epi8(nibbles, _mm512_set1_epi8('0'));
  text = _mm512_mask_add_epi8(text, _mm512_cmpgt_epu8_mask(nibbles, _mm512_set1_epi8(9)), text,
                              _mm512_set1_epi8('a' - '0' - 10));
  // The level's tens (tag * 205 >> 11 is tag / 10 below 1024) in byte 14, ones in 15.
  const __m512i tens = _mm512_srli_epi16(_mm512_mullo_epi16(record, _mm512_set1_epi16(205)), 11);
  const __m512i ones = _mm512_sub_epi16(record, _mm512_mullo_epi16(tens, _mm512_set1_epi16(10)));
  const __m512i level = _mm512_add_epi8(_mm512_or_si512(tens, _mm512_slli_epi16(ones, 8)), _mm512_set1_epi8('0'));
  const __m512i type = _mm512_add_epi8(record, _mm512_set1_epi8('0'));
  constexpr __mmask64 kLevelBytes = 0xC000C000C000C000ull;
  text = _mm512_mask_blend_epi8(kLevelBytes, _mm512_mask_blend_epi8(0x1000100010001000ull, text, type), level);
  const __m512i separators = _mm512_maskz_set1_epi8(1, ' ');
  const __m512i constants = _mm512_mask_set1_epi8(separators, 2, '\n');
  _mm512_storeu_si512(out, _mm512_permutex2var_epi8(text, _mm512_load_si512(kPermutations[1].data()), constants));
  return true;
}
#endif

// format_records for din (kExtended false) and extended din: the common line
// where it applies (8 address digits), the general line elsewhere; din lines
// without units four at a time with `units` AVX-512. Counts each record in
// `summary` in the same pass: a second pass over the records cost the writer
// about a third of what formatting them does.
template <bool kExtended>
void format_text_records(std::span<const Record> records, unsigned address_digits, unsigned unit_digits,
                         ByteBuffer& out, RecordSummary& summary, VectorUnits units = best_vector_units()) {
  const std::size_t start = out.size();
  // A quad writes 64 bytes: room for a line of kMaxTextLine (more than 16) per record covers it.
  static_assert(kMaxTextLine >= 16);
  out.reserve(start + records.size() * kMaxTextLine);
  char* p = out.data() + start;
  const TextLayout layout{address_digits, true, unit_digits};
  if (address_digits != 8) {
    for (const Record& record : records) {
      summary.add(record);
      p = put_text_line(p, record, kExtended, layout);
    }
  } else {
    std::size_t i = 0;
#if defined(__x86_64__)
    if (!kExtended && unit_digits == 0 && units == VectorUnits::Avx512) {
      for (; i + 4 <= records.size(); i += 4) {
        if (put_common_din_quad(p, records.data() + i)) {
          for (std::size_t k = i; k < i + 4; ++k) summary.add(records[k]);
          p += 4 * kDin8TaggedLine;
          continue;
        }
        for (std::size_t k = i; k < i + 4; ++k) {
          summary.add(records[k]);
          if (!put_common_line<kExtended>(p, records[k], unit_digits)) p = put_text_line(p, records[k], kExtended, layout);
        }
      }
    }
#else
    (void)units;
#endif
    for (; i < records.size(); ++i) {
      summary.add(records[i]);
      if (!put_common_line<kExtended>(p, records[i], unit_digits)) p = put_text_line(p, records[i], kExtended, layout);
    }
  }
  out.resize(static_cast<std::size_t>(p - out.data()));
}

}  // namespace nodetrace::formats::detail
