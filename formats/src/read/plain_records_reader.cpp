// Plain records (FORMAT.md section 3, rule 3): din / extended din text or
// Dinero binary records with no header, read as they come.
#include <algorithm>

#include "read/plain_reader.hpp"
#include "read/reader_kinds.hpp"

namespace nodetrace::formats::detail {
namespace {

class PlainRecordsReader final : public PlainReader {
 public:
  PlainRecordsReader(OpenedInput opened, const ReaderOptions& options) : PlainReader(std::move(opened), options) {
    // Din unless the first record says extended din; binary only when named.
    if (!input_->ensure(4)) {
      settings_.form = options_.form.value_or(RecordForm::Din);
      if (input_->available() > 0 && settings_.form != RecordForm::Binary) {
        settings_.form = options_.form.value_or(
            detect_text_form(std::string_view(input_->data(), input_->available())));
      }
    } else {
      input_->fill_some();
      settings_.form = options_.form.value_or(detect_text_form(
          std::string_view(input_->data(), std::min<std::size_t>(input_->available(), 64))));
    }
    start_workers();
  }

  std::string_view input_kind() const override { return "plain"; }

 private:
  bool append_plain_bytes(std::string& out) override {
    const std::size_t available = input_->fill_some();
    if (available == 0) return false;
    const std::size_t take = std::min(available, kPlainChunkBytes);
    out.append(input_->data(), take);
    input_->consume(take);
    return true;
  }
};

}  // namespace

std::unique_ptr<TraceReader> open_plain_records_reader(OpenedInput opened, const ReaderOptions& options) {
  return std::make_unique<PlainRecordsReader>(std::move(opened), options);
}

}  // namespace nodetrace::formats::detail
