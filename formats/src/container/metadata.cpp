#include "nodetrace/formats/container/metadata.hpp"

#include <fmt/format.h>
#include <algorithm>

#include "nodetrace/base/error.hpp"

namespace nodetrace::formats {

namespace {

const char* const kMarkerKeys[] = {"frame", "time", "nodes_per_level", "nodes", "leaves", "depth"};

const char* const kWindowKeys[] = {"window", "frame"};
const char* const kSamplingKeys[] = {"method", "every", "band_height", "seed", "bands"};
constexpr std::uint64_t kAny = ~std::uint64_t{0};

// An unsigned integer field of `what` (a marker, the header's "sampling"); an
// error names the key and what it holds.
std::uint64_t unsigned_field(const nlohmann::json& value, const std::string& key, std::uint64_t limit,
                             const char* what = "animation frame marker") {
  if (!value.is_number_unsigned() || value.get<std::uint64_t>() > limit) {
    throw base::FormatError(fmt::format("{}: \"{}\" is {}, expected an unsigned integer{}", what, key,
                                  value.dump().substr(0, 40),
                                  limit == ~std::uint64_t{0} ? "" : fmt::format(" up to {}", limit)));
  }
  return value.get<std::uint64_t>();
}

// The keys of `json` that are not among `known`, for a struct's `extra`.
template <std::size_t N>
nlohmann::json other_keys(const nlohmann::json& json, const char* const (&known)[N]) {
  nlohmann::json extra = nlohmann::json::object();
  for (const auto& item : json.items()) {
    const std::string& key = item.key();  // a named reference: clang's lambdas cannot capture bindings
    if (std::find_if(std::begin(known), std::end(known), [&](const char* name) { return key == name; }) ==
        std::end(known)) {
      extra[key] = item.value();
    }
  }
  return extra;
}

}  // namespace

nlohmann::json AnimationFrameMarker::to_json() const {
  nlohmann::json json = extra.is_object() ? extra : nlohmann::json::object();
  json["frame"] = frame;
  json["time"] = time;
  json["nodes_per_level"] = nodes_per_level;
  json["nodes"] = nodes;
  json["leaves"] = leaves;
  json["depth"] = depth;
  return json;
}

AnimationFrameMarker AnimationFrameMarker::from_json(const nlohmann::json& json) {
  if (!json.is_object()) throw base::FormatError("animation frame marker is not a JSON object");
  AnimationFrameMarker marker;
  if (!json.contains("frame")) throw base::FormatError("animation frame marker: no \"frame\" key");
  marker.frame = unsigned_field(json["frame"], "frame", kAny);
  if (json.contains("time")) {
    if (!json["time"].is_number()) {
      throw base::FormatError(fmt::format("animation frame marker: \"time\" is {}, expected a number",
                                    json["time"].dump().substr(0, 40)));
    }
    marker.time = json["time"].get<double>();
  }
  if (json.contains("nodes_per_level")) {
    const nlohmann::json& levels = json["nodes_per_level"];
    if (!levels.is_array()) {
      throw base::FormatError(fmt::format("animation frame marker: \"nodes_per_level\" is {}, expected an array",
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
  marker.extra = other_keys(json, kMarkerKeys);
  return marker;
}

nlohmann::json WindowMarker::to_json() const {
  nlohmann::json json = extra.is_object() ? extra : nlohmann::json::object();
  json["window"] = window;
  json["frame"] = frame;
  return json;
}

WindowMarker WindowMarker::from_json(const nlohmann::json& json) {
  constexpr const char* kWhat = "sample window marker";
  if (!json.is_object()) throw base::FormatError("sample window marker is not a JSON object");
  WindowMarker marker;
  for (const char* key : kWindowKeys) {
    if (!json.contains(key)) throw base::FormatError(fmt::format("sample window marker: no \"{}\" key", key));
  }
  marker.window = unsigned_field(json["window"], "window", kAny, kWhat);
  marker.frame = unsigned_field(json["frame"], "frame", kAny, kWhat);
  marker.extra = other_keys(json, kWindowKeys);
  return marker;
}

nlohmann::json SamplingInfo::to_json() const {
  nlohmann::json json = extra.is_object() ? extra : nlohmann::json::object();
  json["method"] = method;
  json["every"] = every;
  json["band_height"] = band_height;
  json["seed"] = seed;
  json["bands"] = bands;
  return json;
}

SamplingInfo SamplingInfo::from_json(const nlohmann::json& json) {
  constexpr const char* kWhat = "header \"sampling\"";
  if (!json.is_object()) throw base::FormatError("header \"sampling\" is not a JSON object");
  SamplingInfo info;
  const auto method = json.find("method");
  if (method == json.end() || !method->is_string() || method->get<std::string>().empty()) {
    throw base::FormatError("header \"sampling\": \"method\" must be a non-empty string (e.g. \"rows\")");
  }
  info.method = method->get<std::string>();
  if (json.contains("every")) {
    info.every = unsigned_field(json["every"], "every", kAny, kWhat);
    if (info.every == 0) throw base::FormatError("header \"sampling\": \"every\" is 0, expected at least 1");
  }
  if (json.contains("band_height")) info.band_height = unsigned_field(json["band_height"], "band_height", kAny, kWhat);
  if (json.contains("seed")) info.seed = unsigned_field(json["seed"], "seed", kAny, kWhat);
  if (json.contains("bands")) info.bands = unsigned_field(json["bands"], "bands", kAny, kWhat);
  info.extra = other_keys(json, kSamplingKeys);
  return info;
}

std::optional<std::uint32_t> AnimationFrameMarker::layout_split_level() const {
  if (!extra.is_object()) return std::nullopt;
  const auto found = extra.find("split_level");
  if (found == extra.end() || !found->is_number_unsigned()) return std::nullopt;
  return found->get<std::uint32_t>();
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

unsigned TraceHeader::units() const {
  const auto found = json.find("units");
  if (found == json.end()) return 1;
  if (!found->is_number_integer() || found->get<std::int64_t>() < 1 || found->get<std::int64_t>() > kMaxUnits) {
    throw base::FormatError(fmt::format("header: \"units\" is {}, expected a count of traversal units from 1 to {}",
                                        found->dump().substr(0, 40), kMaxUnits));
  }
  return found->get<unsigned>();
}

bool TraceHeader::announces_trailer() const {
  const auto found = json.find("trailer");
  return found != json.end() && found->is_boolean() && found->get<bool>();
}

bool TraceHeader::carries_treelet_maps() const {
  const auto found = json.find("treelet_map");
  return found != json.end() && found->is_boolean() && found->get<bool>();
}

LayoutInfo TraceHeader::layout() const {
  LayoutInfo info;
  if (!json.is_object()) return info;
  const auto layout = json.find("layout");
  if (layout == json.end() || !layout->is_object()) return info;
  if (const auto name = layout->find("name"); name != layout->end() && name->is_string()) {
    info.name = name->get<std::string>();
  }
  if (const auto k = layout->find("split_level"); k != layout->end() && k->is_number_unsigned()) {
    info.split_level = k->get<std::uint32_t>();
  }
  if (const auto size = layout->find("node_size");
      size != layout->end() && size->is_number_unsigned() && size->get<std::uint64_t>() > 0) {
    info.node_size = size->get<std::uint64_t>();
  }
  if (const auto base = layout->find("node_base"); base != layout->end() && base->is_number_unsigned()) {
    info.node_base = base->get<std::uint64_t>();
  }
  return info;
}

std::optional<SamplingInfo> TraceHeader::sampling() const {
  if (!json.is_object()) return std::nullopt;
  const auto found = json.find("sampling");
  if (found == json.end()) return std::nullopt;
  return SamplingInfo::from_json(*found);
}

base::LevelPlacement level_placement(const LayoutInfo& layout, std::optional<std::uint32_t> frame_split_level,
                               std::uint64_t block) {
  base::LevelPlacement placement;
  placement.node_size = layout.node_size;
  placement.node_base = layout.node_base;
  placement.block = block;
  if (layout.name == "bfl") {
    placement.contiguous_levels = ~std::uint32_t{0};
  } else if (layout.name == "hybrid") {
    placement.contiguous_levels = frame_split_level.value_or(layout.split_level.value_or(0));
  } else {
    placement.contiguous_levels = 0;
  }
  return placement;
}

}  // namespace nodetrace::formats
