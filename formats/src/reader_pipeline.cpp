#include "reader_pipeline.hpp"

#include <fmt/format.h>

#include "nodetrace/formats/error.hpp"

namespace nodetrace::formats::detail {

Chunk parse_chunk(const std::string& bytes, ParseSettings settings, Stock& stock) {
  Chunk chunk;
  chunk.records = stock.records.take();
  chunk.bad_record = !parse_records(bytes, settings, chunk.records, chunk.record_error, chunk.ignored_fields);
  return chunk;
}

PipelinedReader::PipelinedReader(OpenedInput opened, const ReaderOptions& options)
    : name_(std::move(opened.name)), input_(std::move(opened.input)), options_(options) {
  threads_ = threads_or_cores(options_.threads);
  settings_.tags_are_levels = options_.tags_are_levels;
}

PipelinedReader::~PipelinedReader() { drain(); }

void PipelinedReader::start_workers() {
  if (settings_.form == RecordForm::Binary && settings_.tags_are_levels) {
    throw UsageError(fmt::format("{}: binary records carry no tag, so their tags cannot be node levels", name_));
  }
  pipeline_ = std::make_unique<OrderedPipeline<Unit>>(threads_);
}

void PipelinedReader::fail(const std::string& message) const {
  throw FormatError(fmt::format("{}: {}", name_, message));
}

void PipelinedReader::cannot_seek() const {
  throw UsageError(fmt::format("{}: cannot seek: only a container file with an index can", name_));
}

void PipelinedReader::seek_to_record(std::uint64_t) { cannot_seek(); }

bool PipelinedReader::next(RecordBatch& batch) {
  if (batch.records.capacity() > 0) stock_->records.give(std::move(batch.records));
  batch.records.clear();
  batch.marker.reset();
  batch.window.reset();
  for (;;) {
    fill_pipeline();
    if (!pipeline_ || pipeline_->empty()) {
      if (!finished_) {
        finished_ = true;
        finish_input();
      }
      return deliver_pending(batch);
    }
    Unit unit = pipeline_->pop();
    switch (unit.kind) {
      case Unit::Kind::FrameMarker: {
        // Whatever is pending began an animation frame or window with no records.
        const bool delivered = deliver_pending(batch);
        pending_marker_ = std::move(unit.marker);
        if (delivered) return true;
        continue;
      }
      case Unit::Kind::WindowMarker: {
        const bool delivered = pending_window_ && deliver_pending(batch);  // a window with no records
        pending_window_ = std::move(unit.window);
        if (delivered) return true;
        continue;
      }
      case Unit::Kind::SkippedFrame: {
        // Markers that begin at the records of a skipped data frame go out
        // on their own, before the jump.
        const bool delivered = deliver_pending(batch);
        records_delivered_ += unit.entry.record_count;
        pass_skipped(unit);
        if (delivered) return true;
        continue;
      }
      case Unit::Kind::Records: break;
    }
    Chunk& chunk = unit.chunk;
    check_chunk(unit, chunk);
    if (chunk.bad_record) {
      throw FormatError(fmt::format("{}: record {}: {}", name_,
                                    records_delivered_ + chunk.record_error.record_in_chunk + 1,
                                    chunk.record_error.message));
    }
    ignored_fields_ += chunk.ignored_fields;
    if (chunk.records.empty() && !pending_marker_ && !pending_window_) continue;
    batch.first_record = records_delivered_;
    records_delivered_ += chunk.records.size();
    batch.records = std::move(chunk.records);
    deliver_pending(batch);
    return true;
  }
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
  const std::size_t limit = static_cast<std::size_t>(threads_) + 2;
  while (!input_done_ && pipeline_->size() < limit) read_unit();
}

void PipelinedReader::drain() {
  if (pipeline_) pipeline_->clear();
}

}  // namespace nodetrace::formats::detail
