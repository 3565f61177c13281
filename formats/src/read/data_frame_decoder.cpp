// One data frame decoded into pieces (data_frame_decoder.hpp).
#define ZSTD_STATIC_LINKING_ONLY  // ZSTD_getFrameHeader, ZSTD_decompressBound, the buffer-less API
#include "read/data_frame_decoder.hpp"

#include <zstd.h>

#include <fmt/format.h>

#include <cstring>

#include "nodetrace/base/error.hpp"
#include "read/reader_kinds.hpp"

namespace nodetrace::formats::detail {
namespace {

// Records per piece handed over (the pieces waiting: data_frame_decoder.hpp).
constexpr std::size_t kPieceRecords = 1u << 14;
// The largest zstd window a reader decodes (zstd's own default limit).
constexpr std::uint64_t kMaxWindow = 1ull << 27;

// Where the records of `text` end: after the last newline, or the last whole
// binary record.
std::size_t whole_records(const char* text, std::size_t size, RecordForm form) {
  if (form == RecordForm::Binary) return size - size % 8;
  const void* newline = size == 0 ? nullptr : ::memrchr(text, '\n', size);
  return newline == nullptr ? 0 : static_cast<std::size_t>(static_cast<const char*>(newline) - text) + 1;
}

// Decompresses and parses one data frame (on a worker) step by step into
// pieces, its text into `hash` (when not nullptr) as data frame
// `hash_frame`; damage goes into a piece's frame_error for the reader to
// report with the frame's place. A bad record is reported only once the
// rest of the frame has decompressed without damage (damage is the better
// answer). True when the whole frame was handed over without damage.
bool decode_data_frame(const std::string& frame, ParseSettings settings, RecordHashChain* hash,
                       std::uint64_t hash_frame, Stock& stock, PieceStream& out) {
  const auto fail_frame = [&](std::string message) {
    Chunk chunk;
    chunk.frame_error = std::move(message);
    out.push(std::move(chunk));
    return false;
  };
  ZSTD_frameHeader header{};
  const std::size_t status = ZSTD_getFrameHeader(&header, frame.data(), frame.size());
  if (ZSTD_isError(status) || status != 0) return fail_frame("damaged zstd frame header");
  if (header.frameContentSize == ZSTD_CONTENTSIZE_UNKNOWN || !header.checksumFlag) {
    return fail_frame("a data frame must record its content size and checksum");
  }
  const unsigned long long bound = ZSTD_decompressBound(frame.data(), frame.size());
  if (bound == ZSTD_CONTENTSIZE_ERROR || header.frameContentSize > bound) {
    return fail_frame("damaged zstd frame (content size does not match its blocks)");
  }
  if (header.windowSize > kMaxWindow) {
    return fail_frame(fmt::format("damaged zstd frame (a window of {} bytes, more than a reader allows)", header.windowSize));
  }
  // Block by block (zstd's buffer-less API) into a ring that holds the
  // window: each block is parsed where zstd put it, with no copy out of a
  // stream buffer. A record cut by the ring's wrap is joined in `seam`.
  thread_local std::unique_ptr<ZSTD_DCtx, decltype(&ZSTD_freeDCtx)> context(ZSTD_createDCtx(), &ZSTD_freeDCtx);
  thread_local ByteBuffer small_window_ring;
  thread_local ByteBuffer held_text;  // text the record hash cannot take yet
  held_text.clear();
  ByteBuffer& ring = header.windowSize > kSmallWindow ? stock.large_window_ring : small_window_ring;
  const std::size_t ring_size = ZSTD_decodingBufferSize_min(header.windowSize, header.frameContentSize);
  if (ZSTD_isError(ring_size)) return fail_frame("damaged zstd frame (its window does not fit in memory)");
  if (ring.size() > 2 * ring_size + (1u << 20)) ring = ByteBuffer{};  // a much larger ring is not kept
  if (ring.size() < std::max<std::size_t>(ring_size, 1)) ring.resize(std::max<std::size_t>(ring_size, 1));
  // A frame no larger than the ring is decoded straight through.
  const bool wraps = ring_size < header.frameContentSize;
  const std::size_t status_begin = ZSTD_decompressBegin(context.get());
  if (ZSTD_isError(status_begin)) return fail_frame(fmt::format("cannot decode ({})", ZSTD_getErrorName(status_begin)));
  const char* src = frame.data();
  std::size_t src_left = frame.size();
  std::size_t pos = 0;    // where the next block goes in the ring
  std::size_t parse = 0;  // the first byte in the ring not yet parsed
  ByteBuffer seam;        // a record cut by the wrap
  std::uint64_t total = 0;
  char last_byte = '\n';
  Chunk piece;
  Chunk bad;  // the piece with the first bad record, held until the frame is known undamaged
  bool have_bad = false;
  const auto parse_text = [&](const char* text, std::size_t size) {
    if (piece.records.capacity() == 0) piece.records = stock.records.take();
    const std::size_t before = piece.records.size();
    piece.records.reserve(before + size / 14 + 16);
    if (!parse_records(std::string_view(text, size), settings, piece.records, piece.record_error,
                       piece.ignored_fields)) {
      piece.bad_record = true;
      piece.record_error.record_in_chunk += before;
      bad = std::move(piece);
      have_bad = true;
      return;
    }
    piece.decoded_bytes += size;
    if (hash) hash->add(hash_frame, text, size, held_text);
  };
  for (;;) {
    const std::size_t need = ZSTD_nextSrcSizeToDecompress(context.get());
    if (need == 0) break;
    if (need > src_left) return fail_frame("damaged zstd frame (it ends inside a block)");
    if (wraps && ring_size - pos < header.blockSizeMax) {  // wrap, as zstd's own streaming does
      seam.append(ring.data() + parse, pos - parse);
      pos = parse = 0;
    }
    const std::size_t got = ZSTD_decompressContinue(context.get(), ring.data() + pos, ring_size - pos, src, need);
    if (ZSTD_isError(got)) return fail_frame(fmt::format("damaged zstd frame ({})", ZSTD_getErrorName(got)));
    src += need;
    src_left -= need;
    if (got == 0) continue;
    total += got;
    char* const block = ring.data() + pos;
    last_byte = block[got - 1];
    pos += got;
    if (have_bad) {  // only looking for damage now
      parse = pos;
      seam.clear();
      continue;
    }
    if (!seam.empty()) {
      // Complete the cut record with the new block's first bytes.
      std::size_t take = got;
      if (settings.form == RecordForm::Binary) {
        take = std::min(got, (8 - seam.size() % 8) % 8);
      } else if (const void* newline = std::memchr(block, '\n', got)) {
        take = static_cast<std::size_t>(static_cast<const char*>(newline) - block) + 1;
      }
      seam.append(block, take);
      parse = pos - got + take;
      const std::size_t cut = whole_records(seam.data(), seam.size(), settings.form);
      if (cut == 0 && parse == pos) continue;  // the record goes on past this block
      parse_text(seam.data(), cut);
      if (have_bad) continue;
      seam.clear();
    }
    const std::size_t cut = whole_records(ring.data() + parse, pos - parse, settings.form);
    parse_text(ring.data() + parse, cut);
    if (have_bad) continue;
    parse += cut;
    if (piece.records.size() >= kPieceRecords) {
      piece.kinds = record_kinds(piece.records.data(), piece.records.size());
      if (!out.push(std::move(piece))) return false;  // abandoned
      piece = Chunk{};
    }
  }
  if (src_left != 0) return fail_frame("damaged zstd frame (bytes after its end)");
  // Anything left unparsed is a last record cut short: the boundary check below names it.
  if (total != header.frameContentSize) return fail_frame("damaged zstd frame (wrong content size)");
  const bool whole = settings.form == RecordForm::Binary ? total % 8 == 0 : total == 0 || last_byte == '\n';
  if (!whole) return fail_frame("data frame does not end at a record boundary");
  if (hash && !have_bad) hash->end_frame(hash_frame, held_text);
  piece.kinds = record_kinds(piece.records.data(), piece.records.size());
  return out.push(std::move(have_bad ? bad : piece)) && !have_bad;
}

}  // namespace

void decode_into(const std::string& frame, ParseSettings settings, RecordHashChain* hash, std::uint64_t hash_frame,
                 Stock& stock, PieceStream& stream, PieceStream* earlier) {
  bool whole = false;
  try {
    if (earlier) earlier->wait_closed();
    whole = decode_data_frame(frame, settings, hash, hash_frame, stock, stream);
  } catch (const std::exception& error) {
    Chunk chunk;
    chunk.frame_error = fmt::format("cannot decode: {}", error.what());
    stream.push(std::move(chunk));
  }
  if (hash && !whole) hash->abandon();
  stream.close();
}

}  // namespace nodetrace::formats::detail
