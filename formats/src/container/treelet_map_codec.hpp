// The bytes of a treelet map frame's payload (internal; FORMAT.md 2.2.2).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "nodetrace/formats/container/treelet_map.hpp"

namespace nodetrace::formats::detail {

// The payload: varints, zstd-compressed when that is smaller. `map` must be
// sorted and free of overlaps (check_treelet_map): gaps are unsigned.
std::string encode_treelet_map(const TreeletMap& map);

// Parses a payload whose first byte is byte `payload_offset` of the file.
// Throws base::FormatError naming the byte (of the file, or of the
// decompressed body) where it found damage; the message does not name the
// source. `max_treelets` bounds what the map may claim (the frame's nodes:
// each treelet holds one at least), and so the memory it takes.
TreeletMap decode_treelet_map(std::string_view payload, std::uint64_t payload_offset, std::uint64_t max_treelets);

}  // namespace nodetrace::formats::detail
