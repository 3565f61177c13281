#include "nodetrace/formats/metadata.hpp"

#include "nodetrace/formats/error.hpp"

namespace nodetrace::formats {

namespace {
const char* const kMarkerKeys[] = {"frame", "time", "nodes_per_level", "nodes", "leaves", "depth"};
}

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
  FrameMarker marker;
  try {
    marker.frame = json.at("frame").get<std::uint64_t>();
    if (json.contains("time")) marker.time = json.at("time").get<double>();
    if (json.contains("nodes_per_level"))
      marker.nodes_per_level = json.at("nodes_per_level").get<std::vector<std::uint64_t>>();
    if (json.contains("nodes")) marker.nodes = json.at("nodes").get<std::uint64_t>();
    if (json.contains("leaves")) marker.leaves = json.at("leaves").get<std::uint64_t>();
    if (json.contains("depth")) marker.depth = json.at("depth").get<std::uint32_t>();
  } catch (const nlohmann::json::exception& error) {
    throw FormatError(std::string("animation frame marker: ") + error.what());
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
