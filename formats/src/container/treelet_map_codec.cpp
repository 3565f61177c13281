// Treelet map payloads (FORMAT.md 2.2.2): a count, a unit, and per treelet
// its length in units with one bit saying whether a gap (in units) since the
// previous treelet's end follows. Treelets of a treelet layout are adjacent
// and of a few lengths, so most take one byte, and zstd shrinks the run of
// near-equal bytes further.
#define ZSTD_STATIC_LINKING_ONLY  // ZSTD_getFrameHeader
#include "container/treelet_map_codec.hpp"

#include <zstd.h>

#include <fmt/format.h>

#include <numeric>

#include "nodetrace/base/error.hpp"

namespace nodetrace::formats::detail {
namespace {

constexpr unsigned char kPlain = 0;
constexpr unsigned char kZstd = 1;
// Small maps, compressed once per animation frame: the strongest level
// costs milliseconds.
constexpr int kMapZstdLevel = 19;
constexpr std::size_t kMaxVarintBytes = 10;

void append_varint(std::string& out, std::uint64_t value) {
  while (value >= 0x80) {
    out.push_back(static_cast<char>((value & 0x7F) | 0x80));
    value >>= 7;
  }
  out.push_back(static_cast<char>(value));
}

std::string encode_body(const TreeletMap& map) {
  std::uint64_t unit = 0;
  for (const TreeletRange& t : map.treelets) unit = std::gcd(std::gcd(unit, t.first), t.bytes);
  if (unit == 0) unit = 1;
  std::string body;
  append_varint(body, map.treelets.size());
  append_varint(body, unit);
  std::uint64_t end = 0;
  for (const TreeletRange& t : map.treelets) {
    const std::uint64_t gap = (t.first - end) / unit;
    append_varint(body, (t.bytes / unit) << 1 | (gap != 0 ? 1 : 0));
    if (gap != 0) append_varint(body, gap);
    end = t.first + t.bytes;
  }
  return body;
}

// Reads the body's varints, naming damage by the byte it is at: byte
// `offset` + i of the file, or of the decompressed body.
class BodyReader {
 public:
  BodyReader(std::string_view body, std::uint64_t offset, bool decompressed)
      : body_(body), offset_(offset), decompressed_(decompressed) {}

  std::uint64_t varint(const char* what) {
    const std::size_t start = position_;
    std::uint64_t value = 0;
    for (unsigned shift = 0;; shift += 7) {
      if (position_ >= body_.size()) fail(start, fmt::format("the map ends inside {}", what));
      if (position_ - start >= kMaxVarintBytes) fail(start, fmt::format("{} is longer than 10 bytes", what));
      const auto byte = static_cast<unsigned char>(body_[position_++]);
      const std::uint64_t bits = byte & 0x7F;
      if (shift == 63 && bits > 1) fail(start, fmt::format("{} is above 2^64 - 1", what));
      value |= bits << shift;
      if ((byte & 0x80) == 0) return value;
    }
  }

  bool at_end() const { return position_ == body_.size(); }
  std::size_t position() const { return position_; }

  [[noreturn]] void fail(std::size_t at, const std::string& what) const {
    throw base::FormatError(decompressed_
                                ? fmt::format("byte {} of its decompressed content: {}", at, what)
                                : fmt::format("byte {}: {}", offset_ + at, what));
  }

 private:
  std::string_view body_;
  std::uint64_t offset_;
  bool decompressed_;
  std::size_t position_ = 0;
};

TreeletMap decode_body(std::string_view body, std::uint64_t offset, bool decompressed, std::uint64_t max_treelets) {
  BodyReader in(body, offset, decompressed);
  const std::uint64_t count = in.varint("the treelet count");
  if (count > max_treelets) {
    in.fail(0, fmt::format("{} treelets, more than the frame's {} nodes (a treelet holds one at least)", count,
                           max_treelets));
  }
  const std::size_t unit_at = in.position();
  const std::uint64_t unit = in.varint("the unit");
  if (unit == 0) in.fail(unit_at, "the unit is 0 bytes");
  TreeletMap map;
  map.treelets.reserve(static_cast<std::size_t>(count));
  constexpr std::uint64_t kTop = ~std::uint64_t{0};
  std::uint64_t end = 0;
  for (std::uint64_t i = 0; i < count; ++i) {
    const std::size_t at = in.position();
    const std::uint64_t length = in.varint("a treelet's length");
    const std::uint64_t gap = (length & 1) != 0 ? in.varint("a treelet's gap") : 0;
    const std::uint64_t units = length >> 1;
    if (gap > (kTop - end) / unit || units > kTop / unit || units * unit > kTop - end - gap * unit) {
      in.fail(at, fmt::format("treelet {} runs past address 2^64 - 1", i + 1));
    }
    const TreeletRange range{end + gap * unit, units * unit};
    map.treelets.push_back(range);
    end = range.first + range.bytes;
  }
  if (!in.at_end()) {
    in.fail(in.position(), fmt::format("{} bytes after the last of its {} treelets", body.size() - in.position(),
                                       count));
  }
  return map;
}

}  // namespace

std::string encode_treelet_map(const TreeletMap& map) {
  const std::string body = encode_body(map);
  std::string compressed(ZSTD_compressBound(body.size()), '\0');
  const std::size_t size = ZSTD_compress(compressed.data(), compressed.size(), body.data(), body.size(), kMapZstdLevel);
  if (ZSTD_isError(size)) throw base::IoError(fmt::format("zstd compression failed: {}", ZSTD_getErrorName(size)));
  std::string payload(1, static_cast<char>(size < body.size() ? kZstd : kPlain));
  payload.append(size < body.size() ? std::string_view(compressed.data(), size) : std::string_view(body));
  return payload;
}

TreeletMap decode_treelet_map(std::string_view payload, std::uint64_t payload_offset, std::uint64_t max_treelets) {
  if (payload.empty()) throw base::FormatError(fmt::format("byte {}: the map is empty (no encoding byte)", payload_offset));
  const auto encoding = static_cast<unsigned char>(payload[0]);
  const std::string_view rest = payload.substr(1);
  if (encoding == kPlain) return decode_body(rest, payload_offset + 1, false, max_treelets);
  if (encoding != kZstd) {
    throw base::FormatError(fmt::format("byte {}: encoding {} is neither 0 (varints) nor 1 (zstd)", payload_offset,
                                        encoding));
  }
  const std::uint64_t frame_at = payload_offset + 1;
  ZSTD_frameHeader header{};
  if (ZSTD_getFrameHeader(&header, rest.data(), rest.size()) != 0 || header.frameType != ZSTD_frame) {
    throw base::FormatError(fmt::format("byte {}: no whole zstd frame header", frame_at));
  }
  // Two varints of 10 bytes at most per treelet, and the count and unit.
  const std::uint64_t most = 2 * kMaxVarintBytes * (max_treelets + 1);
  if (header.frameContentSize == ZSTD_CONTENTSIZE_UNKNOWN || header.frameContentSize > most) {
    throw base::FormatError(fmt::format("byte {}: the zstd frame does not say its content size, or says more than "
                                        "a map of the frame's {} nodes can take ({} bytes)",
                                        frame_at, max_treelets, most));
  }
  const std::size_t frame_size = ZSTD_findFrameCompressedSize(rest.data(), rest.size());
  if (ZSTD_isError(frame_size)) {
    throw base::FormatError(fmt::format("byte {}: the zstd frame is cut short or damaged ({})", frame_at,
                                        ZSTD_getErrorName(frame_size)));
  }
  if (frame_size != rest.size()) {
    throw base::FormatError(fmt::format("byte {}: {} bytes after the zstd frame", frame_at + frame_size,
                                        rest.size() - frame_size));
  }
  std::string body(static_cast<std::size_t>(header.frameContentSize), '\0');
  const std::size_t got = ZSTD_decompress(body.data(), body.size(), rest.data(), rest.size());
  if (ZSTD_isError(got) || got != body.size()) {
    throw base::FormatError(fmt::format("byte {}: the zstd frame is damaged ({})", frame_at,
                                        ZSTD_isError(got) ? ZSTD_getErrorName(got) : "content size differs"));
  }
  return decode_body(body, 0, true, max_treelets);
}

}  // namespace nodetrace::formats::detail
