// Many rays in flight: the order in which traversal units, each with several
// ray slots, issue the node fetches of their rays (docs/guide/rays-in-flight.md).
//
// Each unit has `rays_in_flight` slots. A step is: every free slot takes the
// next ready ray of its unit (slots in order), then every busy slot issues
// its ray's next fetch (slots in order); a ray whose last fetch that was
// finishes and frees its slot for the next step. Units step together: the
// fetches of step s are unit 0's (in slot order), then unit 1's, and so on.
// Ready rays come from the unit's queue: the secondary rays (shadow,
// reflection, refraction) of the rays that have finished, always ahead of
// the next primary ray, then the primary rays of the unit's pixels in the
// order they were added. When several rays finish in one step, their
// secondary rays join the queue together, in slot order, each ray's in the
// order cast. With one unit of one slot and the default order this is the
// order of a sequential render: pixel by pixel, each ray tree depth first.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <string_view>
#include <vector>

#include "nodetrace/formats/record/record.hpp"

namespace nodetrace::tracer {

// Where the secondary rays of a finished ray join the unit's queue.
enum class ReadyOrder : std::uint8_t {
  DepthFirst,    // at its front: a pixel's rays stay together (one slot: the sequential order)
  BreadthFirst,  // behind the secondary rays already waiting (still ahead of the primary rays)
};
std::string_view ready_order_name(ReadyOrder order);  // depth-first, breadth-first
std::optional<ReadyOrder> parse_ready_order(std::string_view name);

// One pixel's rays as the renderer casts them: ray 0 is the primary ray, each
// other ray names its parent (an earlier ray, whose hit it depends on), and a
// parent's secondary rays are in the order it casts them. Each ray's fetches
// are records [begin, end) of `records`.
struct PixelRays {
  static constexpr std::uint32_t kNoParent = ~std::uint32_t{0};
  struct Ray {
    std::uint32_t parent = kNoParent;
    std::uint32_t begin = 0, end = 0;
  };
  std::vector<Ray> rays;
  std::vector<formats::Record> records;
};

class RayScheduler {
 public:
  // Throws base::UsageError unless 1 <= units <= formats::kMaxUnits and
  // rays_in_flight >= 1.
  RayScheduler(unsigned units, unsigned rays_in_flight, ReadyOrder order);

  // Queues the pixel's primary ray behind `unit`'s primary rays. Its rays
  // must form a tree as PixelRays says (checked: base::UsageError).
  void add_pixel(unsigned unit, PixelRays pixel);

  // Runs whole steps, appending each fetch to `out` with its unit set. Stops
  // before a step in which a free slot of some unit would find its queue
  // empty while more pixels may come (returns false: add pixels and call
  // again); with `no_more_pixels` runs to the end (returns true).
  bool run(std::vector<formats::Record>& out, bool no_more_pixels);

  // Pixels added and not yet finished (their rays are held).
  std::size_t pixels_held() const { return pool_.size() - free_.size(); }

 private:
  struct RayRef {
    std::uint32_t pixel = 0, ray = 0;
  };
  struct Slot {
    bool busy = false;
    RayRef ray;
    // Records still to issue, in the pixel's records (whose buffer stays put
    // while pool_ grows: a moved vector keeps it).
    const formats::Record* next = nullptr;
    const formats::Record* end = nullptr;
  };
  struct Unit {
    std::vector<Slot> slots;
    std::deque<RayRef> secondary;
    std::deque<std::uint32_t> primaries;  // pixels whose primary ray waits
  };
  struct HeldPixel {
    PixelRays rays;
    std::vector<std::uint32_t> child_begin;  // ray r's children: children[child_begin[r], child_begin[r + 1])
    std::vector<std::uint32_t> children;
    std::uint32_t unfinished = 0;
  };

  // Fills the free slots of `unit`; false when one waits for a pixel.
  bool refill(Unit& unit, bool no_more_pixels);
  // A ray is done: its secondary rays go to `ready`, and its pixel is
  // released after its last ray.
  void finish(RayRef ray, std::vector<RayRef>& ready);
  void make_ready(Unit& unit, const std::vector<RayRef>& ready);

  ReadyOrder order_;
  std::vector<Unit> units_;
  std::vector<HeldPixel> pool_;
  std::vector<std::uint32_t> free_;  // unused entries of pool_
  std::vector<RayRef> ready_;        // scratch: rays made ready in one step by one unit
};

}  // namespace nodetrace::tracer
