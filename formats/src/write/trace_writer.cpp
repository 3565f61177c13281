#include "nodetrace/formats/write/trace_writer.hpp"

#include <xxhash.h>
#include <zstd.h>

#include <fmt/format.h>

#include <vector>

#include "container/container.hpp"
#include "container/treelet_map_codec.hpp"
#include "nodetrace/base/error.hpp"
#include "nodetrace/base/output_file.hpp"
#include "nodetrace/formats/record/record_summary.hpp"
#include "codec/record_codec.hpp"
#include "nodetrace/base/ordered_pipeline.hpp"

namespace nodetrace::formats {

TraceWriter::~TraceWriter() = default;

namespace {

struct Encoded {
  detail::ByteBuffer text;        // the record bytes
  detail::ByteBuffer compressed;  // the zstd frame (containers)
};

// Text and compressed buffers are kept apart: handing a small compressed
// buffer out for text would reallocate (and page-fault) it every frame.
struct Stock {
  detail::Recycler<detail::ByteBuffer> text{8};
  detail::Recycler<detail::ByteBuffer> compressed{8};
};

// A data frame's text, compressed (containers) on a worker thread.
Encoded encode(detail::ByteBuffer text, bool compress, int level, unsigned window_log, Stock& stock) {
  Encoded encoded;
  encoded.text = std::move(text);
  if (compress) {
    struct Deleter {
      void operator()(ZSTD_CCtx* context) const { ZSTD_freeCCtx(context); }
    };
    thread_local std::unique_ptr<ZSTD_CCtx, Deleter> context(ZSTD_createCCtx());
    ZSTD_CCtx_reset(context.get(), ZSTD_reset_session_and_parameters);
    ZSTD_CCtx_setParameter(context.get(), ZSTD_c_compressionLevel, level);
    // A 4 MiB window rather than the 0.5-2 MiB zstd gives levels 1-6: a data
    // frame is about 14 MB of text, and the longer reach finds more repeats.
    // Measured at level 3 on 14 MB frames: 3% smaller on a tracer trace, 0.6%
    // on formats_bench's, and no slower (fewer, longer matches). zstd still
    // shrinks the window of a frame smaller than that.
    if (window_log != 0) {
      // The large window with long-distance matching, as `zstd --long` sets
      // them: on 4M Kitchen records `zstd -19 --long=26` was 12% smaller and
      // took 26% less CPU than `zstd -19` (FORMAT.md 2.3.1).
      ZSTD_CCtx_setParameter(context.get(), ZSTD_c_windowLog, static_cast<int>(window_log));
      ZSTD_CCtx_setParameter(context.get(), ZSTD_c_enableLongDistanceMatching, 1);
    } else if (level >= 1 && level <= 6) {
      ZSTD_CCtx_setParameter(context.get(), ZSTD_c_windowLog, 22);
    }
    ZSTD_CCtx_setParameter(context.get(), ZSTD_c_checksumFlag, 1);
    ZSTD_CCtx_setParameter(context.get(), ZSTD_c_contentSizeFlag, 1);
    encoded.compressed = stock.compressed.take();
    encoded.compressed.resize(ZSTD_compressBound(encoded.text.size()));
    const std::size_t size = ZSTD_compress2(context.get(), encoded.compressed.data(), encoded.compressed.size(),
                                            encoded.text.data(), encoded.text.size());
    if (ZSTD_isError(size)) throw base::IoError(fmt::format("zstd compression failed: {}", ZSTD_getErrorName(size)));
    encoded.compressed.resize(size);
  }
  return encoded;
}

}  // namespace

nlohmann::json container_header(nlohmann::json header, const WriterOptions& options) {
  header["container"] = {{"name", detail::kContainerName}, {"version", detail::kContainerVersion}};
  header["records"] = std::string(form_name(options.form));
  if (options.tags_are_levels && options.form != RecordForm::Binary) {
    header["tag"] = "node-level";
  } else {
    header.erase("tag");
  }
  header.erase("units");
  if (options.units > 1) header["units"] = options.units;
  header["trailer"] = true;
  // The writer's, like "container": a converted archive's stale setting
  // must not travel on.
  header.erase("compression");
  if (options.window_log != 0) {
    header["compression"] = {{"level", options.zstd_level}, {"window_log", options.window_log}};
  }
  // Only traces with maps say so, so other traces keep their bytes.
  header.erase("treelet_map");
  if (options.treelet_maps) header["treelet_map"] = true;
  return header;
}

namespace {

class Writer final : public TraceWriter {
 public:
  Writer(const std::string& path, nlohmann::json header, const WriterOptions& options)
      : path_(path), name_(path == "-" ? "<stdout>" : path), options_(options) {
    if (options_.records_per_data_frame == 0) throw base::UsageError("records per frame must be at least 1");
    if (options_.address_digits != 8 && options_.address_digits != 16) {
      throw base::UsageError(fmt::format("address digits must be 8 or 16, not {}", options_.address_digits));
    }
    if (options_.zstd_level < ZSTD_minCLevel() || options_.zstd_level > ZSTD_maxCLevel()) {
      throw base::UsageError(fmt::format("zstd level {} is outside {}..{}", options_.zstd_level, ZSTD_minCLevel(),
                                   ZSTD_maxCLevel()));
    }
    const int min_window_log = ZSTD_cParam_getBounds(ZSTD_c_windowLog).lowerBound;
    if (options_.window_log != 0 &&
        (options_.window_log < static_cast<unsigned>(min_window_log) || options_.window_log > kMaxWindowLog)) {
      throw base::UsageError(fmt::format("window log {} is outside {}..{}", options_.window_log, min_window_log,
                                   kMaxWindowLog));
    }
    if (header.is_null()) header = nlohmann::json::object();
    if (!header.is_object()) throw base::UsageError("the trace header must be a JSON object");
    container_ = decide_trace_output(path, options_.kind, options_.form).container;
    levels_ = container_ && options_.tags_are_levels && options_.form != RecordForm::Binary;
    if (options_.units == 0 || options_.units > kMaxUnits) {
      throw base::UsageError(fmt::format("traversal units must be 1 to {}, not {}", kMaxUnits, options_.units));
    }
    if (options_.units > 1 && (options_.form == RecordForm::Binary || (container_ && !levels_))) {
      throw base::UsageError(fmt::format("records of {} traversal units carry the unit after a node-level tag; {}",
                                         options_.units,
                                         options_.form == RecordForm::Binary ? "binary records have no tag"
                                                                             : "this trace's tags are not node levels"));
    }
    unit_digits_ = unit_digits_for(options_.units);
    pipeline_ = std::make_unique<base::OrderedPipeline<Item>>(options_.threads);
    XXH64_reset(record_hash_.get(), 0);
    XXH64_reset(content_hash_.get(), 0);
    out_ = std::make_unique<base::OutputFile>(path_);
    if (container_) {
      header = container_header(std::move(header), options_);
      layout_ = TraceHeader{header}.layout();
      emit(detail::skippable_frame(detail::kHeaderMagic, header.dump()), true);
    }
    reserve_pending_text();
  }

  ~Writer() override {
    if (finished_) return;
    pipeline_.reset();  // waits for the jobs in flight
    // out_'s destructor removes the temporary.
  }

  void begin_animation_frame(const AnimationFrameMarker& marker) override {
    check_open();
    queue_marker(detail::kMarkerMagic, marker.to_json(), treelet_map_frame(marker));
    ++markers_;  // after queue_marker: the data frame it ends belongs to the previous animation frame
  }

  void begin_window(const WindowMarker& marker) override {
    check_open();
    queue_marker(detail::kWindowMagic, marker.to_json());
    ++windows_;
  }

  void write(std::span<const Record> records) override {
    check_open();
    while (!records.empty()) {
      // Whole runs up to the end of the pending data frame: one cheap pass
      // checks them, then they are formatted (and counted) straight into the
      // frame's text while they are still in the cache, and the new text is
      // hashed while it is (formatting costs about what copying them for a
      // worker would; compression, the bulk of the work, runs on the workers).
      const std::size_t room = options_.records_per_data_frame - pending_records_;
      const std::span<const Record> run = records.first(std::min<std::size_t>(room, records.size()));
      records = records.subspan(run.size());
      if (!writable(run)) {
        write_one_by_one(run);  // throws, naming the first bad record
      }
      const std::size_t text_before = pending_text_.size();
      detail::format_records(run, options_.form, options_.address_digits, unit_digits_, records_total_, pending_text_,
                             summary_);
      hash_text_from(text_before);
      pending_records_ += run.size();
      records_total_ += run.size();
      if (pending_records_ >= options_.records_per_data_frame) submit_pending();
    }
  }

  void add_totals(const nlohmann::json& totals) override {
    if (!totals.is_object()) throw base::UsageError("totals must be a JSON object");
    extra_totals_.update(totals);
  }

  void finish() override {
    check_open();
    submit_pending();
    drain(true);
    if (container_) {
      TraceTrailer trailer;
      trailer.index = std::move(index_);
      trailer.totals = extra_totals_;
      trailer.totals["records"] = records_total_;
      trailer.totals["records_per_tag"] = summary_.records_per_tag();
      trailer.totals["records_per_type"] = summary_.records_per_type();
      trailer.totals["animation_frames"] = markers_;
      // Only sampled traces say it, so unsampled traces keep their bytes.
      if (windows_ > 0) trailer.totals["sample_windows"] = windows_;
      trailer.totals["data_frames"] = trailer.index.size();
      trailer.totals["record_bytes"] = record_bytes_;
      trailer.record_hash = XXH64_digest(record_hash_.get());
      trailer.content_hash = XXH64_digest(content_hash_.get());
      emit(detail::encode_trailer(trailer), false);
    }
    out_->commit();
    finished_ = true;
  }

 private:
  // What goes into the file, in order: a marker's bytes, or a data frame.
  struct Item {
    bool is_data_frame = false;
    std::string ready;  // a marker's bytes
    Encoded encoded;    // a data frame's text and zstd frame
    std::uint64_t first_record = 0;
    std::uint64_t record_count = 0;
    std::uint64_t animation_frame = 0;
  };

  // True when every record of the run can be written.
  bool writable(std::span<const Record> run) const {
    const bool din = options_.form == RecordForm::Din;
    const bool binary = options_.form == RecordForm::Binary;
    // One unit writes no unit field: whatever a record's unit, it is dropped.
    const unsigned unit_limit = options_.units > 1 ? options_.units : kMaxUnits;
    bool bad = false;
    for (const Record& record : run) {
      bad |= static_cast<unsigned>(record.type) >= static_cast<unsigned>(kAccessTypeCount);
      bad |= levels_ && record.tag == kTagNone;
      bad |= binary && (record.address > 0xFFFFFFFFu || record.size > 0xFFFFu);
      bad |= !din && record.size == 0;
      bad |= unit_index(record.unit) >= unit_limit;
    }
    return !bad;
  }

  // record_hash covers the record text in trace order, which is the order
  // write() formats it in; hashing it here, just written, reads it from the
  // cache rather than from memory when its data frame is done.
  void hash_text_from(std::size_t offset) {
    XXH64_update(record_hash_.get(), pending_text_.data() + offset, pending_text_.size() - offset);
  }

  // The records of a run with a bad one, as they were written before bulk
  // checking: those before it are kept, then the error names it.
  void write_one_by_one(std::span<const Record> run) {
    for (const Record& record : run) {
      const auto type = static_cast<unsigned>(record.type);
      if (type >= static_cast<unsigned>(kAccessTypeCount)) {
        fail(fmt::format("record {}: access type {} is not one of Dinero IV's (0-5)", records_total_ + 1, type));
      }
      if (levels_ && record.tag == kTagNone) {
        fail(fmt::format("record {}: untagged, but the trace marks its tags as node levels", records_total_ + 1));
      }
      if (options_.form == RecordForm::Binary && (record.address > 0xFFFFFFFFu || record.size > 0xFFFFu)) {
        fail(fmt::format("record {}: address {:#x} or size {} does not fit a binary record (32-bit address, 16-bit size)",
                         records_total_ + 1, record.address, record.size));
      }
      if (options_.units > 1 && unit_index(record.unit) >= options_.units) {
        fail(fmt::format("record {}: unit {} is not one of the trace's {} traversal units", records_total_ + 1,
                         unit_index(record.unit), options_.units));
      }
      if (record.size == 0 && options_.form != RecordForm::Din) {
        fail(fmt::format("record {}: size 0 (a reference is at least 1 byte)", records_total_ + 1));
      }
      const std::size_t text_before = pending_text_.size();
      detail::format_records(std::span<const Record>(&record, 1), options_.form, options_.address_digits,
                             unit_digits_, records_total_, pending_text_, summary_);
      hash_text_from(text_before);
      ++pending_records_;
      ++records_total_;
    }
  }

  // The frame holding the marker's treelet map, checked against the frame's
  // node addresses; empty when the trace carries no maps.
  std::string treelet_map_frame(const AnimationFrameMarker& marker) const {
    if (!container_) return {};
    if (marker.treelets.has_value() != options_.treelet_maps) {
      throw base::UsageError(fmt::format(
          "{}: animation frame {}: {}", name_, marker.frame,
          options_.treelet_maps ? "the trace carries a treelet map per animation frame, but this marker has none"
                                : "the marker has a treelet map, but the writer was not asked to carry maps "
                                  "(WriterOptions::treelet_maps)"));
    }
    if (!marker.treelets) return {};
    try {
      check_treelet_map(*marker.treelets, node_address_range(layout_.node_base, marker.nodes, layout_.node_size));
    } catch (const base::FormatError& error) {
      fail(fmt::format("treelet map of animation frame {}: {}", marker.frame, error.what()));
    }
    return detail::skippable_frame(detail::kTreeletMapMagic, detail::encode_treelet_map(*marker.treelets));
  }

  // A marker ends the pending data frame (a marker never splits one) and,
  // in a container, follows it in the file, with what goes right after it
  // (`after`: a treelet map).
  void queue_marker(std::uint32_t magic, const nlohmann::json& json, std::string after = {}) {
    submit_pending();
    if (!container_) return;
    Item item;
    item.ready = detail::skippable_frame(magic, json.dump()) + after;
    pipeline_->push_ready(std::move(item));
    drain(false);
  }

  [[noreturn]] void fail(const std::string& message) const { throw base::FormatError(fmt::format("{}: {}", name_, message)); }

  void check_open() const {
    if (finished_) throw base::UsageError(fmt::format("{}: the writer is already finished", name_));
  }

  void submit_pending() {
    if (pending_records_ == 0) return;
    Item item;
    item.is_data_frame = true;
    item.first_record = records_total_ - pending_records_;
    item.record_count = pending_records_;
    item.animation_frame = markers_ == 0 ? 0 : markers_ - 1;
    detail::ByteBuffer text = std::move(pending_text_);
    pending_text_ = stock_->text.take();
    pending_records_ = 0;
    reserve_pending_text();
    pipeline_->submit([item = std::move(item), text = std::move(text), compress = container_,
                       level = options_.zstd_level, window_log = options_.window_log, stock = stock_]() mutable {
      item.encoded = encode(std::move(text), compress, level, window_log, *stock);
      return std::move(item);
    });
    drain(false);
  }

  // Room for a whole frame's text up front (pages are touched only as lines
  // are written), so formatting never reallocates mid-frame.
  void reserve_pending_text() {
    pending_text_.reserve(std::min<std::uint64_t>(options_.records_per_data_frame, 1u << 20) * detail::kMaxTextLine);
  }

  // Writes finished items in order; waits for all when `all`, else only while
  // more jobs are in flight than keep the threads busy (bounded memory).
  void drain(bool all) {
    const std::size_t limit = static_cast<std::size_t>(pipeline_->threads()) + 1;
    while (!pipeline_->empty() && (all || pipeline_->size() > limit || pipeline_->front_ready())) {
      Item item;
      try {
        item = pipeline_->pop();
      } catch (const base::FormatError& error) {
        fail(error.what());
      }
      if (!item.is_data_frame) {
        emit(item.ready, true);
        continue;
      }
      Encoded& encoded = item.encoded;
      record_bytes_ += encoded.text.size();
      if (!container_) {
        emit(encoded.text.view(), false);
        stock_->text.give(std::move(encoded.text));
        continue;
      }
      stock_->text.give(std::move(encoded.text));
      DataFrameIndexEntry entry;
      entry.offset = offset_;
      entry.compressed_size = encoded.compressed.size();
      entry.first_record = item.first_record;
      entry.record_count = item.record_count;
      entry.animation_frame = item.animation_frame;
      entry.checksum = detail::load_le32(encoded.compressed.data() + encoded.compressed.size() - 4);
      index_.push_back(entry);
      emit(encoded.compressed.view(), true);
      stock_->compressed.give(std::move(encoded.compressed));
    }
  }

  void emit(std::string_view bytes, bool hashed) {
    if (hashed) XXH64_update(content_hash_.get(), bytes.data(), bytes.size());
    out_->write(bytes);
    offset_ += bytes.size();
  }

  struct HashStateDeleter {
    void operator()(XXH64_state_t* state) const { XXH64_freeState(state); }
  };

  std::string path_;
  std::string name_;
  WriterOptions options_;
  bool container_ = false;
  bool levels_ = false;
  LayoutInfo layout_;  // the header's: where a treelet map may point
  unsigned unit_digits_ = 0;  // 0: no unit field
  bool finished_ = false;
  std::unique_ptr<base::OutputFile> out_;
  std::shared_ptr<Stock> stock_ = std::make_shared<Stock>();
  std::unique_ptr<base::OrderedPipeline<Item>> pipeline_;  // the data frames being compressed, and the markers between
  detail::ByteBuffer pending_text_;  // the text of the data frame being filled
  std::uint64_t pending_records_ = 0;
  std::vector<DataFrameIndexEntry> index_;
  RecordSummary summary_;  // the trailer's records_per_tag / records_per_type
  std::uint64_t records_total_ = 0;
  std::uint64_t markers_ = 0;
  std::uint64_t windows_ = 0;
  std::uint64_t offset_ = 0;
  std::uint64_t record_bytes_ = 0;
  nlohmann::json extra_totals_ = nlohmann::json::object();
  std::unique_ptr<XXH64_state_t, HashStateDeleter> record_hash_{XXH64_createState()};
  std::unique_ptr<XXH64_state_t, HashStateDeleter> content_hash_{XXH64_createState()};
};

}  // namespace

std::unique_ptr<TraceWriter> TraceWriter::create(const std::string& path, nlohmann::json header,
                                                 const WriterOptions& options) {
  return std::make_unique<Writer>(path, std::move(header), options);
}

}  // namespace nodetrace::formats
