#include "nodetrace/tracer/render/ray_scheduler.hpp"

#include <fmt/format.h>

#include <cstdint>

#include "nodetrace/base/error.hpp"

namespace nodetrace::tracer {

namespace {

// Asks for the cache line `bytes` past `record`, which may lie past its
// array: computed as an integer, since a pointer may not point there.
inline void prefetch_ahead(const formats::Record* record, std::uintptr_t bytes) {
  __builtin_prefetch(reinterpret_cast<const void*>(reinterpret_cast<std::uintptr_t>(record) + bytes));
}

}  // namespace

std::string_view ready_order_name(ReadyOrder order) {
  return order == ReadyOrder::DepthFirst ? "depth-first" : "breadth-first";
}

std::optional<ReadyOrder> parse_ready_order(std::string_view name) {
  if (name == "depth-first") return ReadyOrder::DepthFirst;
  if (name == "breadth-first") return ReadyOrder::BreadthFirst;
  return std::nullopt;
}

RayScheduler::RayScheduler(unsigned units, unsigned rays_in_flight, ReadyOrder order) : order_(order) {
  if (units < 1 || units > formats::kMaxUnits) {
    throw base::UsageError(fmt::format("traversal units must be 1 to {}, not {}", formats::kMaxUnits, units));
  }
  if (rays_in_flight < 1) throw base::UsageError("rays in flight must be at least 1");
  units_.resize(units);
  for (Unit& unit : units_) unit.slots.resize(rays_in_flight);
}

void RayScheduler::add_pixel(unsigned unit, PixelRays pixel) {
  if (unit >= units_.size()) {
    throw base::UsageError(fmt::format("unit {} is not one of the scheduler's {}", unit, units_.size()));
  }
  const auto rays = static_cast<std::uint32_t>(pixel.rays.size());
  if (rays == 0) throw base::UsageError("a pixel has at least its primary ray");
  HeldPixel held;
  held.child_begin.assign(std::size_t{rays} + 1, 0);
  for (std::uint32_t r = 0; r < rays; ++r) {
    const PixelRays::Ray& ray = pixel.rays[r];
    if ((r == 0) != (ray.parent == PixelRays::kNoParent) || (r > 0 && ray.parent >= r) || ray.begin > ray.end ||
        ray.end > pixel.records.size()) {
      throw base::UsageError(fmt::format("ray {} of a pixel: its parent or its records are not a ray tree's", r));
    }
    if (r > 0) ++held.child_begin[ray.parent + 1];
  }
  for (std::uint32_t r = 0; r < rays; ++r) held.child_begin[r + 1] += held.child_begin[r];
  held.children.resize(rays - 1);
  std::vector<std::uint32_t> placed(held.child_begin.begin(), held.child_begin.end() - 1);
  for (std::uint32_t r = 1; r < rays; ++r) held.children[placed[pixel.rays[r].parent]++] = r;
  held.unfinished = rays;
  held.rays = std::move(pixel);
  std::uint32_t index;
  if (!free_.empty()) {
    index = free_.back();
    free_.pop_back();
    pool_[index] = std::move(held);
  } else {
    index = static_cast<std::uint32_t>(pool_.size());
    pool_.push_back(std::move(held));
  }
  units_[unit].primaries.push_back(index);
}

void RayScheduler::finish(RayRef ray, std::vector<RayRef>& ready) {
  HeldPixel& pixel = pool_[ray.pixel];
  for (std::uint32_t c = pixel.child_begin[ray.ray]; c < pixel.child_begin[ray.ray + 1]; ++c) {
    ready.push_back({ray.pixel, pixel.children[c]});
  }
  if (--pixel.unfinished == 0) {
    pixel = HeldPixel{};  // frees its records
    free_.push_back(ray.pixel);
  }
}

void RayScheduler::make_ready(Unit& unit, const std::vector<RayRef>& ready) {
  if (order_ == ReadyOrder::DepthFirst) {
    unit.secondary.insert(unit.secondary.begin(), ready.begin(), ready.end());
  } else {
    unit.secondary.insert(unit.secondary.end(), ready.begin(), ready.end());
  }
}

bool RayScheduler::refill(Unit& unit, bool no_more_pixels) {
  for (Slot& slot : unit.slots) {
    while (!slot.busy) {
      RayRef ray;
      if (!unit.secondary.empty()) {
        ray = unit.secondary.front();
        unit.secondary.pop_front();
      } else if (!unit.primaries.empty()) {
        ray = {unit.primaries.front(), 0};
        unit.primaries.pop_front();
      } else if (no_more_pixels) {
        break;  // the slot idles: its unit has no work left
      } else {
        return false;
      }
      const PixelRays& pixel = pool_[ray.pixel].rays;
      const PixelRays::Ray& traced = pixel.rays[ray.ray];
      if (traced.begin == traced.end) {
        // A ray that fetches nothing finishes as it starts.
        ready_.clear();
        finish(ray, ready_);
        make_ready(unit, ready_);
        continue;
      }
      slot = {true, ray, pixel.records.data() + traced.begin, pixel.records.data() + traced.end};
      for (std::uintptr_t line = 0; line < 4; ++line) prefetch_ahead(slot.next, 64 * line);  // run() reads 16 ahead
    }
  }
  return true;
}

bool RayScheduler::run(std::vector<formats::Record>& out, bool no_more_pixels) {
  for (;;) {
    for (Unit& unit : units_) {
      if (!refill(unit, no_more_pixels)) return false;
    }
    bool busy = false;
    for (std::size_t u = 0; u < units_.size(); ++u) {
      Unit& unit = units_[u];
      const formats::TraversalUnit unit_field = formats::traversal_unit(static_cast<unsigned>(u));
      ready_.clear();
      for (Slot& slot : unit.slots) {
        if (!slot.busy) continue;
        busy = true;
        formats::Record record = *slot.next;
        // The records were traced on another core a while ago: fetch a few
        // cache lines ahead of each slot (measured: loading them was most of
        // the scheduler's time at 32 rays in flight).
        prefetch_ahead(slot.next, 16 * sizeof(formats::Record));
        record.unit = unit_field;
        out.push_back(record);
        if (++slot.next == slot.end) {
          slot.busy = false;
          finish(slot.ray, ready_);
        }
      }
      if (!ready_.empty()) make_ready(unit, ready_);
    }
    if (!busy) return true;  // every slot idle after a refill with no more pixels: done
  }
}

}  // namespace nodetrace::tracer
