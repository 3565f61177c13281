#include "nodetrace/base/sample_rate.hpp"

#include <fmt/format.h>

#include <charconv>

#include "nodetrace/base/error.hpp"

namespace nodetrace::base {

std::uint64_t parse_sample_rate(std::string_view text, std::string_view option) {
  const auto whole = [](std::string_view digits, std::uint64_t& value) {
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    return !digits.empty() && error == std::errc() && end == digits.data() + digits.size();
  };
  const auto slash = text.find('/');
  std::uint64_t numerator = 0;
  std::uint64_t every = 0;
  if (slash == std::string_view::npos || !whole(text.substr(0, slash), numerator) ||
      !whole(text.substr(slash + 1), every) || numerator != 1 || every == 0) {
    throw UsageError(fmt::format("{}: '{}' is not a sampling rate: expected 1/K with K a whole "
                                 "number >= 1 (one unit in every K; 1/1 is everything)",
                                 option, text));
  }
  return every;
}

}  // namespace nodetrace::base
