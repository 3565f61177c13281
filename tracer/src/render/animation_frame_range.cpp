#include "nodetrace/tracer/render/animation_frame_range.hpp"

#include <charconv>

#include "nodetrace/base/error.hpp"

namespace nodetrace::tracer {

std::vector<std::uint64_t> AnimationFrameRange::frames() const {
  std::vector<std::uint64_t> result;
  result.reserve(count());
  for (std::uint64_t f = first;; f += step) {
    result.push_back(f);
    if (last - f < step) break;  // the next one would pass `last` (or wrap)
  }
  return result;
}

namespace {

bool parse_whole(std::string_view text, std::uint64_t& value) {
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  return !text.empty() && error == std::errc() && end == text.data() + text.size();
}

}  // namespace

AnimationFrameRange parse_frame_range(std::string_view text, std::string_view option) {
  const auto fail = [&](std::string_view why) {
    throw base::UsageError(std::string(option) + ": expected A-B or A-B:STEP such as 0-9 or 0-99:10, got '" +
                              std::string(text) + "'" + std::string(why));
  };
  AnimationFrameRange range;
  std::string_view span = text;
  if (const auto colon = text.find(':'); colon != std::string_view::npos) {
    span = text.substr(0, colon);
    if (!parse_whole(text.substr(colon + 1), range.step)) fail("");
    if (range.step == 0) fail(" (STEP is at least 1)");
  }
  const auto dash = span.find('-');
  if (dash == std::string_view::npos || !parse_whole(span.substr(0, dash), range.first) ||
      !parse_whole(span.substr(dash + 1), range.last)) {
    fail("");
  }
  if (range.last < range.first) throw base::UsageError(std::string(option) + " A-B needs A <= B");
  return range;
}

void check_frame_range(const AnimationFrameRange& range, std::uint64_t frames, const std::string& scene) {
  if (range.last >= frames) {
    throw base::UsageError("frame " + std::to_string(range.last) + " is out of range: " + scene + " has " +
                              std::to_string(frames) + " frame(s), numbered from 0");
  }
}

}  // namespace nodetrace::tracer
