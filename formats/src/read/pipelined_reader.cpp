#include "read/pipelined_reader.hpp"

#include <fmt/format.h>

#include "nodetrace/base/error.hpp"

namespace nodetrace::formats::detail {

Chunk parse_chunk(const std::string& bytes, ParseSettings settings, Stock& stock) {
  Chunk chunk;
  chunk.records = stock.records.take();
  chunk.bad_record = !parse_records(bytes, settings, chunk.records, chunk.record_error, chunk.ignored_fields);
  chunk.kinds = record_kinds(chunk.records.data(), chunk.records.size());
  return chunk;
}

bool PieceStream::push(Chunk&& piece) {
  std::unique_lock lock(mutex_);
  room_.wait(lock, [this] { return abandoned_ || pieces_.size() < capacity_; });
  if (abandoned_) return false;
  pieces_.push_back(std::move(piece));
  if (pieces_.size() == reader_batch()) piece_ready_.notify_all();  // also wakes wait_closed, which goes back to sleep
  return true;
}

void PieceStream::close() {
  std::lock_guard lock(mutex_);
  closed_ = true;
  piece_ready_.notify_all();
}

bool PieceStream::pop(Chunk& piece) {
  std::unique_lock lock(mutex_);
  if (pieces_.empty()) piece_ready_.wait(lock, [this] { return closed_ || pieces_.size() >= reader_batch(); });
  if (pieces_.empty()) return false;
  piece = std::move(pieces_.front());
  pieces_.pop_front();
  if (pieces_.size() == capacity_ / 2) room_.notify_one();
  return true;
}

void PieceStream::abandon() {
  std::lock_guard lock(mutex_);
  abandoned_ = true;
  pieces_.clear();
  room_.notify_all();
}

void PieceStream::wait_closed() {
  std::unique_lock lock(mutex_);
  piece_ready_.wait(lock, [this] { return closed_; });
}

PipelinedReader::PipelinedReader(OpenedInput opened, const ReaderOptions& options)
    : name_(std::move(opened.name)), input_(std::move(opened.input)), options_(options) {
  threads_ = base::threads_or_cores(options_.threads);
  // Frames decoded at once: the pipeline's (fill_pipeline) and the one read.
  const std::size_t frames = std::size_t{threads_} + 2;
  stock_->records.keep_at_most(frames * (kPiecesWaiting + 1) + kBatchesHeld);
  settings_.tags_are_levels = options_.tags_are_levels;
}

PipelinedReader::~PipelinedReader() { drain(); }

void PipelinedReader::start_workers() {
  if (settings_.form == RecordForm::Binary && settings_.tags_are_levels) {
    throw base::UsageError(fmt::format("{}: binary records carry no tag, so their tags cannot be node levels", name_));
  }
  pipeline_ = std::make_unique<base::OrderedPipeline<DecodeUnit>>(threads_);
}

void PipelinedReader::fail(const std::string& message) const {
  throw base::FormatError(fmt::format("{}: {}", name_, message));
}

void PipelinedReader::cannot_seek() const {
  throw base::UsageError(fmt::format("{}: cannot seek: only a container file with an index can", name_));
}

void PipelinedReader::seek_to_record(std::uint64_t) { cannot_seek(); }

bool PipelinedReader::next(RecordBatch& batch) {
  if (batch.records.capacity() > 0) stock_->records.give(std::move(batch.records));
  batch.records.clear();
  batch.kinds = RecordKinds{};
  batch.marker.reset();
  batch.window.reset();
  for (;;) {
    fill_pipeline();
    if (streaming_) {
      Chunk piece;
      if (streaming_->stream->pop(piece)) {
        if (deliver_chunk(*streaming_, piece, batch)) return true;
        continue;
      }
      live_streams_.pop_front();  // the oldest live stream is this one
      const DecodeUnit unit = std::move(*streaming_);
      streaming_.reset();
      end_stream(unit);
      continue;
    }
    if (!pipeline_ || pipeline_->empty()) {
      if (!finished_) {
        finished_ = true;
        finish_input();
      }
      return deliver_pending(batch);
    }
    DecodeUnit unit = pipeline_->pop();
    switch (unit.kind) {
      case DecodeUnit::Kind::AnimationFrameMarker: {
        // Whatever is pending began an animation frame or window with no records.
        const bool delivered = deliver_pending(batch);
        pending_marker_ = std::move(unit.marker);
        if (delivered) return true;
        continue;
      }
      case DecodeUnit::Kind::WindowMarker: {
        const bool delivered = pending_window_ && deliver_pending(batch);  // a window with no records
        pending_window_ = std::move(unit.window);
        if (delivered) return true;
        continue;
      }
      case DecodeUnit::Kind::SkippedDataFrame: {
        // Markers that begin at the records of a skipped data frame go out
        // on their own, before the jump.
        const bool delivered = deliver_pending(batch);
        records_delivered_ += unit.entry.record_count;
        pass_skipped(unit);
        if (delivered) return true;
        continue;
      }
      case DecodeUnit::Kind::Records: break;
    }
    if (unit.stream) {
      streaming_ = std::move(unit);
      continue;
    }
    if (deliver_chunk(unit, unit.chunk, batch)) return true;
  }
}

bool PipelinedReader::deliver_chunk(const DecodeUnit& unit, Chunk& chunk, RecordBatch& batch) {
  check_chunk(unit, chunk);
  if (chunk.bad_record) {
    throw base::FormatError(fmt::format(
        "{}: record {}: {}{}", name_, records_delivered_ + chunk.record_error.record_in_chunk + 1,
        chunk.record_error.message,
        chunk.record_error.not_text
            ? fmt::format(" (the record holds a NUL byte, so the input is not text: for Dinero binary records give {})",
                          options_.binary_form_option)
            : ""));
  }
  ignored_fields_ += chunk.ignored_fields;
  if (chunk.records.empty() && !pending_marker_ && !pending_window_) {
    if (chunk.records.capacity() > 0) stock_->records.give(std::move(chunk.records));
    return false;
  }
  batch.first_record = records_delivered_;
  records_delivered_ += chunk.records.size();
  batch.records = std::move(chunk.records);
  batch.kinds = chunk.kinds;
  deliver_pending(batch);
  return true;
}

void PipelinedReader::post_stream_job(std::shared_ptr<PieceStream> stream, std::function<void()> job) {
  if (!decoders_) decoders_ = std::make_unique<base::WorkerThreads>(threads_);
  live_streams_.push_back(std::move(stream));
  decoders_->post(std::move(job));
}

bool PipelinedReader::deliver_pending(RecordBatch& batch) {
  if (!pending_marker_ && !pending_window_) return false;
  if (batch.records.empty()) batch.first_record = records_delivered_;
  batch.marker = std::move(pending_marker_);
  batch.window = std::move(pending_window_);
  pending_marker_.reset();
  pending_window_.reset();
  return true;
}

void PipelinedReader::fill_pipeline() {
  const std::size_t limit = static_cast<std::size_t>(threads_) + 1;
  while (!input_done_ && pipeline_->size() < limit) read_decode_unit();
}

void PipelinedReader::drain() {
  // Abandoned streams let their workers stop; they own what they use.
  for (const auto& stream : live_streams_) stream->abandon();
  live_streams_.clear();
  streaming_.reset();
  if (pipeline_) pipeline_->clear();
}

}  // namespace nodetrace::formats::detail
