// One trace of a render in one layout.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "nodetrace/tracer/accel/layout.hpp"

namespace nodetrace::tracer {

// One more trace of the same render in another layout: the rays visit the
// same nodes in the same order whatever the layout, only the addresses
// differ, so each further layout costs a remapping of the records, not a
// render. Its trace equals, byte for byte, the one a render with that layout
// alone writes.
struct LayoutTrace {
  LayoutKind layout = LayoutKind::Dfl;
  std::optional<std::uint32_t> split_level;  // hybrid: a fixed K ...
  std::optional<std::uint64_t> high_size;    // ... or K from the high cache's size
  std::string output;  // the trace file; empty: none (other sinks may still take the records)
};

}  // namespace nodetrace::tracer
