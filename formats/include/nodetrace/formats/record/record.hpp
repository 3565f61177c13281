// The record model: one memory reference of a trace.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>

namespace nodetrace::formats {

// Dinero IV's access types, numbered as din labels.
enum class AccessType : std::uint8_t {
  Read = 0,
  Write = 1,
  InstructionFetch = 2,
  Misc = 3,
  CopyBack = 4,
  Invalidate = 5,
};
inline constexpr int kAccessTypeCount = 6;

// A record's tag. Node levels are 0..kMaxLevel; the other values mark the
// optional streams (`p`, `t`) or the absence of a tag.
using Tag = std::uint16_t;
inline constexpr Tag kMaxLevel = 0xFFF0;
inline constexpr Tag kTagPrimitiveList = 0xFFFD;  // written as `p`
inline constexpr Tag kTagTriangle = 0xFFFE;       // written as `t`
inline constexpr Tag kTagNone = 0xFFFF;           // untagged record

constexpr bool is_level(Tag tag) { return tag <= kMaxLevel; }

// The traversal unit that issued a record (DESIGN.md "Trace records": a trace
// of several units writes it as a decimal field after the tag). An enum, so
// that a brace initialiser written before the field existed, `{address,
// size, type, tag}`, does not compile rather than put the tag in it.
enum class TraversalUnit : std::uint8_t {};
inline constexpr unsigned kMaxUnits = 256;  // units 0..255
constexpr unsigned unit_index(TraversalUnit unit) { return static_cast<unsigned>(unit); }
constexpr TraversalUnit traversal_unit(unsigned index) { return static_cast<TraversalUnit>(index); }

struct Record {
  std::uint64_t address = 0;
  // Bytes referenced. Din has no size field: din records carry 4, the size
  // Dinero IV gives them (see dinero_view).
  std::uint32_t size = 4;
  AccessType type = AccessType::Read;
  // Unit 0 unless the trace says its records carry units (in the padding
  // byte before the tag: a Record stays 16 bytes).
  TraversalUnit unit{};
  Tag tag = kTagNone;

  friend bool operator==(const Record&, const Record&) = default;
};

// What every record of a run is, found in one pass: one of Dinero IV's
// demand fetches (types 0-3: read, write, instruction fetch, misc), and
// tagged with a node level.
struct RecordKinds {
  bool demand_fetches = false;
  bool levels = false;
};

inline RecordKinds record_kinds(const Record* records, std::size_t count) {
  // Without a branch per record: a type above 3 sets a bit above the two
  // low ones, a tag above kMaxLevel carries into bit 16 when 15 is added.
  static_assert(static_cast<unsigned>(AccessType::Misc) == 3 && kMaxLevel == 0xFFFF - 15);
  std::uint64_t types = 0;
  std::uint64_t tags = 0;
  if constexpr (std::endian::native == std::endian::little && sizeof(Record) == 16 &&
                offsetof(Record, type) == 12 && offsetof(Record, tag) == 14) {
    // The second word of each record (size, type, unit, tag) on its own:
    // the compiler vectorises this without taking the records apart.
    for (std::size_t i = 0; i < count; ++i) {
      std::uint64_t word;
      std::memcpy(&word, reinterpret_cast<const char*>(records + i) + 8, 8);
      types |= word;
      tags |= (word >> 48) + 15;
    }
    types >>= 32;
  } else {
    for (std::size_t i = 0; i < count; ++i) {
      types |= static_cast<unsigned>(records[i].type);
      tags |= records[i].tag + 15u;
    }
  }
  return {(types & 0xFC) == 0, (tags & 0x10000) == 0};
}

// The three record forms of docs/ARCHITECTURE.md "Trace records".
enum class RecordForm : std::uint8_t {
  Din,          // `LABEL HEXADDR TAG`          (dineroIV -informat d)
  ExtendedDin,  // `TYPE HEXADDR HEXSIZE TAG`   (dineroIV -informat D)
  Binary,       // 8 bytes: u32 address, u16 size, u8 type, pad (-informat b)
};

// Names used on command lines and in container headers: din, xdin, binary.
std::string_view form_name(RecordForm form);
std::optional<RecordForm> parse_form_name(std::string_view name);

// The form a file name gives, the one rule of every program that writes or
// reads by name: .din / .din.zst din, .xdin / .xdin.zst extended din,
// .bin / .bin.zst binary; nullopt for any other name (and "-").
std::optional<RecordForm> form_of_file_name(std::string_view path);

// The Dinero IV -informat letter: d, D, b.
char dinero_informat(RecordForm form);

// The reference as Dinero IV simulates a record read in `form`: din rounds the
// address down to a multiple of 4 and uses size 4; the others keep both.
constexpr Record dinero_view(Record record, RecordForm form) {
  if (form == RecordForm::Din) {
    record.address &= ~std::uint64_t{3};
    record.size = 4;
  }
  return record;
}

// Tag text as written in records: decimal level (2 digits minimum), `p`, `t`,
// or empty for kTagNone.
std::string tag_text(Tag tag);

}  // namespace nodetrace::formats
