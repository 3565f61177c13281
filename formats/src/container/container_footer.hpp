// Recognising a container by its footer (internal; FORMAT.md section 3, rule
// 0): a file whose last 20 bytes lead back to a trailer frame is a container
// whatever its first bytes say, and a damaged header magic is reported as
// such rather than read as plain records.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "read/input.hpp"

namespace nodetrace::formats::detail {

// True when `footer` (the last 20 bytes of an input of `size` bytes) is a
// container footer and, for a seekable input, its length leads to a trailer
// frame (a stream cannot look back: the footer's magic and version say enough).
bool footer_leads_to_trailer(const Input& input, std::string_view footer, std::uint64_t size);

// True when the last bytes of the seekable `input` are such a footer.
bool ends_with_container_footer(const Input& input);

// A container whose header magic (its first 4 bytes, `first_bytes`) is
// damaged: names the first byte that differs from 50 2A 4D 18. `what` is
// "the file" or "the stream".
[[noreturn]] void fail_damaged_header_magic(const std::string& name, const std::string& first_bytes,
                                            const char* what);

}  // namespace nodetrace::formats::detail
