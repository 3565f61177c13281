#include "nodetrace/formats/record/tag_filter.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <string>

#include "nodetrace/base/error.hpp"

namespace nodetrace::formats {

TagFilter TagFilter::parse(std::string_view text, std::string_view option) {
  TagFilter filter;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string item(text.substr(start, comma - start));
    start = comma + 1;
    if (item == "p") {
      filter.primitive_lists_ = true;
      continue;
    }
    if (item == "t") {
      filter.triangles_ = true;
      continue;
    }
    const auto number = [&](const std::string& digits) -> unsigned long {
      if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos || digits.size() > 5 ||
          std::stoul(digits) > kMaxLevel) {
        throw base::UsageError(
            fmt::format("{}: '{}' is not a level, a range (A-B, A-) or p / t (e.g. 0-3,9-,p)", option, item));
      }
      return std::stoul(digits);
    };
    const std::size_t dash = item.find('-');
    unsigned long low, high;
    if (dash == std::string::npos) {
      low = high = number(item);
    } else {
      low = number(item.substr(0, dash));
      high = dash + 1 == item.size() ? kMaxLevel : number(item.substr(dash + 1));
      if (high < low) throw base::UsageError(fmt::format("{}: range '{}' is empty", option, item));
    }
    for (unsigned long level = low; level <= high; ++level) filter.levels_[level] = true;
  }
  return filter;
}

}  // namespace nodetrace::formats
