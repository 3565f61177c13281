// Which animation frames a command renders or describes: `--frames A-B` or
// `A-B:STEP` (every STEP-th frame from A up to B), or one `--frame N`; and
// the check that they exist in a scene. One parser and one check for every
// front end.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace nodetrace::tracer {

struct AnimationFrameRange {
  std::uint64_t first = 0, last = 0;
  std::uint64_t step = 1;
  // first, first + step, ... up to last.
  std::vector<std::uint64_t> frames() const;
  std::uint64_t count() const { return (last - first) / step + 1; }
};

// "A-B" or "A-B:STEP" with A <= B and STEP >= 1; throws base::UsageError
// naming `option` otherwise.
AnimationFrameRange parse_frame_range(std::string_view text, std::string_view option = "--frames");

// Throws base::UsageError when the range reaches past the `frames` frames
// of `scene` (its name, for the message).
void check_frame_range(const AnimationFrameRange& range, std::uint64_t frames, const std::string& scene);

}  // namespace nodetrace::tracer
