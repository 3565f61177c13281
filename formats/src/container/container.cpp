#include "container/container.hpp"

#include <fmt/format.h>
#include <xxhash.h>

#include "nodetrace/base/error.hpp"

namespace nodetrace::formats::detail {

std::string skippable_frame(std::uint32_t magic, std::string_view payload) {
  std::string frame;
  frame.reserve(kSkippableHeaderSize + payload.size());
  append_le32(frame, magic);
  append_le32(frame, static_cast<std::uint32_t>(payload.size()));
  frame.append(payload);
  return frame;
}

std::string hash_text(std::uint64_t hash) { return fmt::format("{:016x}", hash); }

namespace {
std::uint64_t parse_hash(const nlohmann::json& json, const char* key) {
  const std::string text = json.at(key).get<std::string>();
  if (text.size() != 16 || text.find_first_not_of("0123456789abcdef") != std::string::npos) {
    throw base::FormatError(fmt::format("trailer: \"{}\" is not 16 lower-case hex digits", key));
  }
  return std::stoull(text, nullptr, 16);
}
// The totals FORMAT.md 2.4 defines are counts: a number JSON holds but
// uint64 does not (2^64 + 5 parses as a double) is refused, not shown as
// whatever it converts to.
void check_counts(const nlohmann::json& totals) {
  const auto check = [](const nlohmann::json& value, const std::string& name) {
    if (!value.is_number_unsigned()) {
      throw base::FormatError(
          fmt::format("trailer: totals.{} is {}, not a count (an integer from 0 to 2^64 - 1)", name, value.dump()));
    }
  };
  for (const char* key : {"records", "animation_frames", "sample_windows", "data_frames", "record_bytes"}) {
    if (totals.contains(key)) check(totals[key], key);
  }
  for (const char* key : {"records_per_tag", "records_per_type"}) {
    if (!totals.contains(key)) continue;
    if (!totals[key].is_object()) throw base::FormatError(fmt::format("trailer: totals.{} is not an object", key));
    for (const auto& [name, value] : totals[key].items()) check(value, std::string(key) + "." + name);
  }
}
}  // namespace

std::string encode_trailer(const TraceTrailer& trailer) {
  const std::string text = trailer.to_json().dump();
  std::string payload = text;
  append_le64(payload, XXH64(text.data(), text.size(), 0));
  append_le32(payload, static_cast<std::uint32_t>(text.size()));
  append_le32(payload, kContainerVersion);
  append_le32(payload, kFooterMagic);
  return skippable_frame(kTrailerMagic, payload);
}

TraceTrailer decode_trailer_json(std::string_view text) {
  TraceTrailer trailer;
  try {
    const auto json = nlohmann::json::parse(text);
    for (const auto& row : json.at("index")) {
      if (!row.is_array() || row.size() != 6) throw base::FormatError("trailer: an index entry is not 6 numbers");
      DataFrameIndexEntry entry;
      entry.offset = row[0].get<std::uint64_t>();
      entry.compressed_size = row[1].get<std::uint64_t>();
      entry.first_record = row[2].get<std::uint64_t>();
      entry.record_count = row[3].get<std::uint64_t>();
      entry.animation_frame = row[4].get<std::uint64_t>();
      entry.checksum = row[5].get<std::uint32_t>();
      trailer.index.push_back(entry);
    }
    trailer.totals = json.at("totals");
    if (!trailer.totals.is_object()) throw base::FormatError("trailer: \"totals\" is not an object");
    check_counts(trailer.totals);
    trailer.record_hash = parse_hash(json, "record_hash");
    trailer.content_hash = parse_hash(json, "content_hash");
  } catch (const nlohmann::json::exception& error) {
    throw base::FormatError(std::string("trailer: ") + error.what());
  }
  return trailer;
}

}  // namespace nodetrace::formats::detail

namespace nodetrace::formats {

nlohmann::json TraceTrailer::to_json() const {
  nlohmann::json json = nlohmann::json::object();
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& entry : index) {
    rows.push_back({entry.offset, entry.compressed_size, entry.first_record, entry.record_count,
                    entry.animation_frame, entry.checksum});
  }
  json["index"] = std::move(rows);
  json["totals"] = totals;
  json["record_hash"] = detail::hash_text(record_hash);
  json["content_hash"] = detail::hash_text(content_hash);
  return json;
}

}  // namespace nodetrace::formats
