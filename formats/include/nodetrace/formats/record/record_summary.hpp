// Counts of records by tag and by access type, and their JSON as a
// container's trailer totals hold them (FORMAT.md 2.4: `records_per_tag`,
// `records_per_type`). The writer keeps one for the trailer; readers of a
// trace without a trailer count one themselves (tracetool info).
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "nodetrace/formats/record/record.hpp"

namespace nodetrace::formats {

class RecordSummary {
 public:
  void add(const Record& record) {
    ++per_tag_[record.tag];
    ++per_type_[static_cast<unsigned>(record.type)];
    ++records_;
  }
  void add(std::span<const Record> records) {
    for (const Record& record : records) add(record);
  }

  std::uint64_t records() const { return records_; }
  // Tag keys (tag_key) to counts, only the non-zero ones.
  nlohmann::json records_per_tag() const;
  // All six access type names (access_type_name) to counts.
  nlohmann::json records_per_type() const;

 private:
  std::vector<std::uint64_t> per_tag_ = std::vector<std::uint64_t>(std::size_t{1} << 16, 0);
  std::array<std::uint64_t, kAccessTypeCount> per_type_{};
  std::uint64_t records_ = 0;
};

// The totals' name of an access type: read, write, instruction_fetch, misc,
// copy_back, invalidate.
std::string_view access_type_name(AccessType type);

// The totals' key of a tag: the decimal level without padding, "p", "t", or
// "none" for an untagged record.
std::string tag_key(Tag tag);

// A records_per_tag object's entries in reading order: levels by number,
// then p, t, none.
std::vector<std::pair<std::string, std::uint64_t>> ordered_tag_counts(const nlohmann::json& per_tag);

}  // namespace nodetrace::formats
