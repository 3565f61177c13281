// The container reader (FORMAT.md sections 2 and 3): the header, then frame
// by frame markers, data frames (decoded on the workers and handed over in
// pieces, so memory stays small, each frame checked against the index) and
// the trailer; from a file it reads the trailer from the end
// first, which gives the index for keep_data_frame and seek_to_record.
#define ZSTD_STATIC_LINKING_ONLY  // ZSTD_getFrameHeader, ZSTD_decompressBound, the buffer-less API
#include <xxhash.h>
#include <zstd.h>

#include <fmt/format.h>

#include <algorithm>
#include <cstring>

#include "container/container.hpp"
#include "container/treelet_map_codec.hpp"
#include "nodetrace/base/error.hpp"
#include "read/data_frame_decoder.hpp"
#include "read/reader_kinds.hpp"

namespace nodetrace::formats::detail {
namespace {

std::string data_frames_text(std::uint64_t count) {
  return fmt::format("{} data frame{}", count, count == 1 ? "" : "s");
}

class ContainerReader final : public PipelinedReader {
 public:
  ContainerReader(OpenedInput opened, const ReaderOptions& options) : PipelinedReader(std::move(opened), options) {
    open_container();
    start_workers();
  }

  std::string_view input_kind() const override { return "container"; }
  std::uint64_t data_frames_decompressed() const override { return data_frames_decompressed_; }
  std::uint64_t data_frames_skipped() const override { return data_frames_skipped_; }

  void seek_to_record(std::uint64_t record) override {
    if (!input_->seekable() || !trailer_) cannot_seek();
    const auto& index = trailer_->index;
    auto found = std::find_if(index.begin(), index.end(), [&](const DataFrameIndexEntry& entry) {
      return record >= entry.first_record && record < entry.first_record + entry.record_count;
    });
    if (found == index.end()) {
      throw base::UsageError(fmt::format("{}: record {} is beyond the trace's {} records", name_, record,
                                   index.empty() ? 0 : index.back().first_record + index.back().record_count));
    }
    drain();
    input_->seek(found->offset);
    data_frames_ = static_cast<std::uint64_t>(found - index.begin());
    next_skip_ = static_cast<std::size_t>(data_frames_);
    records_read_ = records_delivered_ = found->first_record;
    frame_records_ = 0;
    pending_marker_.reset();
    pending_window_.reset();
    markers_ = found->animation_frame + 1;
    hashes_valid_ = false;
    saw_trailer_ = false;
    finished_ = false;
    input_done_ = false;
  }

 private:
  // Reads one whole skippable frame at the current position into `payload`.
  void read_skippable(std::string& payload, const char* what) {
    if (!input_->ensure(kSkippableHeaderSize)) fail(fmt::format("truncated: {} at byte {} is cut short", what, input_->offset()));
    const std::uint32_t size = load_le32(input_->data() + 4);
    if (!input_->ensure(kSkippableHeaderSize + size)) {
      fail(fmt::format("truncated: {} at byte {} is cut short", what, input_->offset()));
    }
    payload.assign(input_->data() + kSkippableHeaderSize, size);
    consume_hashed(kSkippableHeaderSize + size);
  }

  void consume_hashed(std::size_t count) {
    XXH64_update(content_hash_.get(), input_->data(), count);
    input_->consume(count);
  }

  void open_container() {
    XXH64_reset(content_hash_.get(), 0);
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
        (*container)["name"] != kContainerName || !(*container)["version"].is_number_unsigned()) {
      fail(fmt::format("header does not name the container (\"container\": {{\"name\": \"{}\", \"version\": N}})",
                       kContainerName));
    }
    const auto version = (*container)["version"].get<std::uint64_t>();
    if (version != kContainerVersion) {
      fail(fmt::format("container version {} is not one this reader knows ({})", version, kContainerVersion));
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
    if (const auto maps = header_.json.find("treelet_map"); maps != header_.json.end() && !maps->is_boolean()) {
      fail(fmt::format("damaged header: \"treelet_map\" is {}, not true or false", maps->dump().substr(0, 40)));
    }
    layout_ = header_.layout();
    settings_.form = *form;
    settings_.tags_are_levels = options_.tags_are_levels || header_.tags_are_levels();
    try {
      settings_.units = header_.units();
    } catch (const base::FormatError& error) {
      fail(error.what());
    }
    header_end_ = input_->offset();
    if (input_->seekable() && header_.announces_trailer()) trailer_ = read_trailer_from_end();
    if (input_->seekable() && trailer_ && options_.keep_data_frame) {
      skip_.reserve(trailer_->index.size());
      for (const DataFrameIndexEntry& entry : trailer_->index) skip_.push_back(!options_.keep_data_frame(entry));
      skips_some_ = std::find(skip_.begin(), skip_.end(), true) != skip_.end();
    }
  }

  TraceTrailer read_trailer_from_end() {
    const std::uint64_t size = input_->size();
    const auto missing = [&](const std::string& why) {
      fail(fmt::format("truncated or damaged: no valid trailer at the end of the file ({})", why));
    };
    if (size < header_end_ + kSkippableHeaderSize + kFooterSize) missing("file too short");
    const std::string footer = input_->read_at(size - kFooterSize, kFooterSize);
    if (load_le32(footer.data() + 16) != kFooterMagic) missing("no footer magic");
    if (load_le32(footer.data() + 12) != kContainerVersion) missing("footer version is not 1");
    const std::uint64_t json_size = load_le32(footer.data() + 8);
    if (json_size + kFooterSize + kSkippableHeaderSize > size - header_end_) {
      missing("footer's length runs past the header");
    }
    const std::uint64_t start = size - kFooterSize - json_size - kSkippableHeaderSize;
    const std::string frame_header = input_->read_at(start, kSkippableHeaderSize);
    if (load_le32(frame_header.data()) != kTrailerMagic ||
        load_le32(frame_header.data() + 4) != json_size + kFooterSize) {
      missing("the footer's length does not lead to the trailer frame");
    }
    const std::string json = input_->read_at(start + kSkippableHeaderSize, json_size);
    if (XXH64(json.data(), json.size(), 0) != load_le64(footer.data())) missing("trailer hash mismatch");
    TraceTrailer trailer;
    try {
      trailer = decode_trailer_json(json);
    } catch (const base::FormatError& error) {
      fail(error.what());
    }
    check_index_fits(trailer.index, start);
    return trailer;
  }

  // The index read from the end must describe this file (FORMAT.md 3): its
  // data frames in order between the header and the trailer, each beginning
  // with a zstd magic, the last ending with its checksum, and only skippable frames
  // (markers) after the last. Readers that trust the trailer (tracetool info)
  // would otherwise show another trace's counts under this header.
  void check_index_fits(const std::vector<DataFrameIndexEntry>& index, std::uint64_t trailer_start) const {
    std::uint64_t end = header_end_;
    for (std::size_t i = 0; i < index.size(); ++i) {
      const DataFrameIndexEntry& entry = index[i];
      const auto misfit = [&](const char* why) {
        fail_index_misfit(index, trailer_start,
                          fmt::format("data frame {} at byte {} of {} bytes {}", i + 1, entry.offset,
                                      entry.compressed_size, why));
      };
      if (entry.offset < end) misfit("overlaps the header or the data frame before it");
      if (entry.compressed_size < 8 || entry.compressed_size > trailer_start - entry.offset) {
        misfit("does not end before the trailer");
      }
      if (load_le32(input_->read_at(entry.offset, 4).data()) != kZstdMagic) misfit("is not a zstd frame");
      // The last frame's checksum ties the index to these frames; earlier
      // ones are checked as they are read, where frames out of order are
      // told apart from damage.
      if (i + 1 == index.size() &&
          load_le32(input_->read_at(entry.offset + entry.compressed_size - 4, 4).data()) != entry.checksum) {
        misfit("does not end with the index's checksum");
      }
      end = entry.offset + entry.compressed_size;
    }
    while (end < trailer_start) {  // markers of animation frames or windows without records
      if (trailer_start - end < kSkippableHeaderSize) break;
      const std::string frame = input_->read_at(end, kSkippableHeaderSize);
      const std::uint32_t magic = load_le32(frame.data());
      if ((magic & kSkippableMask) != kHeaderMagic || magic == kHeaderMagic || magic == kTrailerMagic) break;
      end += kSkippableHeaderSize + load_le32(frame.data() + 4);
    }
    if (end != trailer_start) {
      fail_index_misfit(index, trailer_start,
                        fmt::format("the bytes from byte {} to the trailer at byte {} are not in it", end,
                                    trailer_start));
    }
  }

  // A misfit index: two traces joined (`cat a.din.zst b.din.zst`, the
  // trailer at the end being b's) when a header begins where the last trace
  // would, else damage.
  [[noreturn]] void fail_index_misfit(const std::vector<DataFrameIndexEntry>& index, std::uint64_t trailer_start,
                                      const std::string& what) const {
    if (!index.empty()) {
      const std::uint64_t last_end = index.back().offset + index.back().compressed_size;
      if (last_end < trailer_start && trailer_start - last_end >= header_end_) {
        const std::uint64_t other = trailer_start - last_end;
        if (load_le32(input_->read_at(other, 4).data()) == kHeaderMagic) fail(joined_traces_message(other));
      }
    }
    fail(fmt::format("damaged: the trailer's index does not fit the file: {}", what));
  }

  static std::string joined_traces_message(std::uint64_t second_header) {
    return fmt::format("two traces joined: a second trace's header begins at byte {} (a container holds one "
                       "trace; `cat` of two containers is not one: read or convert each on its own)",
                       second_header);
  }

  void read_decode_unit() override {
    if (skip_data_frame_here()) return;
    if (input_->at_end()) {
      input_done_ = true;
      return;
    }
    const std::uint64_t offset = input_->offset();
    if (!input_->ensure(4)) fail(fmt::format("truncated: stray bytes at byte {}", offset));
    const std::uint32_t magic = load_le32(input_->data());
    if (magic == kZstdMagic) {
      std::size_t size = 0;
      for (std::size_t want = 1u << 16;; want *= 2) {
        input_->ensure(want);
        size = ZSTD_findFrameCompressedSize(input_->data(), input_->available());
        if (!ZSTD_isError(size)) break;
        if (input_->available() < want) {  // the whole rest of the input is not a whole frame
          fail(fmt::format("truncated or damaged: data frame {} at byte {} is incomplete ({})", data_frames_ + 1,
                           offset, ZSTD_getErrorName(size)));
        }
      }
      DecodeUnit unit;
      unit.data_frame = data_frames_++;
      unit.entry.offset = offset;
      unit.entry.compressed_size = size;
      unit.entry.animation_frame = markers_ == 0 ? 0 : markers_ - 1;
      unit.entry.checksum = size >= 4 ? load_le32(input_->data() + size - 4) : 0;
      std::string frame(input_->data(), size);
      consume_hashed(size);
      // The record hash, unless frames are skipped or were (seek): it is
      // then not checked, and its chain would wait for them.
      std::shared_ptr<RecordHashChain> hash = hashes_valid_ && !skips_some_ ? record_hash_ : nullptr;
      if (!hash) unhashed_frames_ = true;
      auto stream = std::make_shared<PieceStream>(hash ? kPiecesWaitingHashed : kPiecesWaiting);
      // Large windows one at a time: each waits for the previous one.
      std::shared_ptr<PieceStream> earlier;
      ZSTD_frameHeader frame_header{};
      if (ZSTD_getFrameHeader(&frame_header, frame.data(), frame.size()) == 0 &&
          frame_header.windowSize > kSmallWindow) {
        earlier = std::exchange(last_large_window_, stream);
      }
      unit.stream = stream;
      const std::uint64_t hash_frame = unit.data_frame;
      pipeline_->push_ready(std::move(unit));
      post_stream_job(stream, [frame = std::move(frame), settings = settings_, hash = std::move(hash), hash_frame,
                               stock = stock_, stream, earlier = std::move(earlier)] {
        decode_into(frame, settings, hash.get(), hash_frame, *stock, *stream, earlier.get());
      });
      return;
    }
    if ((magic & kSkippableMask) != kHeaderMagic) {
      fail(fmt::format("damaged: bytes at byte {} are not a zstd frame (magic {:#010x})", offset, magic));
    }
    if (magic == kTrailerMagic) {
      read_stream_trailer(offset);
      return;
    }
    const char* what = magic == kMarkerMagic       ? "animation frame marker"
                       : magic == kWindowMagic     ? "sample window marker"
                       : magic == kTreeletMapMagic ? "treelet map"
                                                   : "skippable frame";
    std::string payload;
    read_skippable(payload, what);
    if (magic == kHeaderMagic) fail(joined_traces_message(offset));
    // In a trace without maps a 0x184D2A53 frame is someone else's (FORMAT.md 2.5).
    if (magic == kTreeletMapMagic && header_.carries_treelet_maps()) {
      fail(fmt::format("treelet map at byte {} does not follow an animation frame marker (FORMAT.md 2.2.2: each "
                       "stands right after its marker)",
                       offset));
    }
    if (magic != kMarkerMagic && magic != kWindowMagic) return;  // someone else's skippable frame
    DecodeUnit unit;
    try {
      const nlohmann::json json = nlohmann::json::parse(payload);
      if (magic == kMarkerMagic) {
        unit.kind = DecodeUnit::Kind::AnimationFrameMarker;
        unit.marker = AnimationFrameMarker::from_json(json);
      } else {
        unit.kind = DecodeUnit::Kind::WindowMarker;
        unit.window = WindowMarker::from_json(json);
      }
    } catch (const nlohmann::json::exception& error) {
      fail(fmt::format("{} at byte {} is not valid JSON ({})", what, offset, error.what()));
    } catch (const base::FormatError& error) {
      fail(fmt::format("at byte {}: {}", offset, error.what()));
    }
    if (unit.kind == DecodeUnit::Kind::AnimationFrameMarker) {
      if (header_.carries_treelet_maps()) unit.marker.treelets = read_treelet_map(unit.marker, offset);
      ++markers_;
    }
    pipeline_->push_ready(std::move(unit));
  }

  // The treelet map that must follow the marker at `marker_offset`, checked
  // against the frame's node addresses (FORMAT.md 2.2.2).
  TreeletMap read_treelet_map(const AnimationFrameMarker& marker, std::uint64_t marker_offset) {
    const std::uint64_t offset = input_->offset();
    if (!input_->ensure(4) || load_le32(input_->data()) != kTreeletMapMagic) {
      fail(fmt::format("animation frame {} (marker at byte {}) has no treelet map at byte {}: the header says "
                       "every marker is followed by one",
                       marker.frame, marker_offset, offset));
    }
    std::string payload;
    read_skippable(payload, "treelet map");
    const std::string where = fmt::format("treelet map of animation frame {} at byte {}", marker.frame, offset);
    try {
      TreeletMap map = decode_treelet_map(payload, offset + kSkippableHeaderSize, marker.nodes);
      check_treelet_map(map, node_address_range(layout_.node_base, marker.nodes, layout_.node_size));
      return map;
    } catch (const base::FormatError& error) {
      fail(fmt::format("{}: {}", where, error.what()));
    }
  }

  // keep_data_frame: when the index's next data frame starts here and is not
  // kept, steps over it (nothing read, nothing decompressed) and queues its
  // place; otherwise keeps reads ahead from running into the next skipped one.
  bool skip_data_frame_here() {
    if (skip_.empty()) return false;
    const auto& index = trailer_->index;
    while (next_skip_ < skip_.size() && (!skip_[next_skip_] || next_skip_ < data_frames_)) ++next_skip_;
    input_->limit_reads_to(next_skip_ < skip_.size() ? index[next_skip_].offset : 0);
    // Past the last skipped frame (at the trailer, data_frames_ is the index's size) nothing is skipped.
    if (next_skip_ >= skip_.size() || next_skip_ != data_frames_ || index[data_frames_].offset != input_->offset()) {
      return false;
    }
    const DataFrameIndexEntry& entry = index[data_frames_];
    if (entry.compressed_size == 0 || entry.offset + entry.compressed_size > input_->size()) {
      fail(fmt::format("damaged index: data frame {} at byte {} of {} bytes runs past the end of the file",
                       data_frames_ + 1, entry.offset, entry.compressed_size));
    }
    DecodeUnit unit;
    unit.kind = DecodeUnit::Kind::SkippedDataFrame;
    unit.entry = entry;
    unit.data_frame = data_frames_++;
    input_->skip(entry.compressed_size);
    skipped_bytes_ = true;
    pipeline_->push_ready(std::move(unit));
    return true;
  }

  void read_stream_trailer(std::uint64_t offset) {
    if (!input_->ensure(kSkippableHeaderSize)) fail(fmt::format("truncated: trailer at byte {}", offset));
    const std::uint32_t size = load_le32(input_->data() + 4);
    if (size < kFooterSize || !input_->ensure(kSkippableHeaderSize + size)) {
      fail(fmt::format("truncated: trailer at byte {} is cut short", offset));
    }
    const char* footer = input_->data() + kSkippableHeaderSize + size - kFooterSize;
    const std::string_view json(input_->data() + kSkippableHeaderSize, size - kFooterSize);
    if (load_le32(footer + 16) != kFooterMagic || load_le32(footer + 12) != kContainerVersion ||
        load_le32(footer + 8) != json.size() || XXH64(json.data(), json.size(), 0) != load_le64(footer)) {
      fail(fmt::format("damaged trailer at byte {} (footer does not match)", offset));
    }
    TraceTrailer trailer;
    try {
      trailer = decode_trailer_json(json);
    } catch (const base::FormatError& error) {
      fail(error.what());
    }
    stream_content_hash_ = XXH64_digest(content_hash_.get());
    input_->consume(kSkippableHeaderSize + size);
    if (!input_->at_end()) {
      if (input_->ensure(4) && load_le32(input_->data()) == kHeaderMagic) fail(joined_traces_message(input_->offset()));
      fail(fmt::format("unexpected bytes after the trailer at byte {}", input_->offset()));
    }
    if (trailer_ && !(trailer_->index == trailer.index)) fail("the trailer read from the end differs from the stream's");
    if (!trailer_) trailer_ = std::move(trailer);
    saw_trailer_ = true;
    input_done_ = true;
  }

  void check_chunk(const DecodeUnit& unit, Chunk& chunk) override {
    if (!chunk.frame_error.empty()) fail(fmt::format("{}: {}", where(unit), chunk.frame_error));
    frame_records_ += chunk.records.size();
    record_bytes_ += chunk.decoded_bytes;
  }

  void end_stream(const DecodeUnit& unit) override {
    DataFrameIndexEntry seen = unit.entry;
    seen.first_record = records_read_;
    seen.record_count = frame_records_;
    records_read_ += frame_records_;
    frame_records_ = 0;
    ++data_frames_decompressed_;
    if (trailer_) check_index_entry(seen, unit.data_frame, where(unit));
    seen_.push_back(seen);
  }

  static std::string where(const DecodeUnit& unit) {
    return fmt::format("data frame {} at byte {}", unit.data_frame + 1, unit.entry.offset);
  }

  void check_index_entry(const DataFrameIndexEntry& seen, std::uint64_t number, const std::string& where) const {
    const auto& index = trailer_->index;
    if (number >= index.size()) fail(fmt::format("{}: the index lists only {}", where, data_frames_text(index.size())));
    const DataFrameIndexEntry& expected = index[number];
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

  void finish_input() override {
    if (!saw_trailer_) {
      if (header_.announces_trailer()) {
        fail(fmt::format("truncated: the file ends after {} without the trailer the header announces",
                         data_frames_text(data_frames_)));
      }
      return;
    }
    const auto& index = trailer_->index;
    if (data_frames_ != index.size()) {
      fail(fmt::format("the index lists {} but the file holds {}", data_frames_text(index.size()), data_frames_));
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
    if (record_hash_ && !unhashed_frames_ && record_hash_->digest() != trailer_->record_hash) {
      fail("record hash mismatch: the records are not the ones the trailer describes");
    }
    if (stream_content_hash_ != trailer_->content_hash) {
      fail("content hash mismatch: the bytes before the trailer were changed");
    }
  }

  void pass_skipped(const DecodeUnit& unit) override {
    records_read_ += unit.entry.record_count;
    seen_.push_back(unit.entry);
    ++data_frames_skipped_;
  }

  struct HashStateDeleter {
    void operator()(XXH64_state_t* state) const { XXH64_freeState(state); }
  };

  std::vector<bool> skip_;     // keep_data_frame's answer per index entry (true: skip)
  std::size_t next_skip_ = 0;  // the first skipped data frame not yet passed
  bool skipped_bytes_ = false;
  bool skips_some_ = false;       // keep_data_frame skips a data frame
  bool unhashed_frames_ = false;  // a data frame was decoded without the record hash
  bool saw_trailer_ = false;
  bool hashes_valid_ = true;
  std::uint64_t data_frames_decompressed_ = 0;
  std::uint64_t data_frames_skipped_ = 0;
  std::uint64_t header_end_ = 0;
  LayoutInfo layout_;  // the header's: where a frame's treelet map may point
  std::uint64_t data_frames_ = 0;
  std::uint64_t markers_ = 0;
  std::uint64_t records_read_ = 0;  // records in the data frames handed over so far
  std::uint64_t frame_records_ = 0;  // records of the data frame being delivered, so far
  std::shared_ptr<PieceStream> last_large_window_;  // the last frame posted with a large window
  std::vector<DataFrameIndexEntry> seen_;
  std::unique_ptr<XXH64_state_t, HashStateDeleter> content_hash_{XXH64_createState()};
  // Fed by the workers (nullptr when the options leave the record hash unchecked).
  std::shared_ptr<RecordHashChain> record_hash_ =
      options_.check_record_hash ? std::make_shared<RecordHashChain>() : nullptr;
  std::uint64_t stream_content_hash_ = 0;
};

}  // namespace

std::unique_ptr<TraceReader> open_container_reader(OpenedInput opened, const ReaderOptions& options) {
  return std::make_unique<ContainerReader>(std::move(opened), options);
}

}  // namespace nodetrace::formats::detail
