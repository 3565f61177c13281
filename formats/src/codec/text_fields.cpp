#include "codec/text_fields.hpp"

#include <fmt/format.h>

#include <cstring>

namespace nodetrace::formats::detail {

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

bool read_address(const char*& p, const char* end, std::uint64_t& address, std::string& message) {
  p = skip_blanks(p, end);
  if (p == end) {
    message = "short line";
    return false;
  }
  unsigned char bad = 0;
  switch (read_hex(p, end, address, bad)) {
    case HexStatus::BadDigit: message = bad_digit(bad, "address"); return false;
    case HexStatus::Empty: message = "no hex digits in address"; return false;
    case HexStatus::TooWide: message = "address wider than 64 bits"; return false;
    case HexStatus::Ok: break;
  }
  return true;
}

namespace {

// The tag field as a node level, `p` or `t`; `p` is left after it.
bool read_tag(const char*& p, const char* end, Tag& tag, std::string& message) {
  p = skip_blanks(p, end);
  if (p == end) {
    message = "missing tag (the trace's tags are node levels)";
    return false;
  }
  const char* stop = token_end(p, end);
  const std::string_view token(p, static_cast<std::size_t>(stop - p));
  p = stop;
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

// The unit field after the tag: decimal, below `units`.
bool read_unit(const char* p, const char* end, unsigned units, TraversalUnit& unit, std::string& message) {
  p = skip_blanks(p, end);
  if (p == end) {
    message = fmt::format("missing unit (the trace's header says its records carry one of {} traversal units)", units);
    return false;
  }
  const std::string_view token(p, static_cast<std::size_t>(token_end(p, end) - p));
  std::uint64_t value = 0;
  for (const char c : token) {
    if (c < '0' || c > '9' || value >= units) {
      message = fmt::format("unit '{}' is not a traversal unit of this trace (0 to {})", shown_token(token), units - 1);
      return false;
    }
    value = value * 10 + static_cast<unsigned>(c - '0');
  }
  if (value >= units) {
    message = fmt::format("unit '{}' is not a traversal unit of this trace (0 to {})", shown_token(token), units - 1);
    return false;
  }
  unit = traversal_unit(static_cast<unsigned>(value));
  return true;
}

}  // namespace

bool read_line_rest(const char* p, const char* end, const ParseSettings& settings, Record& record,
                    std::string& message, bool& ignored_fields) {
  record.tag = kTagNone;
  record.unit = TraversalUnit{};
  if (settings.tags_are_levels) {
    if (!read_tag(p, end, record.tag, message)) return false;
    return !settings.reads_units() || read_unit(p, end, settings.units, record.unit, message);
  }
  ignored_fields = skip_blanks(p, end) != end;
  return true;  // whatever follows is ignored, as Dinero IV ignores it
}

bool parse_text_lines(std::string_view bytes, const ParseSettings& settings, FastParser fast, bool fast_tagged,
                      VariableParser variable, LineParser line, std::vector<Record>& out, RecordError& error,
                      std::uint64_t& ignored_fields) {
  const char* p = bytes.data();
  const char* const end = p + bytes.size();
  const std::size_t first = out.size();
  const bool fast_ignores_tags = fast_tagged && !settings.tags_are_levels;
  // Room for lines of 6 bytes (`0 0 0` and its newline): growing the
  // records while parsing copies them all.
  out.reserve(out.size() + bytes.size() / 6 + 1);
  while (p < end) {
    if (fast) {
      const std::size_t before = out.size();
      p += fast(p, end, settings.tags_are_levels, settings.units, out);
      if (fast_ignores_tags) ignored_fields += out.size() - before;
      if (p == end) break;
    }
    // The variable-width path takes no unit field: lines of a trace whose
    // records carry units go to the general parser when not fixed-width.
    if (!settings.reads_units()) p += variable(p, end, settings.tags_are_levels, out, ignored_fields);
    if (p == end) break;
    // One line the fast paths did not take.
    const char* newline = static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(end - p)));
    const char* line_end = newline ? newline : end;
    Record record;
    bool ignored = false;
    if (!line(p, line_end, settings, record, error.message, ignored)) {
      error.record_in_chunk = out.size() - first;
      return false;
    }
    ignored_fields += ignored;
    out.push_back(record);
    p = newline ? newline + 1 : end;
  }
  return true;
}

}  // namespace nodetrace::formats::detail
