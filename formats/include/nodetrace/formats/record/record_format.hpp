// Formatting one record in a record form (FORMAT.md section 1): a din or
// extended din text line, or an 8-byte Dinero binary record. The trace writer
// formats whole data frames with the same code (and a faster path for the
// common line), so a record formatted here has the bytes the writer gives it.
#pragma once

#include <cstddef>

#include "nodetrace/formats/record/record.hpp"

namespace nodetrace::formats {

// How text fields are laid out.
struct TextLayout {
  // The address has at least this many hex digits, zero-padded (one that
  // needs more gets more): 8 or 16 in our traces, 1 for no padding.
  unsigned address_digits = 8;
  // Write the tag field (a record with kTagNone has none either way).
  bool tags = true;
  // 0: no unit field. Else each tagged record's traversal unit follows its
  // tag, zero-padded to this many decimal digits (those of the trace's
  // largest unit, so every line has the same length): `0 00001a38 07 3`.
  unsigned unit_digits = 0;
};

// The digits of the largest unit of a trace of `units` units (1 to 3); 0 for
// one unit, whose records carry no unit field.
constexpr unsigned unit_digits_for(unsigned units) {
  return units <= 1 ? 0 : units <= 10 ? 1 : units <= 100 ? 2 : 3;
}

// Our traces' lines: `0 00001a38 07`, `r 00001a38 8 07`.
inline constexpr TextLayout kTraceTextLayout{8, true};
// The text Dinero IV is fed: no padding, no tag (`0 1a38`, `r 1a38 8`).
inline constexpr TextLayout kDineroTextLayout{1, false};

// The most bytes format_record writes: a text line with 16 address digits, 8
// size digits, 5 tag digits, 3 unit digits, the blanks and the newline
// (binary: 8).
inline constexpr std::size_t kMaxFormattedRecord = 1 + 1 + 16 + 1 + 8 + 1 + 5 + 1 + 3 + 1;

// Writes `record` in `form` at `out` (room for kMaxFormattedRecord bytes) and
// returns the bytes written; text ends with its newline. The layout applies
// to text only. Throws base::FormatError when a binary record cannot hold the
// address (32 bits) or the size (16 bits).
std::size_t format_record(const Record& record, RecordForm form, const TextLayout& layout, char* out);

}  // namespace nodetrace::formats
