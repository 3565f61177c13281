#include "nodetrace/base/byte_size.hpp"

#include <fmt/format.h>

#include <charconv>
#include <limits>

#include "nodetrace/base/error.hpp"

namespace nodetrace::base {

std::optional<std::uint64_t> parse_scaled_number(std::string_view text) {
  std::uint64_t value = 0;
  const char* const end = text.data() + text.size();
  const auto [next, error] = std::from_chars(text.data(), end, value);
  if (error != std::errc{} || next == text.data()) return std::nullopt;
  unsigned shift = 0;
  if (next != end) {
    if (next + 1 != end) return std::nullopt;
    switch (*next) {
      case 'k': case 'K': shift = 10; break;
      case 'm': case 'M': shift = 20; break;
      case 'g': case 'G': shift = 30; break;
      default: return std::nullopt;
    }
  }
  if (value > (std::numeric_limits<std::uint64_t>::max() >> shift)) return std::nullopt;
  return value << shift;
}

std::uint64_t parse_byte_size(std::string_view text) {
  const std::optional<std::uint64_t> value = parse_scaled_number(text);
  if (!value || *value == 0) {
    throw UsageError(fmt::format(
        "'{}' is not a size: expected a positive number of bytes, optionally with k, m or g "
        "(e.g. 8k)",
        text));
  }
  return *value;
}

std::uint64_t parse_byte_size(std::string_view text, std::string_view option) {
  try {
    return parse_byte_size(text);
  } catch (const UsageError& error) {
    throw UsageError(fmt::format("{}: {}", option, error.what()));
  }
}

}  // namespace nodetrace::base
