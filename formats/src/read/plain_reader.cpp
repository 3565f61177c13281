#include "read/plain_reader.hpp"

namespace nodetrace::formats::detail {
namespace {

constexpr std::size_t kMaxLineBytes = 1u << 20;

}  // namespace

void PlainReader::read_decode_unit() {
  std::string chunk = std::move(carry_);
  carry_ = std::string();
  bool more = true;
  if (!first_plain_.empty()) {
    chunk += first_plain_;
    first_plain_ = std::string();
  } else {
    more = append_plain_bytes(chunk);
  }
  if (!more && chunk.empty()) {
    input_done_ = true;
    return;
  }
  const bool final = !more;
  if (!final) {
    // Parse whole records only; the rest waits for the next bytes.
    std::size_t cut;
    if (settings_.form == RecordForm::Binary) {
      cut = chunk.size() - chunk.size() % 8;
    } else {
      const std::size_t newline = chunk.rfind('\n');
      cut = newline == std::string::npos ? 0 : newline + 1;
    }
    carry_.assign(chunk, cut, std::string::npos);
    chunk.resize(cut);
    if (carry_.size() > kMaxLineBytes) {
      DecodeUnit unit;
      unit.chunk = parse_chunk(chunk, settings_, *stock_);
      if (!unit.chunk.bad_record) {
        unit.chunk.bad_record = true;
        unit.chunk.record_error = {unit.chunk.records.size(), "line longer than 1 MiB"};
      }
      pipeline_->push_ready(std::move(unit));
      input_done_ = true;
      return;
    }
    if (chunk.empty()) return;
  }
  record_bytes_ += chunk.size();
  pipeline_->submit([chunk = std::move(chunk), settings = settings_, stock = stock_] {
    DecodeUnit unit;
    unit.chunk = parse_chunk(chunk, settings, *stock);
    return unit;
  });
}

}  // namespace nodetrace::formats::detail
