// Plain zstd streams (FORMAT.md section 3, rule 2), e.g. `zstd -c t.din`:
// decompressed as they come (skippable frames skipped) and read as plain
// records. A stream that ends with a container footer is a container whose
// header magic is damaged, and is reported so.
#include <zstd.h>

#include <fmt/format.h>

#include "container/container.hpp"
#include "container/container_footer.hpp"
#include "read/plain_reader.hpp"
#include "read/reader_kinds.hpp"

namespace nodetrace::formats::detail {
namespace {

class PlainZstdReader final : public PlainReader {
 public:
  PlainZstdReader(OpenedInput opened, const ReaderOptions& options, std::string first_bytes)
      : PlainReader(std::move(opened), options), first_bytes_(std::move(first_bytes)) {
    zstd_.reset(ZSTD_createDStream());
    settings_.form = options_.form.value_or(RecordForm::Din);
    if (!options_.form) {
      // Look at the first decompressed bytes to tell din from extended din.
      if (append_plain_bytes(first_plain_)) settings_.form = detect_text_form(first_plain_);
    }
    start_workers();
  }

  std::string_view input_kind() const override { return "zstd"; }

 private:
  bool append_plain_bytes(std::string& out) override {
    const std::size_t start = out.size();
    out.resize(start + kPlainChunkBytes);
    ZSTD_outBuffer output{out.data(), out.size(), start};
    while (output.pos < output.size) {
      const std::size_t before = output.pos;
      const std::size_t available = input_->fill_some();
      if (available == 0) {
        if (tail_.size() == kFooterSize && footer_leads_to_trailer(*input_, tail_, input_->offset())) {
          fail_damaged_header_magic(name_, first_bytes_, "the stream");
        }
        if (zstd_status_ != 0) fail(fmt::format("truncated: the zstd stream ends inside a frame at byte {}", input_->offset()));
        break;
      }
      // Between frames (status 0) the next one starts here. Damage may show
      // only at the frame's end (its checksum), so an error names where the
      // frame began.
      if (zstd_status_ == 0) zstd_frame_start_ = input_->offset();
      ZSTD_inBuffer in{input_->data(), available, 0};
      zstd_status_ = ZSTD_decompressStream(zstd_.get(), &output, &in);
      if (ZSTD_isError(zstd_status_)) {
        fail(fmt::format("damaged zstd data in the zstd frame that starts at byte {} ({})", zstd_frame_start_,
                         ZSTD_getErrorName(zstd_status_)));
      }
      remember_tail(input_->data(), in.pos);
      input_->consume(in.pos);
      if (in.pos == 0 && output.pos == before) break;  // no progress: let the caller come back
    }
    out.resize(output.pos);
    return output.pos > start;
  }

  // Plain zstd streams: keeps the last bytes read, to find a container's
  // footer at the end of a stream whose header magic is damaged.
  void remember_tail(const char* data, std::size_t count) {
    tail_.append(data + (count > kFooterSize ? count - kFooterSize : 0),
                 std::min(count, kFooterSize));
    if (tail_.size() > kFooterSize) tail_.erase(0, tail_.size() - kFooterSize);
  }

  struct DStreamDeleter {
    void operator()(ZSTD_DStream* stream) const { ZSTD_freeDStream(stream); }
  };

  std::string first_bytes_;  // the input's first 4 bytes
  std::unique_ptr<ZSTD_DStream, DStreamDeleter> zstd_;
  std::size_t zstd_status_ = 0;
  std::uint64_t zstd_frame_start_ = 0;  // offset of the frame being decoded
  std::string tail_;                    // the last bytes read
};

}  // namespace

std::unique_ptr<TraceReader> open_plain_zstd_reader(OpenedInput opened, const ReaderOptions& options,
                                                    std::string first_bytes) {
  return std::make_unique<PlainZstdReader>(std::move(opened), options, std::move(first_bytes));
}

}  // namespace nodetrace::formats::detail
