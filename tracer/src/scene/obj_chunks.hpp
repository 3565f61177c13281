// Reading an OBJ text in chunks on several threads, with the result of
// read_obj_one_thread for every file it accepts.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "scene/obj_mesh.hpp"

namespace nodetrace::tracer::detail {

// `text` cut into at most `count` chunks, each a run of whole lines ending
// after a '\n' (the last one at the end of the text); no chunk is empty.
std::vector<std::string_view> split_at_lines(std::string_view text, std::size_t count);

// Runs job(i) for i in [0, count) on up to `threads` threads (0: one per
// core); rethrows the exception of the lowest i that threw.
void for_each_chunk(std::size_t count, unsigned threads, const std::function<void(std::size_t)>& job);

// Threads for a load: `requested`, or one per core for 0.
unsigned load_threads(unsigned requested);

// The chunks (consecutive, together the whole text) each parsed by
// tinyobjloader's callback API on its own thread; then the chunks' vertex
// and normal counts give the relative (negative) indices their offsets,
// quads are split as LoadObj splits them, and the `mtllib` / `usemtl`
// lines, found by a scan of each chunk, give each face LoadObj's material.
// nullopt for a file this cannot read exactly as LoadObj does (faces of
// more than 4 corners, whose triangulation is tinyobjloader's own; `l`, `p`
// or `vw` lines, which LoadObj checks; a nameless `g`; a lone CR or a NUL
// byte; a quad whose split is a tie within rounding, or that refers ahead
// to a vertex): read it with read_obj_one_thread.
std::optional<ObjMesh> read_obj_chunks(std::span<const std::string_view> chunks, tinyobj::MaterialReader& material_reader,
                                       unsigned threads);

}  // namespace nodetrace::tracer::detail
