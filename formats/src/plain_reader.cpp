#include "plain_reader.hpp"

namespace nodetrace::formats::detail {
namespace {

constexpr std::size_t kMaxLineBytes = 1u << 20;

}  // namespace

void PlainReader::read_unit() {
  std::string bytes;
  if (!first_plain_.empty()) {
    bytes = std::move(first_plain_);
    first_plain_.clear();
  } else if (!next_plain_bytes(bytes) && carry_.empty()) {
    input_done_ = true;
    return;
  }
  const bool final = bytes.empty();
  std::string chunk = std::move(carry_);
  carry_.clear();
  chunk += bytes;
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
      Unit unit;
      std::promise<Chunk> result;
      Chunk bad = parse_chunk(chunk, settings_, *stock_);
      if (!bad.bad_record) {
        bad.bad_record = true;
        bad.record_error = {bad.records.size(), "line longer than 1 MiB"};
      }
      result.set_value(std::move(bad));
      unit.chunk = result.get_future();
      units_.push_back(std::move(unit));
      input_done_ = true;
      return;
    }
    if (chunk.empty()) return;
  }
  record_bytes_ += chunk.size();
  Unit unit;
  unit.chunk = pool_->submit([chunk = std::move(chunk), settings = settings_, stock = stock_] {
    return parse_chunk(chunk, settings, *stock);
  });
  units_.push_back(std::move(unit));
}

}  // namespace nodetrace::formats::detail
