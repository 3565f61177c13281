// A numeric option's accepted values, checked by CLI11 as it parses: CLI11's
// own Range says "Value abc not in range 1 to 65536" of a value that is not a
// number at all; this one says which of the two is wrong. Its description in
// --help is Range's ("INT in [1 - 65536]").
#pragma once

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cmath>
#include <string>
#include <type_traits>

namespace nodetrace::cli {

class NumberRange : public CLI::Validator {
 public:
  template <typename T>
  NumberRange(T min, T max) {
    description(fmt::format("{} in [{} - {}]", CLI::detail::type_name<T>(), min, max));
    func_ = [min, max](std::string& input) -> std::string {
      const std::string not_one = fmt::format("'{}' is not {}: expected {} to {}", input,
                                              std::is_integral_v<T> ? "a whole number" : "a number", min, max);
      const std::string outside = fmt::format("{} is outside {} to {}", input, min, max);
      T value{};
      if (!CLI::detail::lexical_cast(input, value)) {
        // A whole number T cannot hold (-1 for an unsigned option) is out of range.
        double number = 0;
        const bool whole =
            CLI::detail::lexical_cast(input, number) && std::isfinite(number) && number == std::trunc(number);
        return std::is_integral_v<T> && whole ? outside : not_one;
      }
      if (value != value) return not_one;  // NaN
      if (!(value >= min && value <= max)) return outside;
      return {};
    };
  }
};

}  // namespace nodetrace::cli
