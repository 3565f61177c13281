// What every loader checks of a triangle it adds (internal): coordinates
// finite and within the range the renderer supports, and zero-area
// triangles dropped, counted for one summary warning.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "nodetrace/tracer/scene/scene.hpp"

namespace nodetrace::tracer::detail {

class TriangleChecks {
 public:
  // Throws SceneError naming `where()` ("file:line") for a coordinate that
  // is not finite or beyond +-kMaxSceneCoordinate. Returns false for a
  // zero-area triangle, which the loader drops; the first one's `where()` is
  // kept for the warning. `where` is called only then: a loader's per-line
  // text costs more than the checks.
  bool keep(const Triangle& triangle, const std::function<std::string()>& where);
  // "N zero-area triangles dropped (the first at FILE:LINE)", if any.
  std::optional<std::string> warning() const;

 private:
  std::uint64_t dropped_ = 0;
  std::string first_dropped_;
};

// Throws SceneError naming `where` for a coordinate out of range (the
// check of keep() alone, for coordinates known only after transforms).
void check_coordinates_in_range(const Triangle& triangle, const std::function<std::string()>& where);

}  // namespace nodetrace::tracer::detail
