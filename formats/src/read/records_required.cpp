#include "read/records_required.hpp"

#include <fmt/format.h>

#include "nodetrace/base/error.hpp"

namespace nodetrace::formats::detail {

namespace {

class RecordsRequired final : public TraceReader {
 public:
  explicit RecordsRequired(std::unique_ptr<TraceReader> reader) : reader_(std::move(reader)) {}

  const std::string& source_name() const override { return reader_->source_name(); }
  const TraceHeader& header() const override { return reader_->header(); }
  RecordForm form() const override { return reader_->form(); }
  bool tags_are_levels() const override { return reader_->tags_are_levels(); }
  unsigned units() const override { return reader_->units(); }
  bool next(RecordBatch& batch) override {
    if (reader_->next(batch)) {
      any_records_ = any_records_ || !batch.records.empty();
      return true;
    }
    if (!any_records_ && reader_->data_frames_skipped() == 0) {
      fail_no_records(source_name());
    }
    return false;
  }
  const std::optional<TraceTrailer>& trailer() const override { return reader_->trailer(); }
  void seek_to_record(std::uint64_t record) override {
    reader_->seek_to_record(record);
    any_records_ = true;  // what came before the seek is not this reader's to judge
  }
  std::uint64_t record_bytes() const override { return reader_->record_bytes(); }
  std::uint64_t records_with_ignored_fields() const override { return reader_->records_with_ignored_fields(); }
  std::string_view input_kind() const override { return reader_->input_kind(); }
  std::uint64_t data_frames_decompressed() const override { return reader_->data_frames_decompressed(); }
  std::uint64_t data_frames_skipped() const override { return reader_->data_frames_skipped(); }

 private:
  std::unique_ptr<TraceReader> reader_;
  bool any_records_ = false;
};

}  // namespace

void fail_no_records(const std::string& source_name) {
  throw base::FormatError(fmt::format("{}: no records: an input without records is not a trace{}", source_name,
                                      source_name == "<stdin>" ? " (did the command before the pipe fail?)" : ""));
}

std::unique_ptr<TraceReader> records_required(std::unique_ptr<TraceReader> reader) {
  return std::make_unique<RecordsRequired>(std::move(reader));
}

}  // namespace nodetrace::formats::detail
