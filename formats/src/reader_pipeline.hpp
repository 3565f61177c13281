// What every kind of trace reader shares (internal): the in-order pipeline
// of units (data frames or text chunks decoded on worker threads, markers
// between them) and the delivery of records and markers in trace order.
// container_reader.cpp, plain_zstd_reader.cpp and plain_text_reader.cpp
// fill the pipeline from their kind of input; reader.cpp picks the kind.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "buffers.hpp"
#include "nodetrace/formats/reader.hpp"
#include "record_codec.hpp"
#include "nodetrace/formats/ordered_pipeline.hpp"
#include "trace_input.hpp"

namespace nodetrace::formats::detail {

// What a worker hands back for one data frame or text chunk.
struct Chunk {
  std::vector<Record> records;
  ByteBuffer bytes;  // the decompressed record bytes (containers: hashed in order)
  bool bad_record = false;
  RecordError record_error;
  std::uint64_t ignored_fields = 0;  // records whose trailing fields were ignored
  std::string frame_error;           // damage found before parsing
};

// Buffers handed back by the consumer for the workers to reuse.
struct Stock {
  Recycler<ByteBuffer> bytes{16};
  Recycler<std::vector<Record>> records{16};
};

Chunk parse_chunk(const std::string& bytes, ParseSettings settings, Stock& stock);

// One item of the in-order pipeline.
struct Unit {
  enum class Kind { Records, FrameMarker, WindowMarker, SkippedFrame };
  Kind kind = Kind::Records;
  FrameMarker marker;
  WindowMarker window;
  Chunk chunk;  // Records: filled on a worker
  // Containers: where the data frame is and what the index should say.
  FrameIndexEntry entry;
  std::uint64_t data_frame = 0;
};

// Opens the input named `path` ("-": standard input) under the name errors use.
struct OpenedInput {
  std::string name;
  std::unique_ptr<Input> input;
};

class PipelinedReader : public TraceReader {
 public:
  PipelinedReader(OpenedInput opened, const ReaderOptions& options);
  ~PipelinedReader() override;

  const std::string& source_name() const override { return name_; }
  const TraceHeader& header() const override { return header_; }
  RecordForm form() const override { return settings_.form; }
  bool tags_are_levels() const override { return settings_.tags_are_levels; }
  const std::optional<TraceTrailer>& trailer() const override { return trailer_; }
  std::uint64_t record_bytes() const override { return record_bytes_; }
  std::uint64_t records_with_ignored_fields() const override { return ignored_fields_; }
  bool next(RecordBatch& batch) final;
  void seek_to_record(std::uint64_t record) override;

 protected:
  // Queues the input's next unit, or sets input_done_ at its end.
  virtual void read_unit() = 0;
  // Checks a data frame's chunk before its records go out (containers).
  virtual void check_chunk(const Unit& unit, Chunk& chunk) { (void)unit, (void)chunk; }
  // A data frame skipped by keep_data_frame, in its turn (containers).
  virtual void pass_skipped(const Unit& unit) { (void)unit; }
  // The input has ended: final checks (containers: trailer, index, hashes).
  virtual void finish_input() {}

  // Once the settings are known: the worker threads; rejects binary records
  // read as node levels.
  void start_workers();
  // Waits for every job in flight (they own their data) and forgets them.
  void drain();
  [[noreturn]] void fail(const std::string& message) const;
  [[noreturn]] void cannot_seek() const;

  std::string name_;
  std::unique_ptr<Input> input_;
  ReaderOptions options_;
  ParseSettings settings_;
  TraceHeader header_;
  std::optional<TraceTrailer> trailer_;
  std::shared_ptr<Stock> stock_ = std::make_shared<Stock>();
  // The units in trace order, data decoded on the workers.
  std::unique_ptr<OrderedPipeline<Unit>> pipeline_;
  std::optional<FrameMarker> pending_marker_;
  std::optional<WindowMarker> pending_window_;
  bool input_done_ = false;
  bool finished_ = false;
  std::uint64_t records_delivered_ = 0;  // records returned by next()
  std::uint64_t record_bytes_ = 0;
  std::uint64_t ignored_fields_ = 0;

 private:
  void fill_pipeline();
  // Moves the pending markers into `batch` (at the current record); false
  // when none is pending.
  bool deliver_pending(RecordBatch& batch);

  unsigned threads_ = 1;
};

}  // namespace nodetrace::formats::detail
