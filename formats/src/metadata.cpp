#include "nodetrace/formats/metadata.hpp"

#include <fmt/format.h>

#include "nodetrace/formats/error.hpp"

namespace nodetrace::formats {

namespace {

const char* const kMarkerKeys[] = {"frame", "time", "nodes_per_level", "nodes", "leaves", "depth"};

// A marker's unsigned integer field; an error names the key and what it holds.
std::uint64_t unsigned_field(const nlohmann::json& value, const std::string& key, std::uint64_t limit) {
  if (!value.is_number_unsigned() || value.get<std::uint64_t>() > limit) {
    throw FormatError(fmt::format("animation frame marker: \"{}\" is {}, expected an unsigned integer{}", key,
                                  value.dump().substr(0, 40),
                                  limit == ~std::uint64_t{0} ? "" : fmt::format(" up to {}", limit)));
  }
  return value.get<std::uint64_t>();
}

}  // namespace

nlohmann::json FrameMarker::to_json() const {
  nlohmann::json json = extra.is_object() ? extra : nlohmann::json::object();
  json["frame"] = frame;
  json["time"] = time;
  json["nodes_per_level"] = nodes_per_level;
  json["nodes"] = nodes;
  json["leaves"] = leaves;
  json["depth"] = depth;
  return json;
}

FrameMarker FrameMarker::from_json(const nlohmann::json& json) {
  if (!json.is_object()) throw FormatError("animation frame marker is not a JSON object");
  constexpr std::uint64_t kAny = ~std::uint64_t{0};
  FrameMarker marker;
  if (!json.contains("frame")) throw FormatError("animation frame marker: no \"frame\" key");
  marker.frame = unsigned_field(json["frame"], "frame", kAny);
  if (json.contains("time")) {
    if (!json["time"].is_number()) {
      throw FormatError(fmt::format("animation frame marker: \"time\" is {}, expected a number",
                                    json["time"].dump().substr(0, 40)));
    }
    marker.time = json["time"].get<double>();
  }
  if (json.contains("nodes_per_level")) {
    const nlohmann::json& levels = json["nodes_per_level"];
    if (!levels.is_array()) {
      throw FormatError(fmt::format("animation frame marker: \"nodes_per_level\" is {}, expected an array",
                                    levels.dump().substr(0, 40)));
    }
    for (std::size_t i = 0; i < levels.size(); ++i) {
      marker.nodes_per_level.push_back(unsigned_field(levels[i], fmt::format("nodes_per_level[{}]", i), kAny));
    }
  }
  if (json.contains("nodes")) marker.nodes = unsigned_field(json["nodes"], "nodes", kAny);
  if (json.contains("leaves")) marker.leaves = unsigned_field(json["leaves"], "leaves", kAny);
  if (json.contains("depth")) {
    marker.depth = static_cast<std::uint32_t>(unsigned_field(json["depth"], "depth", 0xFFFFFFFFu));
  }
  for (const auto& [key, value] : json.items()) {
    bool known = false;
    for (const char* name : kMarkerKeys) known = known || key == name;
    if (!known) marker.extra[key] = value;
  }
  return marker;
}

std::optional<RecordForm> TraceHeader::form() const {
  const auto found = json.find("records");
  if (found == json.end() || !found->is_string()) return std::nullopt;
  return parse_form_name(found->get<std::string>());
}

bool TraceHeader::tags_are_levels() const {
  const auto found = json.find("tag");
  return found != json.end() && found->is_string() && found->get<std::string>() == "node-level";
}

bool TraceHeader::announces_trailer() const {
  const auto found = json.find("trailer");
  return found != json.end() && found->is_boolean() && found->get<bool>();
}

}  // namespace nodetrace::formats
