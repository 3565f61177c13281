// What every kind of trace reader shares (internal): the in-order pipeline
// of units (data frames or text chunks decoded on worker threads, markers
// between them) and the delivery of records and markers in trace order.
// container_reader.cpp, plain_zstd_reader.cpp and plain_records_reader.cpp
// fill the pipeline from their kind of input; reader.cpp picks the kind.
#pragma once

#include <algorithm>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "read/buffers.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"
#include "codec/record_codec.hpp"
#include "nodetrace/base/ordered_pipeline.hpp"
#include "read/input.hpp"

namespace nodetrace::formats::detail {

// What a worker hands back for one data frame or text chunk.
struct Chunk {
  std::vector<Record> records;
  RecordKinds kinds;  // of the records (found on the worker, where they are in cache)
  std::uint64_t decoded_bytes = 0;   // record bytes these records came from
  bool bad_record = false;
  RecordError record_error;
  std::uint64_t ignored_fields = 0;  // records whose trailing fields were ignored
  std::string frame_error;           // damage found before parsing
};

// Pieces a data frame's worker may decode ahead of the reader
// (container_reader.cpp says why 32).
inline constexpr std::size_t kPiecesWaiting = 32;
// Batches a consumer may hold before handing them back: cachesim's sweep
// holds two groups of 2^18 records, 32 pieces.
inline constexpr std::size_t kBatchesHeld = 32;

// Buffers handed back by the consumer for the workers to reuse: as many
// record buffers as may be in use at once (pieces waiting in every frame
// the workers decode, one filling in each, the batches the consumer
// holds), so that pieces reuse memory rather than touching fresh pages
// (with 40 kept, the policy grid of 36 configurations on BART Kitchen took
// 24,700 page faults and 0.24 s of system time, with enough 18,200 and
// 0.16-0.22 s; a buffer is kept only once it was in use, so the memory held
// is that of the busiest moment).
struct Stock {
  Recycler<std::vector<Record>> records{0};  // sized by PipelinedReader
  // The ring of data frames with a large zstd window (archives): they are
  // decoded one at a time, so one ring serves them all and memory holds one
  // window, not one per worker.
  ByteBuffer large_window_ring;
};

// One data frame decoded on a worker and handed to the reader in pieces of
// a few thousand records, at most `capacity` of them waiting: the frame's
// text and records are never held whole, so memory does not grow with the
// frame (a frame is megabytes; a piece stays in the processor's cache).
class PieceStream {
 public:
  explicit PieceStream(std::size_t capacity) : capacity_(capacity) {}

  // Worker: hands over a piece, waiting for room; false once the reader has
  // abandoned the stream (the worker should stop).
  bool push(Chunk&& piece);
  // Worker: the frame is done (always called, also after an error).
  void close();
  // Reader: the next piece, waiting for it; false once the stream is closed
  // and every piece was taken.
  bool pop(Chunk& piece);
  // Reader: no more pieces wanted (drain, seek, destruction).
  void abandon();
  // Waits until the worker closed the stream.
  void wait_closed();

 private:
  // Each side sleeps until the other has done half a queue's worth (pieces
  // for the reader, room for the worker) rather than waking per piece.
  std::size_t reader_batch() const { return std::max<std::size_t>(1, capacity_ / 2); }

  std::mutex mutex_;
  std::condition_variable piece_ready_;  // the reader waits here, and wait_closed
  std::condition_variable room_;         // the worker waits here
  std::deque<Chunk> pieces_;
  std::size_t capacity_;
  bool closed_ = false;
  bool abandoned_ = false;
};

Chunk parse_chunk(const std::string& bytes, ParseSettings settings, Stock& stock);

// One item of the in-order pipeline.
struct DecodeUnit {
  enum class Kind { Records, AnimationFrameMarker, WindowMarker, SkippedDataFrame };
  Kind kind = Kind::Records;
  AnimationFrameMarker marker;
  WindowMarker window;
  Chunk chunk;  // Records: filled on a worker
  // Records decoded in pieces (containers): the chunk is then unused.
  std::shared_ptr<PieceStream> stream;
  // Containers: where the data frame is and what the index should say.
  DataFrameIndexEntry entry;
  std::uint64_t data_frame = 0;
};

// An opened input and the name errors give it (the path, or "<stdin>").
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
  unsigned units() const override { return settings_.reads_units() ? settings_.units : 1; }
  const std::optional<TraceTrailer>& trailer() const override { return trailer_; }
  std::uint64_t record_bytes() const override { return record_bytes_; }
  std::uint64_t records_with_ignored_fields() const override { return ignored_fields_; }
  bool next(RecordBatch& batch) final;
  void seek_to_record(std::uint64_t record) override;

 protected:
  // Queues the input's next unit, or sets input_done_ at its end.
  virtual void read_decode_unit() = 0;
  // Checks a data frame's chunk (or a piece of it) before its records go
  // out (containers).
  virtual void check_chunk(const DecodeUnit& unit, Chunk& chunk) { (void)unit, (void)chunk; }
  // A data frame read in pieces has delivered its last piece (containers:
  // the frame's index entry).
  virtual void end_stream(const DecodeUnit& unit) { (void)unit; }
  // Runs `job` on the stream decoders (threads_ of them, started on first
  // use), jobs starting in the order they are posted; the stream is
  // abandoned by drain().
  void post_stream_job(std::shared_ptr<PieceStream> stream, std::function<void()> job);
  // A data frame skipped by keep_data_frame, in its turn (containers).
  virtual void pass_skipped(const DecodeUnit& unit) { (void)unit; }
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
  std::unique_ptr<base::OrderedPipeline<DecodeUnit>> pipeline_;
  std::optional<AnimationFrameMarker> pending_marker_;
  std::optional<WindowMarker> pending_window_;
  bool input_done_ = false;
  bool finished_ = false;
  std::uint64_t records_delivered_ = 0;  // records returned by next()
  std::uint64_t record_bytes_ = 0;
  std::uint64_t ignored_fields_ = 0;

 private:
  void fill_pipeline();
  // Hands out a chunk or piece of `unit`: false when it carries nothing to deliver.
  bool deliver_chunk(const DecodeUnit& unit, Chunk& chunk, RecordBatch& batch);
  // Moves the pending markers into `batch` (at the current record); false
  // when none is pending.
  bool deliver_pending(RecordBatch& batch);

  unsigned threads_ = 1;
  // The data frame being delivered piece by piece, if any.
  std::optional<DecodeUnit> streaming_;
  // Streams posted and not yet finished, to abandon on drain().
  std::deque<std::shared_ptr<PieceStream>> live_streams_;
  std::unique_ptr<base::WorkerThreads> decoders_;
};

}  // namespace nodetrace::formats::detail
