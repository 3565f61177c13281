#include "nodetrace/formats/read/observed_totals.hpp"

#include <fmt/format.h>

#include <string>

#include "nodetrace/base/error.hpp"

namespace nodetrace::formats {

namespace {

// What the reading found: "the file has" 2 "data frame"s (no noun: the
// count alone).
struct Found {
  const char* verb;
  const char* noun = "";
};

[[noreturn]] void differs(const TraceReader& reader, const std::string& key, const nlohmann::json& stated,
                          std::uint64_t seen, Found found) {
  const std::string noun = *found.noun == '\0' ? "" : fmt::format(" {}{}", found.noun, seen == 1 ? "" : "s");
  throw base::FormatError(fmt::format("{}: the trailer's totals say {} {}, but {} {}{}", reader.source_name(), key,
                                      stated.dump(), found.verb, seen, noun));
}

void check_count(const TraceReader& reader, const nlohmann::json& totals, const char* key, std::uint64_t seen,
                 Found found) {
  if (!totals.contains(key)) return;
  const nlohmann::json& stated = totals[key];
  if (!stated.is_number_unsigned() || stated.get<std::uint64_t>() != seen) differs(reader, key, stated, seen, found);
}

// Each key of either object: a count the trailer states for it, or 0 where
// it names none (records_per_tag lists only the tags seen).
void check_counts(const TraceReader& reader, const nlohmann::json& totals, const char* key,
                  const nlohmann::json& seen) {
  if (!totals.contains(key)) return;
  const nlohmann::json& stated = totals[key];
  const auto count_in = [](const nlohmann::json& object, const std::string& name) {
    const auto found = object.find(name);
    return found == object.end() ? nlohmann::json(0) : *found;
  };
  for (const nlohmann::json* side : {&stated, &seen}) {
    for (const auto& [name, ignored] : side->items()) {
      const nlohmann::json stated_count = count_in(stated, name);
      const std::uint64_t seen_count = count_in(seen, name).get<std::uint64_t>();
      if (!stated_count.is_number_unsigned() || stated_count.get<std::uint64_t>() != seen_count) {
        differs(reader, std::string(key) + "." + name, stated_count, seen_count, {"the records hold"});
      }
    }
  }
}

}  // namespace

void ObservedTotals::check_trailer(const TraceReader& reader) const {
  if (!reader.trailer()) return;
  const nlohmann::json& totals = reader.trailer()->totals;
  check_count(reader, totals, "records", summary_.records(), {"the data frames hold", "record"});
  // Levels counted apart only when the writer read them as the reader does
  // (--tags-are-levels on a container whose header does not say so makes
  // levels of what its writer counted as untagged).
  if (reader.tags_are_levels() == reader.header().tags_are_levels()) {
    check_counts(reader, totals, "records_per_tag", summary_.records_per_tag());
  }
  check_counts(reader, totals, "records_per_type", summary_.records_per_type());
  check_count(reader, totals, "animation_frames", markers_, {"the file has", "animation-frame marker"});
  if (totals.contains("sample_windows") || windows_ > 0) {
    check_count(reader, totals.contains("sample_windows") ? totals : nlohmann::json{{"sample_windows", 0}},
                "sample_windows", windows_, {"the file has", "window marker"});
  }
  check_count(reader, totals, "data_frames", reader.trailer()->index.size(), {"the file has", "data frame"});
  check_count(reader, totals, "record_bytes", reader.record_bytes(), {"the data frames decompress to", "byte"});
}

}  // namespace nodetrace::formats
