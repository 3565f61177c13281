// Container metadata: the header, the animation-frame and sample-window
// markers and the trailer's totals (formats/FORMAT.md gives the JSON of each).
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "nodetrace/base/split_level.hpp"
#include "nodetrace/formats/container/treelet_map.hpp"
#include "nodetrace/formats/record/record.hpp"

namespace nodetrace::formats {

// One animation frame's marker.
struct AnimationFrameMarker {
  std::uint64_t frame = 0;
  double time = 0.0;
  // That frame's kd-tree: nodes per level (index = level), totals, depth.
  std::vector<std::uint64_t> nodes_per_level;
  std::uint64_t nodes = 0;
  std::uint64_t leaves = 0;
  std::uint32_t depth = 0;
  // Further keys written by the producer, kept as they were.
  nlohmann::json extra = nlohmann::json::object();
  // The frame's treelet map, when the trace carries one (not in the
  // marker's JSON: FORMAT.md gives the frame that holds it).
  std::optional<TreeletMap> treelets;

  nlohmann::json to_json() const;
  static AnimationFrameMarker from_json(const nlohmann::json& json);  // throws base::FormatError

  // The hybrid layout's K for this frame (key "split_level", kept in
  // `extra`: the tracer sizes the BFL part per frame); nullopt when absent.
  std::optional<std::uint32_t> layout_split_level() const;
};

// A sample window begins (FORMAT.md: skippable frame, magic 0x184D2A52).
struct WindowMarker {
  std::uint64_t window = 0;  // 0-based number of the window in the full domain
                             // of its animation frame (e.g. band b of the image)
  std::uint64_t frame = 0;   // animation frame number it belongs to
  nlohmann::json extra = nlohmann::json::object();  // producer keys, e.g. "rows": [y0, y1)

  nlohmann::json to_json() const;
  static WindowMarker from_json(const nlohmann::json& json);  // throws base::FormatError
};

// The header's "sampling" key (absent: the trace is not sampled).
struct SamplingInfo {
  std::string method;             // "rows" (the tracer's row bands)
  std::uint64_t every = 1;        // one band in every `every` (rate 1/every)
  std::uint64_t band_height = 0;  // rows per band
  std::uint64_t seed = 0;
  std::uint64_t bands = 0;        // bands in one full image (last band may be shorter)
  nlohmann::json extra = nlohmann::json::object();  // further producer keys

  nlohmann::json to_json() const;
  static SamplingInfo from_json(const nlohmann::json& json);  // throws base::FormatError
};

// The header's "layout": how the producer placed the kd-tree nodes
// (address = node_base + slot * node_size).
struct LayoutInfo {
  std::string name;                          // dfl, bfl, hybrid, veb, ...; empty: not said
  std::optional<std::uint32_t> split_level;  // hybrid only: levels < K in BFL order
  std::uint64_t node_size = 8;
  std::uint64_t node_base = 0;
};

// The header's JSON with typed access to what readers need. Plain traces
// (text, or zstd from another tool) have an empty header.
struct TraceHeader {
  nlohmann::json json = nlohmann::json::object();

  bool present() const { return !json.empty(); }
  // Record form announced by the header ("records"), if any.
  std::optional<RecordForm> form() const;
  // True when the header says `"tag": "node-level"`.
  bool tags_are_levels() const;
  // The traversal units whose records the trace holds (`"units": N`, 1 when
  // absent); above 1 every record carries its unit after the tag. Throws
  // base::FormatError when the key holds no count from 1 to kMaxUnits.
  unsigned units() const;
  // True when the header announces a trailer (a missing one is truncation).
  bool announces_trailer() const;
  // True when the header says `"treelet_map": true`: every animation-frame
  // marker is followed by its frame's treelet map (FORMAT.md 2.2.2).
  bool carries_treelet_maps() const;
  // The "layout" object; defaults (node_size 8, base 0, no name) for what it
  // does not say or when absent.
  LayoutInfo layout() const;
  // The "sampling" object; nullopt when absent (the trace is not sampled).
  // Throws base::FormatError when it is there but malformed.
  std::optional<SamplingInfo> sampling() const;
};

// The placement of a trace's layout (its name and, for hybrid, the frame's K).
base::LevelPlacement level_placement(const LayoutInfo& layout, std::optional<std::uint32_t> frame_split_level,
                                     std::uint64_t block);

// Per data frame entry of the trailer's index.
struct DataFrameIndexEntry {
  std::uint64_t offset = 0;           // byte offset of the zstd frame in the file
  std::uint64_t compressed_size = 0;  // bytes of the zstd frame
  std::uint64_t first_record = 0;     // 0-based number of its first record
  std::uint64_t record_count = 0;
  std::uint64_t animation_frame = 0;
  // The frame's zstd content checksum (low 32 bits of XXH64 of its records),
  // which tells frames apart when checking their order.
  std::uint32_t checksum = 0;

  friend bool operator==(const DataFrameIndexEntry&, const DataFrameIndexEntry&) = default;
};

struct TraceTrailer {
  std::vector<DataFrameIndexEntry> index;
  nlohmann::json totals = nlohmann::json::object();  // records, records_per_tag, ...
  std::uint64_t record_hash = 0;                     // xxHash64 of all record bytes
  std::uint64_t content_hash = 0;  // xxHash64 of every file byte before the trailer

  // The trailer's JSON as the container holds it (FORMAT.md 2.4).
  nlohmann::json to_json() const;
};

}  // namespace nodetrace::formats
