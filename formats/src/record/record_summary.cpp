#include "nodetrace/formats/record/record_summary.hpp"

#include <algorithm>

namespace nodetrace::formats {

namespace {

constexpr std::string_view kTypeNames[kAccessTypeCount] = {"read", "write", "instruction_fetch",
                                                           "misc", "copy_back", "invalidate"};

}  // namespace

std::string_view access_type_name(AccessType type) { return kTypeNames[static_cast<unsigned>(type)]; }

std::string tag_key(Tag tag) {
  if (tag == kTagNone) return "none";
  if (is_level(tag)) return std::to_string(tag);
  return tag_text(tag);
}

nlohmann::json RecordSummary::records_per_tag() const {
  nlohmann::json per_tag = nlohmann::json::object();
  for (std::size_t tag = 0; tag < per_tag_.size(); ++tag) {
    if (per_tag_[tag] != 0) per_tag[tag_key(static_cast<Tag>(tag))] = per_tag_[tag];
  }
  return per_tag;
}

nlohmann::json RecordSummary::records_per_type() const {
  nlohmann::json per_type = nlohmann::json::object();
  for (int type = 0; type < kAccessTypeCount; ++type) {
    per_type[std::string(kTypeNames[type])] = per_type_[static_cast<std::size_t>(type)];
  }
  return per_type;
}

std::vector<std::pair<std::string, std::uint64_t>> ordered_tag_counts(const nlohmann::json& per_tag) {
  std::vector<std::pair<std::string, std::uint64_t>> rows;
  for (const auto& [key, value] : per_tag.items()) rows.emplace_back(key, value.get<std::uint64_t>());
  const auto rank = [](const std::string& key) -> std::pair<int, unsigned long> {
    if (!key.empty() && key.find_first_not_of("0123456789") == std::string::npos) return {0, std::stoul(key)};
    return {key == "p" ? 1 : key == "t" ? 2 : 3, 0};
  };
  std::sort(rows.begin(), rows.end(), [&](const auto& a, const auto& b) { return rank(a.first) < rank(b.first); });
  return rows;
}

}  // namespace nodetrace::formats
