// A set of tags to keep, from the text users give on command lines
// (`tracetool cat --tags 0-3,9-,p`): levels, level ranges, `p` and `t`.
#pragma once

#include <string_view>
#include <vector>

#include "nodetrace/formats/record/record.hpp"

namespace nodetrace::formats {

class TagFilter {
 public:
  // Comma-separated items: a level `N`, a range `A-B` or `A-` (to the largest
  // level), `p` (primitive lists), `t` (triangles). Throws base::UsageError naming
  // `option` and the item that is none of these, or an empty range.
  static TagFilter parse(std::string_view text, std::string_view option = "--tags");

  bool keeps(Tag tag) const {
    if (is_level(tag)) return levels_[tag];
    if (tag == kTagPrimitiveList) return primitive_lists_;
    if (tag == kTagTriangle) return triangles_;
    return false;  // untagged records carry no level to keep
  }

 private:
  std::vector<bool> levels_ = std::vector<bool>(std::size_t{kMaxLevel} + 1, false);
  bool primitive_lists_ = false;
  bool triangles_ = false;
};

}  // namespace nodetrace::formats
