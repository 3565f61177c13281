// Records handed from one thread to a TraceReader on another, in memory:
// the reader delivers what a reader of the container the producer would
// write delivers (its header, markers, and each record as its form reads
// back), with no text made, compressed or parsed. Or the same batches
// handed to a function on the producer's own thread, as they are made.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "nodetrace/formats/container/metadata.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"
#include "nodetrace/formats/record/record.hpp"
#include "nodetrace/formats/write/trace_writer.hpp"

namespace nodetrace::formats {

// `record` as a trace of `form` gives it back: din carries no size (4
// bytes, as Dinero IV reads it), binary no tag and no unit.
Record as_read_back(Record record, RecordForm form);

class RecordPipe {
 public:
  // `name`: the trace's name in the reader's messages; `header` and
  // `options`: what TraceWriter::create would be given for the container.
  // The producer runs at most `batches_ahead` batches ahead of the reader;
  // the reader waits for half of them (or the end) before it reads on.
  RecordPipe(std::string name, const nlohmann::json& header, const WriterOptions& options,
             std::size_t batches_ahead = 8);
  ~RecordPipe();
  RecordPipe(const RecordPipe&) = delete;
  RecordPipe& operator=(const RecordPipe&) = delete;

  // From now on (before the first write) each batch goes to `consume` on
  // the producer's thread as it is made, with no thread, queue or wake-up
  // between (its exceptions reach the producer's call); reader() then
  // serves only the header and form.
  using BatchConsumer = std::function<void(const RecordBatch&)>;
  void feed_to(BatchConsumer consume);

  // The producer's side, in trace order, from one thread.
  void begin_animation_frame(const AnimationFrameMarker& marker);
  void begin_window(const WindowMarker& marker);
  // Copies the records; waits while the reader is behind.
  void write(std::span<const Record> records);
  // The end of the records; `totals` go in the reader's trailer.
  void finish(const nlohmann::json& totals);
  // The producer stopped before the end: the reader's next() throws
  // base::IoError saying `why`.
  void fail(const std::string& why);

  // The reader's side: one reader, used from one thread, while the pipe lives.
  std::unique_ptr<TraceReader> reader();
  // The reader gave up: from now on the producer's writes are dropped.
  void stop_reading();

 private:
  class Reader;
  void push(RecordBatch&& batch);
  void write_piece(std::span<const Record> records);
  void flush_pending_markers();

  std::string name_;
  TraceHeader header_;
  RecordForm form_;
  std::size_t batches_ahead_;
  std::size_t wake_at_;  // the queue's length that wakes a waiting reader
  BatchConsumer consume_;
  // The producer's: markers waiting for the records they begin at.
  std::optional<AnimationFrameMarker> pending_marker_;
  std::optional<WindowMarker> pending_window_;
  std::uint64_t records_written_ = 0;
  // Shared, under mutex_.
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<RecordBatch> batches_;
  std::vector<std::vector<Record>> spare_;  // record memory the reader is done with
  bool finished_ = false, reading_stopped_ = false;
  std::optional<std::string> failure_;
  std::optional<TraceTrailer> trailer_;
};

}  // namespace nodetrace::formats
