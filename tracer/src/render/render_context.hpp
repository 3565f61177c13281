// What one worker of the render loop carries while it renders a chunk of
// pixels; the shader appends records to it. Internal header.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "nodetrace/tracer/render/render.hpp"

namespace nodetrace::tracer {

// A ray tree of depth D may hold up to 2^D rays (reflection and refraction
// at every hit), so its records are not kept whole: once `records` holds
// flush_at, `flush` hands them on in order (waiting, with threads, until
// every earlier chunk has been emitted). Memory per pixel is the recursion,
// O(max depth).
struct Renderer::Context {
  std::vector<formats::Record>* records = nullptr;
  RenderStats stats;
  std::function<void()> flush;
  std::uint64_t flushed = 0;  // records already handed on
  std::size_t flush_at = 0;
  void maybe_flush() {
    if (records && flush && records->size() >= flush_at) flush();
  }
};

}  // namespace nodetrace::tracer
