// Writing traces: the container of formats/FORMAT.md, or plain records.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "nodetrace/formats/container/metadata.hpp"
#include "nodetrace/formats/write/trace_output.hpp"
#include "nodetrace/formats/record/record.hpp"

namespace nodetrace::formats {

struct WriterOptions {
  RecordForm form = RecordForm::Din;
  OutputKind kind = OutputKind::Auto;  // decide_trace_output (trace_output.hpp) decides Auto
  int zstd_level = 3;
  // 0: the writer's window (4 MiB at levels 1-6, zstd's own above). Else
  // data frames are compressed with a window of 2^window_log bytes and
  // zstd's long-distance matching, and the header says so ("compression",
  // FORMAT.md 2.1): a reader needs up to that much memory per data frame.
  unsigned window_log = 0;
  unsigned threads = 0;                        // compression threads; 0 = one per core
  std::uint64_t records_per_data_frame = 1u << 20;  // records per data frame
  unsigned address_digits = 8;                 // 8, or 16 for addresses above 32 bits
  // Containers: mark the tags as node levels (`"tag": "node-level"`); every
  // record must then carry a level, `p` or `t`. Binary records carry no tag,
  // so a binary container never says so.
  bool tags_are_levels = true;
  // Traversal units of the records (1 to kMaxUnits). Above 1, every tagged
  // text record carries its unit after the tag (fixed width, TextLayout::
  // unit_digits), each must be below `units`, and a container's header says
  // `"units": N` (only then: one unit writes what it always wrote). Binary
  // records cannot carry one.
  unsigned units = 1;
  // Containers: every animation-frame marker carries its frame's treelet map
  // (AnimationFrameMarker::treelets, required then and refused otherwise),
  // written after the marker, and the header says `"treelet_map": true`
  // (FORMAT.md 2.2.2). Plain output drops the maps with the markers.
  bool treelet_maps = false;
};

// The header of a container written with `options`: `header`, the
// producer's part, with the writer's own keys (container, records, tag,
// units, trailer, compression, treelet_map).
nlohmann::json container_header(nlohmann::json header, const WriterOptions& options);

// The archive setting (`--archive`): compressed for size rather than speed.
// Measured on the BART Kitchen trace (75.8 M records): see FORMAT.md 2.3.1.
inline constexpr int kArchiveZstdLevel = 17;
inline constexpr unsigned kArchiveWindowLog = 26;  // 64 MiB: a whole data frame
inline constexpr std::uint64_t kArchiveRecordsPerDataFrame = std::uint64_t{1} << 22;
// The largest window_log a writer accepts: what zstd's decoders accept
// without being told to allow more (ZSTD_WINDOWLOG_LIMIT_DEFAULT), so
// `zstdcat` reads every container we write.
inline constexpr unsigned kMaxWindowLog = 27;

// Sets the archive setting's level, window and records per data frame.
inline void use_archive_setting(WriterOptions& options) {
  options.zstd_level = kArchiveZstdLevel;
  options.window_log = kArchiveWindowLog;
  options.records_per_data_frame = kArchiveRecordsPerDataFrame;
}

class TraceWriter {
 public:
  // `path` is opened by base::OutputFile's rule (output_file.hpp): "-" is
  // standard output, a device or FIFO is written directly, a file is written
  // under a temporary name and renamed into place by finish(). `header` is the producer's part of
  // the container header (scene, render, layout, ...); the writer adds
  // "container", "records" and "tag" itself. Ignored for plain output.
  static std::unique_ptr<TraceWriter> create(const std::string& path, nlohmann::json header,
                                             const WriterOptions& options);
  // Abandons an unfinished output: the temporary file is removed.
  virtual ~TraceWriter();

  // Starts an animation frame (writes its marker in a container; nothing in
  // plain output). Records written before any begin_animation_frame belong to frame 0
  // with no marker.
  virtual void begin_animation_frame(const AnimationFrameMarker& marker) = 0;
  // Starts a sample window: ends the current data frame and writes a window
  // marker (container); nothing in plain output. A window never spans an
  // animation-frame marker: begin_animation_frame ends the open window. When both
  // begin at one record, call begin_animation_frame first (the file holds the frame
  // marker, then the window marker).
  virtual void begin_window(const WindowMarker& marker) = 0;
  virtual void write(std::span<const Record> records) = 0;
  void write(const Record& record) { write(std::span<const Record>(&record, 1)); }
  // Extra totals known only at the end (ray-kind counts, ...), merged into the
  // trailer's "totals" object.
  virtual void add_totals(const nlohmann::json& totals) = 0;
  // Writes the trailer and commits the output (fsync and rename for a file).
  virtual void finish() = 0;
};

}  // namespace nodetrace::formats
