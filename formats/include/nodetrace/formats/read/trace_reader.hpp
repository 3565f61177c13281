// Reading traces: the container of formats/FORMAT.md, plain din / extended
// din / Dinero binary text, plain zstd streams from any tool, and stdin.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "nodetrace/formats/container/metadata.hpp"
#include "nodetrace/formats/record/record.hpp"

namespace nodetrace::formats {

struct ReaderOptions {
  // Read the tag field as a node level even where no header says so
  // (--tags-are-levels). Without it, plain traces are untagged.
  bool tags_are_levels = false;
  // Record form of plain (headerless) input; nullopt detects it from the
  // first record (a letter type -> extended din, a digit label -> din).
  // Binary input is never guessed from its bytes: it is named, by this
  // option or by a file name ending in .bin or .bin.zst.
  std::optional<RecordForm> form;
  // An input with no records is an error (base::FormatError at the end of
  // the trace, naming it), file or pipe alike: an empty trace is most often
  // what a failed command left in a pipe. True only where Dinero IV's
  // behaviour is followed (it reads an empty input as a trace).
  bool allow_empty = false;
  // How the front end names binary input, for the hint given when text
  // records hold a NUL byte (binary read as text).
  std::string binary_form_option = "--informat binary";
  // Decoding threads; 0 means one per core.
  unsigned threads = 0;
  // Seekable containers with an index: data frames for which this returns
  // false are neither read nor decompressed; markers (frame and window) are
  // still delivered in order. The record and content hashes, which cover
  // skipped bytes, are then not checked (footer, index and every frame read
  // are). Ignored (every frame delivered) for input that cannot seek. Called
  // once per data frame, in file order, when the trace is opened.
  std::function<bool(const DataFrameIndexEntry&)> keep_data_frame;
  // Containers: check the trailer's record_hash (XXH64 of all decompressed
  // text). Damage is caught without it (FORMAT.md 3: zstd's checksum of each
  // data frame and the content hash of every byte); it checks what the
  // writer hashed, and costs a pass over all the text, so a simulator may
  // leave it to `tracetool verify`.
  bool check_record_hash = true;
};

// A run of consecutive records, delivered in trace order.
struct RecordBatch {
  // Set when an animation frame begins at records[0] (or, for an animation
  // frame with no records, on an empty batch).
  std::optional<AnimationFrameMarker> marker;
  // Set when a sample window begins at records[0] (or on an empty batch: a
  // window with no records, or one whose data frames were skipped). With
  // `marker` too, the window is the first of that animation frame.
  std::optional<WindowMarker> window;
  std::vector<Record> records;
  // What the reader found every record to be as it parsed them
  // (record_kinds): a simulator may skip its own pass over them. False
  // members: not so, or not known.
  RecordKinds kinds;
  // 0-based position of records[0] in the whole trace (it jumps over the
  // records of data frames skipped by keep_data_frame).
  std::uint64_t first_record = 0;
};

class TraceReader {
 public:
  // `path` "-" reads standard input. Throws base::IoError when it cannot be opened,
  // base::FormatError when what it holds is not a trace.
  static std::unique_ptr<TraceReader> open(const std::string& path,
                                           const ReaderOptions& options = {});
  virtual ~TraceReader();

  // The file name as given, or "<stdin>"; used in every error message.
  virtual const std::string& source_name() const = 0;
  virtual const TraceHeader& header() const = 0;
  virtual RecordForm form() const = 0;
  // True when tags are node levels (header says so, or tags_are_levels).
  virtual bool tags_are_levels() const = 0;
  // The traversal units the records carry: above 1 when the header says
  // `"units"` and the tags are node levels (each record's `unit` is read);
  // 1 otherwise (a unit field is ignored, as Dinero IV ignores it).
  virtual unsigned units() const { return 1; }

  // Fills `batch` with the next records (replacing its contents); returns
  // false at the end of the trace. Throws base::FormatError naming the record number
  // on bad data, and on truncation or damage of a container.
  virtual bool next(RecordBatch& batch) = 0;

  // The trailer: read from the end of a seekable container when opened, else
  // available once next() has returned false. nullopt for plain traces.
  virtual const std::optional<TraceTrailer>& trailer() const = 0;

  // Seekable containers with an index: continue reading at the data frame
  // holding record `record` (0-based); the next batch starts at that frame's
  // first record. Throws base::UsageError when the input cannot seek.
  virtual void seek_to_record(std::uint64_t record) = 0;

  // Bytes of record data (decompressed text or binary records) read so far.
  virtual std::uint64_t record_bytes() const { return 0; }
  // Records delivered so far whose line went on after the fields that were
  // read (e.g. a level tag in a trace not read with tags_are_levels): what a
  // conversion of them drops.
  virtual std::uint64_t records_with_ignored_fields() const { return 0; }
  // What the input is: "container", "zstd" (plain zstd) or "plain".
  virtual std::string_view input_kind() const { return "plain"; }
  // Container data frames decompressed / skipped by keep_data_frame so far
  // (counted as next() delivers them, so the figures do not depend on the
  // thread count).
  virtual std::uint64_t data_frames_decompressed() const { return 0; }
  virtual std::uint64_t data_frames_skipped() const { return 0; }
};

}  // namespace nodetrace::formats
