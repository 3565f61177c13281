// The checks of an OBJ text's `v`, `vn`, `vt` and `f` lines that
// tinyobjloader does not make, chunk by chunk on several threads.
#pragma once

#include <filesystem>
#include <span>
#include <string_view>

namespace nodetrace::tracer::detail {

// tinyobjloader reads a malformed or non-finite coordinate as some number
// without complaint, and trusts face indices (an index past the end reads
// past its arrays): throws SceneError naming the first bad line of the
// text (`chunks`, consecutive, each but the last ending a line), the same
// whatever the chunks and threads. A positive index counts from the file's
// first element of its kind (as tinyobjloader reads it, so a forward
// reference works), a negative one back from the line.
void check_obj_lines(std::span<const std::string_view> chunks, const std::filesystem::path& path, unsigned threads);

}  // namespace nodetrace::tracer::detail
