#include "nodetrace/formats/byte_size.hpp"

#include <fmt/format.h>

#include <charconv>
#include <limits>

#include "nodetrace/formats/error.hpp"

namespace nodetrace::formats {

std::uint64_t parse_byte_size(std::string_view text) {
  std::uint64_t value = 0;
  const char* const end = text.data() + text.size();
  const auto [next, error] = std::from_chars(text.data(), end, value);
  std::uint64_t scale = 1;
  if (next != end && next + 1 == end) {
    switch (*next) {
      case 'k': case 'K': scale = std::uint64_t{1} << 10; break;
      case 'm': case 'M': scale = std::uint64_t{1} << 20; break;
      case 'g': case 'G': scale = std::uint64_t{1} << 30; break;
      default: scale = 0;
    }
  } else if (next != end) {
    scale = 0;
  }
  if (error != std::errc{} || next == text.data() || scale == 0 || value == 0 ||
      value > std::numeric_limits<std::uint64_t>::max() / scale) {
    throw UsageError(fmt::format(
        "'{}' is not a size: expected a positive number of bytes, optionally with k, m or g "
        "(e.g. 8k)",
        text));
  }
  return value * scale;
}

std::uint64_t parse_byte_size(std::string_view text, std::string_view option) {
  try {
    return parse_byte_size(text);
  } catch (const UsageError& error) {
    throw UsageError(fmt::format("{}: {}", option, error.what()));
  }
}

}  // namespace nodetrace::formats
