#define ZSTD_STATIC_LINKING_ONLY  // ZSTD_getFrameHeader, ZSTD_decompressBound
#include "nodetrace/formats/reader.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <xxhash.h>
#include <zstd.h>

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <deque>
#include <future>

#include "container.hpp"
#include "nodetrace/formats/error.hpp"
#include "text_codec.hpp"
#include "thread_pool.hpp"

namespace nodetrace::formats {

TraceReader::~TraceReader() = default;

namespace {

using detail::load_le32;
using detail::load_le64;

constexpr std::size_t kPlainChunkBytes = 4u << 20;  // bytes parsed per job for plain input
constexpr std::size_t kMaxLineBytes = 1u << 20;

// A file or standard input, read through a sliding buffer.
class Input {
 public:
  Input(const std::string& path, const std::string& name) : name_(name) {
    if (path == "-") {
      fd_ = 0;
    } else {
      fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
      if (fd_ < 0) throw IoError(fmt::format("{}: cannot open: {}", name_, std::strerror(errno)));
      owned_ = true;
      struct stat info {};
      if (::fstat(fd_, &info) == 0 && S_ISREG(info.st_mode)) {
        seekable_ = true;
        size_ = static_cast<std::uint64_t>(info.st_size);
      } else if (S_ISDIR(info.st_mode)) {
        ::close(fd_);
        throw IoError(fmt::format("{}: is a directory", name_));
      }
    }
  }
  ~Input() {
    if (owned_) ::close(fd_);
  }
  Input(const Input&) = delete;
  Input& operator=(const Input&) = delete;

  bool seekable() const { return seekable_; }
  std::uint64_t size() const { return size_; }
  // File offset of the first available byte.
  std::uint64_t offset() const { return offset_; }
  const char* data() const { return buffer_.data() + begin_; }
  std::size_t available() const { return end_ - begin_; }
  bool at_end() { return !ensure(1); }

  // Makes `count` bytes available; false when the input ends first.
  bool ensure(std::size_t count) {
    if (available() >= count) return true;
    if (eof_) return false;
    if (begin_ > 0) {
      std::memmove(buffer_.data(), buffer_.data() + begin_, available());
      end_ -= begin_;
      begin_ = 0;
    }
    // 1 MiB, or less for a smaller file (a whole small file in one read
    // without touching a megabyte of pages).
    const std::size_t least = seekable_ ? static_cast<std::size_t>(std::clamp<std::uint64_t>(size_ + 1, 4096, 1u << 20))
                                        : std::size_t{1} << 20;
    if (buffer_.size() < least) buffer_.resize(least);
    while (end_ < count && !eof_) {
      // Grown as bytes arrive, never to a size only claimed: a damaged
      // length field costs no more memory than the bytes that are there.
      if (end_ == buffer_.size()) buffer_.resize(std::min(count, buffer_.size() * 2));
      std::size_t want = buffer_.size() - end_;
      if (read_limit_ != 0) {  // read ahead no further than the limit unless `count` needs it
        const std::uint64_t position = offset_ + (end_ - begin_);
        const std::uint64_t room = read_limit_ > position ? read_limit_ - position : 0;
        want = static_cast<std::size_t>(std::min<std::uint64_t>(want, std::max<std::uint64_t>(room, count - end_)));
      }
      const ssize_t got = ::read(fd_, buffer_.data() + end_, want);
      if (got < 0) {
        if (errno == EINTR) continue;
        throw IoError(fmt::format("{}: read error: {}", name_, std::strerror(errno)));
      }
      if (got == 0) eof_ = true;
      end_ += static_cast<std::size_t>(got);
    }
    return available() >= count;
  }

  // Reads whatever comes next (at least one byte unless at the end).
  std::size_t fill_some() {
    if (!ensure(1)) return 0;
    if (!eof_ && available() < buffer_.size() / 2) ensure(std::min(buffer_.size(), available() + 1));
    return available();
  }

  void consume(std::size_t count) {
    begin_ += count;
    offset_ += count;
  }

  // Moves `count` bytes on, reading none of them that are not already read.
  void skip(std::uint64_t count) {
    if (count <= available()) {
      consume(static_cast<std::size_t>(count));
    } else {
      seek(offset_ + count);
    }
  }

  // Reads ahead stop at file offset `position` (0: no limit), so bytes that
  // will be skipped are not read.
  void limit_reads_to(std::uint64_t position) { read_limit_ = position; }

  // Reads `count` bytes at `position` without disturbing the stream.
  std::string read_at(std::uint64_t position, std::size_t count) const {
    std::string bytes(count, '\0');
    std::size_t done = 0;
    while (done < count) {
      const ssize_t got = ::pread(fd_, bytes.data() + done, count - done, static_cast<off_t>(position + done));
      if (got < 0 && errno == EINTR) continue;
      if (got <= 0) throw IoError(fmt::format("{}: read error at byte {}", name_, position + done));
      done += static_cast<std::size_t>(got);
    }
    return bytes;
  }

  void seek(std::uint64_t position) {
    if (::lseek(fd_, static_cast<off_t>(position), SEEK_SET) < 0) {
      throw IoError(fmt::format("{}: cannot seek: {}", name_, std::strerror(errno)));
    }
    begin_ = end_ = 0;
    offset_ = position;
    eof_ = false;
  }

 private:
  std::string name_;
  int fd_ = -1;
  bool owned_ = false;
  bool seekable_ = false;
  std::uint64_t size_ = 0;
  std::vector<char> buffer_;
  std::size_t begin_ = 0, end_ = 0;
  std::uint64_t offset_ = 0;
  std::uint64_t read_limit_ = 0;
  bool eof_ = false;
};

// What a worker hands back for one data frame or text chunk.
struct Chunk {
  std::vector<Record> records;
  detail::ByteBuffer bytes;  // the decompressed record bytes (containers: hashed in order)
  bool bad_record = false;
  detail::RecordError record_error;
  std::uint64_t ignored_fields = 0;  // records whose trailing fields were ignored
  std::string frame_error;  // damage found before parsing
};

struct Stock {
  detail::Recycler<detail::ByteBuffer> bytes{16};
  detail::Recycler<std::vector<Record>> records{16};
};

Chunk parse_chunk(const std::string& bytes, detail::ParseSettings settings, Stock& stock) {
  Chunk chunk;
  chunk.records = stock.records.take();
  chunk.bad_record = !detail::parse_records(bytes, settings, chunk.records, chunk.record_error, chunk.ignored_fields);
  return chunk;
}

Chunk decode_data_frame(const std::string& frame, detail::ParseSettings settings, Stock& stock) {
  Chunk chunk;
  ZSTD_frameHeader header{};
  const std::size_t status = ZSTD_getFrameHeader(&header, frame.data(), frame.size());
  if (ZSTD_isError(status) || status != 0) {
    chunk.frame_error = "damaged zstd frame header";
    return chunk;
  }
  if (header.frameContentSize == ZSTD_CONTENTSIZE_UNKNOWN || !header.checksumFlag) {
    chunk.frame_error = "a data frame must record its content size and checksum";
    return chunk;
  }
  const unsigned long long bound = ZSTD_decompressBound(frame.data(), frame.size());
  if (bound == ZSTD_CONTENTSIZE_ERROR || header.frameContentSize > bound) {
    chunk.frame_error = "damaged zstd frame (content size does not match its blocks)";
    return chunk;
  }
  detail::ByteBuffer bytes = stock.bytes.take();
  bytes.resize(header.frameContentSize);
  thread_local std::unique_ptr<ZSTD_DCtx, decltype(&ZSTD_freeDCtx)> context(ZSTD_createDCtx(), &ZSTD_freeDCtx);
  const std::size_t size = ZSTD_decompressDCtx(context.get(), bytes.data(), bytes.size(), frame.data(), frame.size());
  if (ZSTD_isError(size)) {
    chunk.frame_error = fmt::format("damaged zstd frame ({})", ZSTD_getErrorName(size));
    return chunk;
  }
  if (size != bytes.size()) {
    chunk.frame_error = "damaged zstd frame (wrong content size)";
    return chunk;
  }
  if (!bytes.empty()) {
    const bool whole = settings.form == RecordForm::Binary ? bytes.size() % 8 == 0 : bytes.data()[bytes.size() - 1] == '\n';
    if (!whole) {
      chunk.frame_error = "data frame does not end at a record boundary";
      return chunk;
    }
  }
  chunk.records = stock.records.take();
  chunk.bad_record =
      !detail::parse_records(bytes.view(), settings, chunk.records, chunk.record_error, chunk.ignored_fields);
  chunk.bytes = std::move(bytes);
  return chunk;
}

// One item of the in-order pipeline.
struct Unit {
  enum class Kind { Records, FrameMarker, WindowMarker, SkippedFrame };
  Kind kind = Kind::Records;
  FrameMarker marker;
  WindowMarker window;
  std::future<Chunk> chunk;
  // Containers: where the data frame is and what the index should say.
  FrameIndexEntry entry;
  std::uint64_t data_frame = 0;
};

enum class Mode { Container, PlainZstd, PlainRaw };

class Reader final : public TraceReader {
 public:
  Reader(const std::string& path, const ReaderOptions& options)
      : name_(path == "-" ? "<stdin>" : path), input_(path, name_), options_(options) {
    open();
  }

  ~Reader() override { drain(); }

  const std::string& source_name() const override { return name_; }
  const TraceHeader& header() const override { return header_; }
  RecordForm form() const override { return settings_.form; }
  bool tags_are_levels() const override { return settings_.tags_are_levels; }
  const std::optional<TraceTrailer>& trailer() const override { return trailer_; }
  std::uint64_t record_bytes() const override { return record_bytes_; }
  std::uint64_t records_with_ignored_fields() const override { return ignored_fields_; }
  std::uint64_t data_frames_decompressed() const override { return data_frames_decompressed_; }
  std::uint64_t data_frames_skipped() const override { return data_frames_skipped_; }
  std::string_view input_kind() const override {
    return mode_ == Mode::Container ? "container" : mode_ == Mode::PlainZstd ? "zstd" : "plain";
  }

  bool next(RecordBatch& batch) override {
    if (batch.records.capacity() > 0) stock_->records.give(std::move(batch.records));
    batch.records.clear();
    batch.marker.reset();
    batch.window.reset();
    for (;;) {
      fill_pipeline();
      if (units_.empty()) {
        if (!finished_) finish();
        return deliver_pending(batch);
      }
      // Markers that begin at the records of a skipped data frame go out on
      // their own, before the jump.
      if (units_.front().kind == Unit::Kind::SkippedFrame && deliver_pending(batch)) return true;
      Unit unit = std::move(units_.front());
      units_.pop_front();
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
        case Unit::Kind::SkippedFrame:
          records_read_ += unit.entry.record_count;
          records_delivered_ += unit.entry.record_count;
          seen_.push_back(unit.entry);
          ++data_frames_skipped_;
          continue;
        case Unit::Kind::Records: break;
      }
      Chunk chunk = unit.chunk.get();
      if (mode_ == Mode::Container) check_data_frame(unit, chunk);
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

  void seek_to_record(std::uint64_t record) override {
    if (mode_ != Mode::Container || !input_.seekable() || !trailer_) {
      throw UsageError(fmt::format("{}: cannot seek: only a container file with an index can", name_));
    }
    const auto& index = trailer_->index;
    auto found = std::find_if(index.begin(), index.end(), [&](const FrameIndexEntry& entry) {
      return record >= entry.first_record && record < entry.first_record + entry.record_count;
    });
    if (found == index.end()) {
      throw UsageError(fmt::format("{}: record {} is beyond the trace's {} records", name_, record,
                                   index.empty() ? 0 : index.back().first_record + index.back().record_count));
    }
    drain();
    input_.seek(found->offset);
    data_frames_ = static_cast<std::uint64_t>(found - index.begin());
    next_skip_ = static_cast<std::size_t>(data_frames_);
    records_read_ = records_delivered_ = found->first_record;
    pending_marker_.reset();
    pending_window_.reset();
    markers_ = found->animation_frame + 1;
    hashes_valid_ = false;
    saw_trailer_ = false;
    finished_ = false;
    input_done_ = false;
  }

 private:
  [[noreturn]] void fail(const std::string& message) const {
    throw FormatError(fmt::format("{}: {}", name_, message));
  }

  // Moves the pending markers into `batch` (at the current record); false
  // when none is pending.
  bool deliver_pending(RecordBatch& batch) {
    if (!pending_marker_ && !pending_window_) return false;
    if (batch.records.empty()) batch.first_record = records_delivered_;
    batch.marker = std::move(pending_marker_);
    batch.window = std::move(pending_window_);
    pending_marker_.reset();
    pending_window_.reset();
    return true;
  }

  void open() {
    threads_ = detail::default_threads(options_.threads);
    settings_.tags_are_levels = options_.tags_are_levels;
    if (!input_.ensure(4)) {
      mode_ = Mode::PlainRaw;
      settings_.form = options_.form.value_or(RecordForm::Din);
      if (input_.available() > 0 && settings_.form != RecordForm::Binary) {
        settings_.form = options_.form.value_or(
            detail::detect_text_form(std::string_view(input_.data(), input_.available())));
      }
    } else {
      const std::uint32_t magic = load_le32(input_.data());
      first_bytes_.assign(input_.data(), 4);
      if (magic != detail::kHeaderMagic && input_.seekable() && ends_with_container_footer()) {
        fail_damaged_header_magic("the file");
      }
      if (magic == detail::kHeaderMagic) {
        mode_ = Mode::Container;
        open_container();
      } else if (magic == detail::kZstdMagic || (magic & detail::kSkippableMask) == detail::kHeaderMagic) {
        mode_ = Mode::PlainZstd;
        zstd_.reset(ZSTD_createDStream());
        settings_.form = options_.form.value_or(RecordForm::Din);
        if (!options_.form) {
          // Look at the first decompressed bytes to tell din from extended din.
          if (next_plain_bytes(first_plain_)) settings_.form = detail::detect_text_form(first_plain_);
        }
      } else {
        mode_ = Mode::PlainRaw;
        input_.fill_some();
        settings_.form = options_.form.value_or(detail::detect_text_form(
            std::string_view(input_.data(), std::min<std::size_t>(input_.available(), 64))));
      }
    }
    if (settings_.form == RecordForm::Binary && settings_.tags_are_levels) {
      throw UsageError(fmt::format("{}: binary records carry no tag, so their tags cannot be node levels", name_));
    }
    pool_ = std::make_unique<detail::ThreadPool>(threads_);
  }

  // True when the last bytes of the (seekable) file are a container footer
  // leading to a trailer frame: the file is a container, whatever its first
  // bytes say.
  bool ends_with_container_footer() {
    const std::uint64_t size = input_.size();
    if (size < detail::kSkippableHeaderSize + detail::kFooterSize) return false;
    return footer_leads_to_trailer(input_.read_at(size - detail::kFooterSize, detail::kFooterSize), size);
  }

  bool footer_leads_to_trailer(std::string_view footer, std::uint64_t size) {
    if (load_le32(footer.data() + 16) != detail::kFooterMagic || load_le32(footer.data() + 12) != detail::kContainerVersion) {
      return false;
    }
    const std::uint64_t json_size = load_le32(footer.data() + 8);
    if (!input_.seekable()) return true;  // a stream cannot look back; the footer's magic and version say enough
    if (json_size + detail::kFooterSize + detail::kSkippableHeaderSize > size) return false;
    const std::string frame = input_.read_at(size - detail::kFooterSize - json_size - detail::kSkippableHeaderSize,
                                             detail::kSkippableHeaderSize);
    return load_le32(frame.data()) == detail::kTrailerMagic && load_le32(frame.data() + 4) == json_size + detail::kFooterSize;
  }

  // A container whose header magic (bytes 0-3) is damaged: names the first
  // byte that differs from 50 2A 4D 18.
  [[noreturn]] void fail_damaged_header_magic(const char* what) const {
    std::string expected;
    detail::append_le32(expected, detail::kHeaderMagic);
    std::size_t byte = 0;
    while (byte + 1 < expected.size() && first_bytes_[byte] == expected[byte]) ++byte;
    fail(fmt::format("damaged container: byte {} is {:#04x} where the header magic 50 2A 4D 18 has {:#04x} ({} ends "
                     "with a container trailer)",
                     byte, static_cast<unsigned char>(first_bytes_[byte]), static_cast<unsigned char>(expected[byte]),
                     what));
  }

  // Plain zstd streams: keeps the last bytes read, to find a container's
  // footer at the end of a stream whose header magic is damaged.
  void remember_tail(const char* data, std::size_t count) {
    tail_.append(data + (count > detail::kFooterSize ? count - detail::kFooterSize : 0),
                 std::min(count, detail::kFooterSize));
    if (tail_.size() > detail::kFooterSize) tail_.erase(0, tail_.size() - detail::kFooterSize);
  }

  // Reads one whole skippable frame at the current position into `payload`.
  void read_skippable(std::string& payload, const char* what) {
    if (!input_.ensure(detail::kSkippableHeaderSize)) fail(fmt::format("truncated: {} at byte {} is cut short", what, input_.offset()));
    const std::uint32_t size = load_le32(input_.data() + 4);
    if (!input_.ensure(detail::kSkippableHeaderSize + size)) {
      fail(fmt::format("truncated: {} at byte {} is cut short", what, input_.offset()));
    }
    payload.assign(input_.data() + detail::kSkippableHeaderSize, size);
    consume_hashed(detail::kSkippableHeaderSize + size);
  }

  void consume_hashed(std::size_t count) {
    XXH64_update(content_hash_.get(), input_.data(), count);
    input_.consume(count);
  }

  void open_container() {
    XXH64_reset(content_hash_.get(), 0);
    XXH64_reset(record_hash_.get(), 0);
    std::string payload;
    read_skippable(payload, "header");
    try {
      header_.json = nlohmann::json::parse(payload);
    } catch (const nlohmann::json::exception& error) {
      fail(fmt::format("header is not valid JSON ({})", error.what()));
    }
    if (!header_.json.is_object()) fail("header is not a JSON object");
    const auto container = header_.json.find("container");
    if (container == header_.json.end() || !container->is_object() || !container->contains("name") ||
        (*container)["name"] != detail::kContainerName || !(*container)["version"].is_number_unsigned()) {
      fail(fmt::format("header does not name the container (\"container\": {{\"name\": \"{}\", \"version\": N}})",
                       detail::kContainerName));
    }
    const auto version = (*container)["version"].get<std::uint64_t>();
    if (version != detail::kContainerVersion) {
      fail(fmt::format("container version {} is not one this reader knows ({})", version, detail::kContainerVersion));
    }
    const auto form = header_.form();
    if (!form) fail("header's \"records\" is not din, xdin or binary");
    // "tag" is "node-level" or absent; a "node-level" under another key is a
    // damaged "tag" (which would make the levels look like no tags at all).
    const auto tag = header_.json.find("tag");
    if (tag != header_.json.end() && !header_.tags_are_levels()) {
      fail(fmt::format("damaged header: \"tag\" is {}, not \"node-level\"", tag->dump()));
    }
    for (const auto& [key, value] : header_.json.items()) {
      if (key != "tag" && value == "node-level") {
        fail(fmt::format("damaged header: key \"{}\" holds \"node-level\", the value of \"tag\"", key));
      }
    }
    settings_.form = *form;
    settings_.tags_are_levels = options_.tags_are_levels || header_.tags_are_levels();
    header_end_ = input_.offset();
    if (input_.seekable() && header_.announces_trailer()) trailer_ = read_trailer_from_end();
    if (input_.seekable() && trailer_ && options_.keep_data_frame) {
      skip_.reserve(trailer_->index.size());
      for (const FrameIndexEntry& entry : trailer_->index) skip_.push_back(!options_.keep_data_frame(entry));
    }
  }

  TraceTrailer read_trailer_from_end() {
    const std::uint64_t size = input_.size();
    const auto missing = [&](const std::string& why) {
      fail(fmt::format("truncated or damaged: no valid trailer at the end of the file ({})", why));
    };
    if (size < header_end_ + detail::kSkippableHeaderSize + detail::kFooterSize) missing("file too short");
    const std::string footer = input_.read_at(size - detail::kFooterSize, detail::kFooterSize);
    if (load_le32(footer.data() + 16) != detail::kFooterMagic) missing("no footer magic");
    if (load_le32(footer.data() + 12) != detail::kContainerVersion) missing("footer version is not 1");
    const std::uint64_t json_size = load_le32(footer.data() + 8);
    if (json_size + detail::kFooterSize + detail::kSkippableHeaderSize > size - header_end_) {
      missing("footer's length runs past the header");
    }
    const std::uint64_t start = size - detail::kFooterSize - json_size - detail::kSkippableHeaderSize;
    const std::string frame_header = input_.read_at(start, detail::kSkippableHeaderSize);
    if (load_le32(frame_header.data()) != detail::kTrailerMagic ||
        load_le32(frame_header.data() + 4) != json_size + detail::kFooterSize) {
      missing("the footer's length does not lead to the trailer frame");
    }
    const std::string json = input_.read_at(start + detail::kSkippableHeaderSize, json_size);
    if (XXH64(json.data(), json.size(), 0) != load_le64(footer.data())) missing("trailer hash mismatch");
    try {
      return detail::decode_trailer_json(json);
    } catch (const FormatError& error) {
      fail(error.what());
    }
  }

  void fill_pipeline() {
    const std::size_t limit = static_cast<std::size_t>(threads_) + 2;
    while (!input_done_ && units_.size() < limit) {
      switch (mode_) {
        case Mode::Container: read_container_unit(); break;
        case Mode::PlainZstd:
        case Mode::PlainRaw: read_plain_unit(); break;
      }
    }
  }

  void read_container_unit() {
    if (skip_data_frame_here()) return;
    if (input_.at_end()) {
      input_done_ = true;
      return;
    }
    const std::uint64_t offset = input_.offset();
    if (!input_.ensure(4)) fail(fmt::format("truncated: stray bytes at byte {}", offset));
    const std::uint32_t magic = load_le32(input_.data());
    if (magic == detail::kZstdMagic) {
      std::size_t size = 0;
      for (std::size_t want = 1u << 16;; want *= 2) {
        input_.ensure(want);
        size = ZSTD_findFrameCompressedSize(input_.data(), input_.available());
        if (!ZSTD_isError(size)) break;
        if (input_.available() < want) {  // the whole rest of the input is not a whole frame
          fail(fmt::format("truncated or damaged: data frame {} at byte {} is incomplete ({})", data_frames_ + 1,
                           offset, ZSTD_getErrorName(size)));
        }
      }
      Unit unit;
      unit.data_frame = data_frames_++;
      unit.entry.offset = offset;
      unit.entry.compressed_size = size;
      unit.entry.animation_frame = markers_ == 0 ? 0 : markers_ - 1;
      unit.entry.checksum = size >= 4 ? load_le32(input_.data() + size - 4) : 0;
      std::string frame(input_.data(), size);
      consume_hashed(size);
      unit.chunk = pool_->submit([frame = std::move(frame), settings = settings_, stock = stock_] {
        return decode_data_frame(frame, settings, *stock);
      });
      units_.push_back(std::move(unit));
      return;
    }
    if ((magic & detail::kSkippableMask) != detail::kHeaderMagic) {
      fail(fmt::format("damaged: bytes at byte {} are not a zstd frame (magic {:#010x})", offset, magic));
    }
    if (magic == detail::kTrailerMagic) {
      read_stream_trailer(offset);
      return;
    }
    const char* what = magic == detail::kMarkerMagic   ? "animation frame marker"
                       : magic == detail::kWindowMagic ? "sample window marker"
                                                       : "skippable frame";
    std::string payload;
    read_skippable(payload, what);
    if (magic == detail::kHeaderMagic) fail(fmt::format("a second header at byte {}", offset));
    if (magic != detail::kMarkerMagic && magic != detail::kWindowMagic) return;  // someone else's skippable frame
    Unit unit;
    try {
      const nlohmann::json json = nlohmann::json::parse(payload);
      if (magic == detail::kMarkerMagic) {
        unit.kind = Unit::Kind::FrameMarker;
        unit.marker = FrameMarker::from_json(json);
      } else {
        unit.kind = Unit::Kind::WindowMarker;
        unit.window = WindowMarker::from_json(json);
      }
    } catch (const nlohmann::json::exception& error) {
      fail(fmt::format("{} at byte {} is not valid JSON ({})", what, offset, error.what()));
    } catch (const FormatError& error) {
      fail(fmt::format("at byte {}: {}", offset, error.what()));
    }
    if (unit.kind == Unit::Kind::FrameMarker) ++markers_;
    units_.push_back(std::move(unit));
  }

  // keep_data_frame: when the index's next data frame starts here and is not
  // kept, steps over it (nothing read, nothing decompressed) and queues its
  // place; otherwise keeps reads ahead from running into the next skipped one.
  bool skip_data_frame_here() {
    if (skip_.empty()) return false;
    const auto& index = trailer_->index;
    while (next_skip_ < skip_.size() && (!skip_[next_skip_] || next_skip_ < data_frames_)) ++next_skip_;
    input_.limit_reads_to(next_skip_ < skip_.size() ? index[next_skip_].offset : 0);
    if (next_skip_ != data_frames_ || index[data_frames_].offset != input_.offset()) return false;
    const FrameIndexEntry& entry = index[data_frames_];
    if (entry.compressed_size == 0 || entry.offset + entry.compressed_size > input_.size()) {
      fail(fmt::format("damaged index: data frame {} at byte {} of {} bytes runs past the end of the file",
                       data_frames_ + 1, entry.offset, entry.compressed_size));
    }
    Unit unit;
    unit.kind = Unit::Kind::SkippedFrame;
    unit.entry = entry;
    unit.data_frame = data_frames_++;
    input_.skip(entry.compressed_size);
    skipped_bytes_ = true;
    units_.push_back(std::move(unit));
    return true;
  }

  void read_stream_trailer(std::uint64_t offset) {
    if (!input_.ensure(detail::kSkippableHeaderSize)) fail(fmt::format("truncated: trailer at byte {}", offset));
    const std::uint32_t size = load_le32(input_.data() + 4);
    if (size < detail::kFooterSize || !input_.ensure(detail::kSkippableHeaderSize + size)) {
      fail(fmt::format("truncated: trailer at byte {} is cut short", offset));
    }
    const char* footer = input_.data() + detail::kSkippableHeaderSize + size - detail::kFooterSize;
    const std::string_view json(input_.data() + detail::kSkippableHeaderSize, size - detail::kFooterSize);
    if (load_le32(footer + 16) != detail::kFooterMagic || load_le32(footer + 12) != detail::kContainerVersion ||
        load_le32(footer + 8) != json.size() || XXH64(json.data(), json.size(), 0) != load_le64(footer)) {
      fail(fmt::format("damaged trailer at byte {} (footer does not match)", offset));
    }
    TraceTrailer trailer;
    try {
      trailer = detail::decode_trailer_json(json);
    } catch (const FormatError& error) {
      fail(error.what());
    }
    stream_content_hash_ = XXH64_digest(content_hash_.get());
    input_.consume(detail::kSkippableHeaderSize + size);
    if (!input_.at_end()) fail(fmt::format("unexpected bytes after the trailer at byte {}", input_.offset()));
    if (trailer_ && !(trailer_->index == trailer.index)) fail("the trailer read from the end differs from the stream's");
    if (!trailer_) trailer_ = std::move(trailer);
    saw_trailer_ = true;
    input_done_ = true;
  }

  // Plain input: the next run of decompressed or raw bytes; false at the end.
  bool next_plain_bytes(std::string& out) {
    out.clear();
    if (mode_ == Mode::PlainRaw) {
      const std::size_t available = input_.fill_some();
      if (available == 0) return false;
      const std::size_t take = std::min(available, kPlainChunkBytes);
      out.assign(input_.data(), take);
      input_.consume(take);
      return true;
    }
    out.resize(kPlainChunkBytes);
    ZSTD_outBuffer output{out.data(), out.size(), 0};
    while (output.pos < output.size) {
      const std::size_t before = output.pos;
      const std::size_t available = input_.fill_some();
      if (available == 0) {
        if (tail_.size() == detail::kFooterSize && footer_leads_to_trailer(tail_, input_.offset())) {
          fail_damaged_header_magic("the stream");
        }
        if (zstd_status_ != 0) fail(fmt::format("truncated: the zstd stream ends inside a frame at byte {}", input_.offset()));
        break;
      }
      // Between frames (status 0) the next one starts here. Damage may show
      // only at the frame's end (its checksum), so an error names where the
      // frame began.
      if (zstd_status_ == 0) zstd_frame_start_ = input_.offset();
      ZSTD_inBuffer in{input_.data(), available, 0};
      zstd_status_ = ZSTD_decompressStream(zstd_.get(), &output, &in);
      if (ZSTD_isError(zstd_status_)) {
        fail(fmt::format("damaged zstd data in the zstd frame that starts at byte {} ({})", zstd_frame_start_,
                         ZSTD_getErrorName(zstd_status_)));
      }
      remember_tail(input_.data(), in.pos);
      input_.consume(in.pos);
      if (in.pos == 0 && output.pos == before) break;  // no progress: let the caller come back
    }
    out.resize(output.pos);
    return !out.empty();
  }

  void read_plain_unit() {
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

  void check_data_frame(const Unit& unit, Chunk& chunk) {
    const std::string where = fmt::format("data frame {} at byte {}", unit.data_frame + 1, unit.entry.offset);
    if (!chunk.frame_error.empty()) fail(fmt::format("{}: {}", where, chunk.frame_error));
    FrameIndexEntry seen = unit.entry;
    seen.first_record = records_read_;
    seen.record_count = chunk.records.size();
    records_read_ += seen.record_count;
    record_bytes_ += chunk.bytes.size();
    ++data_frames_decompressed_;
    if (chunk.bad_record) return;
    if (hashes_valid_) XXH64_update(record_hash_.get(), chunk.bytes.data(), chunk.bytes.size());
    stock_->bytes.give(std::move(chunk.bytes));
    if (trailer_) check_index_entry(seen, unit.data_frame, where);
    seen_.push_back(seen);
  }

  void check_index_entry(const FrameIndexEntry& seen, std::uint64_t number, const std::string& where) const {
    const auto& index = trailer_->index;
    if (number >= index.size()) fail(fmt::format("{}: the index lists only {} data frames", where, index.size()));
    const FrameIndexEntry& expected = index[number];
    if (expected == seen) return;
    if (expected.checksum != seen.checksum) {
      for (std::size_t other = 0; other < index.size(); ++other) {
        if (index[other].checksum == seen.checksum && index[other].compressed_size == seen.compressed_size) {
          fail(fmt::format("{}: frame out of order: it is the index's data frame {}", where, other + 1));
        }
      }
      fail(fmt::format("{}: checksum {:08x} differs from the index's {:08x}", where, seen.checksum, expected.checksum));
    }
    fail(fmt::format("{}: index says offset {}, size {}, first record {}, {} records, animation frame {}; "
                     "found offset {}, size {}, first record {}, {} records, animation frame {}",
                     where, expected.offset, expected.compressed_size, expected.first_record, expected.record_count,
                     expected.animation_frame, seen.offset, seen.compressed_size, seen.first_record,
                     seen.record_count, seen.animation_frame));
  }

  void finish() {
    finished_ = true;
    if (mode_ != Mode::Container) return;
    if (!saw_trailer_) {
      if (header_.announces_trailer()) {
        fail(fmt::format("truncated: the file ends after {} data frames without the trailer the header announces",
                         data_frames_));
      }
      return;
    }
    const auto& index = trailer_->index;
    if (data_frames_ != index.size()) {
      fail(fmt::format("the index lists {} data frames but the file holds {}", index.size(), data_frames_));
    }
    if (!hashes_valid_) return;
    for (std::size_t i = 0; i < seen_.size(); ++i) {
      check_index_entry(seen_[i], i, fmt::format("data frame {} at byte {}", i + 1, seen_[i].offset));
    }
    const auto totals = trailer_->totals.find("records");
    if (totals != trailer_->totals.end() && (!totals->is_number_unsigned() || totals->get<std::uint64_t>() != records_read_)) {
      fail(fmt::format("the trailer's totals say {} records but the data frames hold {}", totals->dump(), records_read_));
    }
    if (skipped_bytes_) return;  // the hashes cover the skipped data frames
    if (XXH64_digest(record_hash_.get()) != trailer_->record_hash) {
      fail("record hash mismatch: the records are not the ones the trailer describes");
    }
    if (stream_content_hash_ != trailer_->content_hash) {
      fail("content hash mismatch: the bytes before the trailer were changed");
    }
  }

  // Waits for every job in flight (they own their data) and forgets them.
  void drain() {
    for (auto& unit : units_) {
      if (unit.chunk.valid()) unit.chunk.wait();
    }
    units_.clear();
  }

  struct HashStateDeleter {
    void operator()(XXH64_state_t* state) const { XXH64_freeState(state); }
  };
  struct DStreamDeleter {
    void operator()(ZSTD_DStream* stream) const { ZSTD_freeDStream(stream); }
  };

  std::string name_;
  Input input_;
  ReaderOptions options_;
  Mode mode_ = Mode::PlainRaw;
  detail::ParseSettings settings_;
  TraceHeader header_;
  std::optional<TraceTrailer> trailer_;
  unsigned threads_ = 1;
  std::shared_ptr<Stock> stock_ = std::make_shared<Stock>();
  std::unique_ptr<detail::ThreadPool> pool_;
  std::deque<Unit> units_;
  std::optional<FrameMarker> pending_marker_;
  std::optional<WindowMarker> pending_window_;
  std::vector<bool> skip_;     // keep_data_frame's answer per index entry (true: skip)
  std::size_t next_skip_ = 0;  // the first skipped data frame not yet passed
  bool skipped_bytes_ = false;
  std::uint64_t data_frames_decompressed_ = 0;
  std::uint64_t data_frames_skipped_ = 0;
  bool input_done_ = false;
  bool finished_ = false;
  bool saw_trailer_ = false;
  bool hashes_valid_ = true;
  std::uint64_t header_end_ = 0;
  std::uint64_t data_frames_ = 0;
  std::uint64_t markers_ = 0;
  std::uint64_t zstd_frame_start_ = 0;  // plain zstd input: offset of the frame being decoded
  std::uint64_t records_read_ = 0;       // containers: records in frames handed over so far
  std::uint64_t records_delivered_ = 0;  // records returned by next()
  std::vector<FrameIndexEntry> seen_;
  std::unique_ptr<XXH64_state_t, HashStateDeleter> content_hash_{XXH64_createState()};
  std::unique_ptr<XXH64_state_t, HashStateDeleter> record_hash_{XXH64_createState()};
  std::uint64_t stream_content_hash_ = 0;
  std::unique_ptr<ZSTD_DStream, DStreamDeleter> zstd_;
  std::size_t zstd_status_ = 0;
  std::string first_plain_;
  std::string first_bytes_;  // the input's first 4 bytes
  std::string tail_;         // plain zstd: the last bytes read
  std::string carry_;
  std::uint64_t record_bytes_ = 0;
  std::uint64_t ignored_fields_ = 0;
};

}  // namespace

std::unique_ptr<TraceReader> TraceReader::open(const std::string& path, const ReaderOptions& options) {
  return std::make_unique<Reader>(path, options);
}

}  // namespace nodetrace::formats
