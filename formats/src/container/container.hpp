// The container's fixed numbers and the trailer's encoding (internal);
// formats/FORMAT.md specifies every byte.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "nodetrace/formats/container/metadata.hpp"

namespace nodetrace::formats::detail {

inline constexpr std::uint32_t kHeaderMagic = 0x184D2A50;
inline constexpr std::uint32_t kMarkerMagic = 0x184D2A51;
inline constexpr std::uint32_t kWindowMagic = 0x184D2A52;
inline constexpr std::uint32_t kTreeletMapMagic = 0x184D2A53;  // follows its animation frame's marker
inline constexpr std::uint32_t kTrailerMagic = 0x184D2A5E;
inline constexpr std::uint32_t kSkippableMask = 0xFFFFFFF0;  // 0x184D2A50..5F are skippable
inline constexpr std::uint32_t kZstdMagic = 0xFD2FB528;
inline constexpr std::uint32_t kFooterMagic = 0x5254544E;  // bytes "NTTR"
inline constexpr std::uint32_t kContainerVersion = 1;
inline constexpr std::size_t kFooterSize = 20;
inline constexpr std::size_t kSkippableHeaderSize = 8;
inline constexpr const char* kContainerName = "nodetrace-trace";

inline std::uint32_t load_le32(const void* bytes) {
  const auto* b = static_cast<const unsigned char*>(bytes);
  return b[0] | (b[1] << 8) | (b[2] << 16) | (std::uint32_t{b[3]} << 24);
}
inline std::uint64_t load_le64(const void* bytes) {
  const auto* b = static_cast<const unsigned char*>(bytes);
  return load_le32(b) | (std::uint64_t{load_le32(b + 4)} << 32);
}
inline void append_le32(std::string& out, std::uint32_t value) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>(value >> (8 * i)));
}
inline void append_le64(std::string& out, std::uint64_t value) {
  for (int i = 0; i < 8; ++i) out.push_back(static_cast<char>(value >> (8 * i)));
}

// A whole skippable frame: magic, payload size, payload.
std::string skippable_frame(std::uint32_t magic, std::string_view payload);

// The trailer's skippable frame, footer included.
std::string encode_trailer(const TraceTrailer& trailer);
// Parses the trailer's JSON (the payload without the footer); throws
// base::FormatError with a message that does not name the source.
TraceTrailer decode_trailer_json(std::string_view json);

std::string hash_text(std::uint64_t hash);  // 16 lower-case hex digits

}  // namespace nodetrace::formats::detail
