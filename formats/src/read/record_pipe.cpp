#include "nodetrace/formats/read/record_pipe.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "nodetrace/base/error.hpp"

namespace nodetrace::formats {

Record as_read_back(Record record, RecordForm form) {
  if (form == RecordForm::Din) record.size = 4;
  if (form == RecordForm::Binary) {
    record.tag = kTagNone;
    record.unit = TraversalUnit{};
  }
  return record;
}

namespace {

// Each record as `form` gives it back, and the kinds of them all
// (record_kinds), in one pass over records the caller has just copied.
RecordKinds read_back_in_place(std::vector<Record>& records, RecordForm form) {
  if constexpr (std::endian::native == std::endian::little && sizeof(Record) == 16 &&
                offsetof(Record, size) == 8 && offsetof(Record, type) == 12 && offsetof(Record, unit) == 13 &&
                offsetof(Record, tag) == 14) {
    // The second word of a record (size, type, unit, tag) changed by a mask
    // and bits set, the same for every record: no branch per record, and
    // the kinds as record_kinds finds them (see there).
    static_assert(static_cast<unsigned>(AccessType::Misc) == 3 && kMaxLevel == 0xFFFF - 15);
    std::uint64_t keep = ~std::uint64_t{0}, set = 0;
    if (form == RecordForm::Din) {
      keep = ~std::uint64_t{0xFFFFFFFF};
      set = 4;
    } else if (form == RecordForm::Binary) {
      keep = 0x000000FFFFFFFFFF;
      set = std::uint64_t{kTagNone} << 48;
    }
    std::uint64_t types = 0, tags = 0;
    char* const bytes = reinterpret_cast<char*>(records.data());
    for (std::size_t i = 0; i < records.size(); ++i) {
      std::uint64_t word;
      std::memcpy(&word, bytes + 16 * i + 8, 8);
      word = (word & keep) | set;
      std::memcpy(bytes + 16 * i + 8, &word, 8);
      types |= word;
      tags |= (word >> 48) + 15;
    }
    types >>= 32;
    return {(types & 0xFC) == 0, (tags & 0x10000) == 0};
  } else {
    if (form != RecordForm::ExtendedDin) {
      for (Record& record : records) record = as_read_back(record, form);
    }
    return record_kinds(records.data(), records.size());
  }
}

}  // namespace

class RecordPipe::Reader final : public TraceReader {
 public:
  explicit Reader(RecordPipe& pipe) : pipe_(pipe) {}
  const std::string& source_name() const override { return pipe_.name_; }
  const TraceHeader& header() const override { return pipe_.header_; }
  RecordForm form() const override { return pipe_.form_; }
  bool tags_are_levels() const override { return pipe_.header_.tags_are_levels(); }
  unsigned units() const override { return tags_are_levels() ? pipe_.header_.units() : 1; }
  std::string_view input_kind() const override { return "container"; }

  bool next(RecordBatch& batch) override {
    std::unique_lock lock(pipe_.mutex_);
    pipe_.changed_.wait(lock, [&] { return pipe_.batches_.size() >= pipe_.wake_at_ || pipe_.finished_ || pipe_.failure_; });
    if (pipe_.failure_) throw base::IoError(fmt::format("{}: {}", pipe_.name_, *pipe_.failure_));
    if (pipe_.batches_.empty()) {
      trailer_ = pipe_.trailer_;
      return false;
    }
    // The caller's last records go back to the producer: their memory is
    // reused rather than paged in afresh for every batch.
    if (batch.records.capacity() > 0) {
      batch.records.clear();
      pipe_.spare_.push_back(std::move(batch.records));
    }
    batch = std::move(pipe_.batches_.front());
    pipe_.batches_.pop_front();
    if (pipe_.batches_.size() == pipe_.batches_ahead_ / 2) pipe_.changed_.notify_all();  // see push()
    return true;
  }

  const std::optional<TraceTrailer>& trailer() const override { return trailer_; }

  void seek_to_record(std::uint64_t) override {
    throw base::UsageError(fmt::format("{}: records handed over in memory cannot be sought", pipe_.name_));
  }

 private:
  RecordPipe& pipe_;
  std::optional<TraceTrailer> trailer_;
};

RecordPipe::RecordPipe(std::string name, const nlohmann::json& header, const WriterOptions& options,
                       std::size_t batches_ahead)
    : name_(std::move(name)),
      form_(options.form),
      batches_ahead_(std::max<std::size_t>(1, batches_ahead)),
      wake_at_(std::max<std::size_t>(1, batches_ahead_ / 2)) {
  header_.json = container_header(header, options);
}

void RecordPipe::feed_to(BatchConsumer consume) {
  if (records_written_ > 0) throw std::logic_error("RecordPipe::feed_to after the first write");
  consume_ = std::move(consume);
}

RecordPipe::~RecordPipe() = default;

std::unique_ptr<TraceReader> RecordPipe::reader() { return std::make_unique<Reader>(*this); }

// Each side sleeps until the other has done half the queue's worth, and is
// woken only then: a wake-up per batch (a reader faster than the render
// waits for every batch) cost the in-render simulation more CPU than
// copying the records.
void RecordPipe::push(RecordBatch&& batch) {
  if (consume_) {
    consume_(batch);
    if (batch.records.capacity() > 0) {
      batch.records.clear();
      spare_.push_back(std::move(batch.records));  // no lock: one thread
    }
    return;
  }
  std::unique_lock lock(mutex_);
  if (batches_.size() >= batches_ahead_) {
    changed_.wait(lock, [&] { return batches_.size() <= batches_ahead_ / 2 || reading_stopped_; });
  }
  if (reading_stopped_) return;
  batches_.push_back(std::move(batch));
  if (batches_.size() == wake_at_) changed_.notify_all();
}

// A marker with no records after it before the next marker or the end
// travels on an empty batch, as a container reader delivers it.
void RecordPipe::flush_pending_markers() {
  if (!pending_marker_ && !pending_window_) return;
  RecordBatch batch;
  batch.marker = std::exchange(pending_marker_, std::nullopt);
  batch.window = std::exchange(pending_window_, std::nullopt);
  batch.first_record = records_written_;
  push(std::move(batch));
}

void RecordPipe::begin_animation_frame(const AnimationFrameMarker& marker) {
  flush_pending_markers();
  pending_marker_ = marker;
}

void RecordPipe::begin_window(const WindowMarker& marker) {
  if (pending_window_) flush_pending_markers();
  pending_window_ = marker;
}

void RecordPipe::write(std::span<const Record> records) {
  // In pieces of a container's decoded size: the reader's simulation then
  // finds each piece in cache, and the pieces in flight are few and of one
  // size, so their memory is reused rather than paged in afresh.
  constexpr std::size_t kPieceRecords = std::size_t{1} << 14;
  for (std::size_t begin = 0; begin < records.size(); begin += kPieceRecords) {
    write_piece(records.subspan(begin, std::min(kPieceRecords, records.size() - begin)));
  }
}

void RecordPipe::write_piece(std::span<const Record> records) {
  RecordBatch batch;
  batch.marker = std::exchange(pending_marker_, std::nullopt);
  batch.window = std::exchange(pending_window_, std::nullopt);
  batch.first_record = records_written_;
  {
    std::lock_guard lock(mutex_);
    if (!spare_.empty()) {
      batch.records = std::move(spare_.back());
      spare_.pop_back();
    }
  }
  batch.records.assign(records.begin(), records.end());
  // As a container's decoding workers do: the simulator then skips its own pass.
  batch.kinds = read_back_in_place(batch.records, form_);
  records_written_ += records.size();
  push(std::move(batch));
}

void RecordPipe::finish(const nlohmann::json& totals) {
  flush_pending_markers();
  TraceTrailer trailer;
  trailer.totals = totals;
  trailer.totals["records"] = records_written_;
  std::lock_guard lock(mutex_);
  trailer_ = std::move(trailer);
  finished_ = true;
  changed_.notify_all();
}

void RecordPipe::fail(const std::string& why) {
  std::lock_guard lock(mutex_);
  failure_ = why;
  changed_.notify_all();
}

void RecordPipe::stop_reading() {
  std::lock_guard lock(mutex_);
  reading_stopped_ = true;
  batches_.clear();
  spare_.clear();
  changed_.notify_all();
}

}  // namespace nodetrace::formats
