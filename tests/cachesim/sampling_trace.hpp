// The synthetic trace of the sampling tests: a container of many data frames
// whose windows differ.
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>

#include "nodetrace/formats/write/trace_writer.hpp"

namespace nodetrace::cachesim {

inline constexpr std::uint64_t kRecordsPerDataFrame = 1024;

// The animation-frame marker of the 10-level complete tree the walks visit.
inline formats::AnimationFrameMarker tree_marker(std::uint64_t frame) {
  formats::AnimationFrameMarker marker;
  marker.frame = frame;
  marker.nodes_per_level = {1, 2, 4, 8, 16, 32, 64, 128, 256, 512};
  marker.nodes = 1023;
  marker.leaves = 512;
  marker.depth = 10;
  return marker;
}

// One root-to-leaf walk (BFL from 0x1000) going right at a level with the
// chance right_in_16 / 16, drawn from `state`.
inline void write_walk(formats::TraceWriter& writer, std::uint64_t& state, std::uint64_t right_in_16) {
  std::uint64_t slot = 0;
  for (formats::Tag level = 0; level < 10; ++level) {
    formats::Record record;
    record.address = 0x1000 + slot * 8;
    record.size = 8;
    record.tag = level;
    writer.write(record);
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    const bool right = ((state >> 33) % 16) < right_in_16;
    slot = 2 * slot + 1 + (right ? 1 : 0);
  }
}

// Two animation frames of 20 data frames each: root-to-leaf walks of a
// 10-level tree (BFL from 0x1000), pseudo-random so windows differ.
inline void write_walks(const std::filesystem::path& path) {
  formats::WriterOptions options;
  options.form = formats::RecordForm::Din;
  options.records_per_data_frame = kRecordsPerDataFrame;
  nlohmann::json header = {{"layout", {{"name", "bfl"}, {"split_level", 4},
                                       {"node_size", 8}, {"node_base", 4096}}}};
  auto writer = formats::TraceWriter::create(path.string(), header, options);
  std::uint64_t state = 12345;
  for (std::uint64_t frame = 0; frame < 2; ++frame) {
    writer->begin_animation_frame(tree_marker(frame));
    // Walks drift through the tree so locality changes along the trace.
    for (std::uint64_t walk = 0; walk < 2048; ++walk) write_walk(*writer, state, 6 + 2 * ((walk / 512) % 3));
  }
  writer->finish();
}

// A row-sampled trace as `tracer render --sample-rows 1/every` writes it:
// header "sampling", then per animation frame one window marker and 600
// records for one band of each stratum of `every` bands (of `bands`).
inline void write_row_sampled(const std::filesystem::path& path, std::uint64_t every,
                              std::uint64_t bands, std::uint64_t frames) {
  formats::WriterOptions options;
  options.form = formats::RecordForm::Din;
  formats::SamplingInfo info;
  info.method = "rows";
  info.every = every;
  info.band_height = 2;
  info.bands = bands;
  nlohmann::json header = {{"layout", {{"name", "bfl"}, {"split_level", 4},
                                       {"node_size", 8}, {"node_base", 4096}}},
                           {"sampling", info.to_json()}};
  auto writer = formats::TraceWriter::create(path.string(), header, options);
  std::uint64_t state = 99;
  for (std::uint64_t frame = 0; frame < frames; ++frame) {
    writer->begin_animation_frame(tree_marker(frame));
    for (std::uint64_t stratum = 0; stratum * every < bands; ++stratum) {
      const std::uint64_t band = stratum * every + (stratum * 7 + frame) % every;
      if (band >= bands) continue;
      formats::WindowMarker window;
      window.window = band;
      window.frame = frame;
      window.extra = {{"rows", {band * 2, band * 2 + 2}}};
      writer->begin_window(window);
      // Bands lower in the image go right more often: windows differ.
      for (std::uint64_t walk = 0; walk < 60; ++walk) write_walk(*writer, state, 2 + band % 12);
    }
  }
  writer->finish();
}

}  // namespace nodetrace::cachesim
