// Rays in flight: the scheduler's order on hand-made rays (worked by hand
// below), its invariants on random ray trees, and the renderer's records
// with units and slots (one slot: the sequential order; any thread count:
// the same bytes).
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <string>

#include "nodetrace/base/error.hpp"
#include "nodetrace/tracer/accel/kdtree.hpp"
#include "nodetrace/tracer/accel/layout.hpp"
#include "nodetrace/tracer/render/ray_scheduler.hpp"
#include "nodetrace/tracer/render/render.hpp"
#include "test_render_scenes.hpp"

namespace nodetrace::tracer {
namespace {

using formats::Record;

// A ray of a hand-made pixel: its parent and its fetches, named by letters
// (a record's address is the letter's code, its tag the digit after it).
struct HandRay {
  std::uint32_t parent;
  std::vector<std::string> fetches;
};

PixelRays pixel(const std::vector<HandRay>& rays) {
  PixelRays pixel;
  for (const HandRay& ray : rays) {
    PixelRays::Ray traced{ray.parent, static_cast<std::uint32_t>(pixel.records.size()), 0};
    for (const std::string& name : ray.fetches) {
      pixel.records.push_back({.address = static_cast<std::uint64_t>(name[0]),
                               .size = 8,
                               .tag = static_cast<formats::Tag>(name[1] - '0')});
    }
    traced.end = static_cast<std::uint32_t>(pixel.records.size());
    pixel.rays.push_back(traced);
  }
  return pixel;
}

constexpr std::uint32_t kPrimary = PixelRays::kNoParent;

// Pixel A: primary a0 a1 a2; its shadow ray s0 s1 and reflection r0; the
// reflection's shadow ray t0 t1. B: primary b0 b1. C: primary c0.
PixelRays pixel_a() {
  return pixel({{kPrimary, {"a0", "a1", "a2"}}, {0, {"s0", "s1"}}, {0, {"r0"}}, {2, {"t0", "t1"}}});
}
PixelRays pixel_b() { return pixel({{kPrimary, {"b0", "b1"}}}); }
PixelRays pixel_c() { return pixel({{kPrimary, {"c0"}}}); }

// The fetches as "a0 b0 ..." (with "/u" after each when `units`).
std::string names(const std::vector<Record>& records, bool units = false) {
  std::string text;
  for (const Record& record : records) {
    if (!text.empty()) text += ' ';
    text += static_cast<char>(record.address);
    text += static_cast<char>('0' + record.tag);
    if (units) text += "/" + std::to_string(formats::unit_index(record.unit));
  }
  return text;
}

std::string schedule(unsigned slots, ReadyOrder order, std::vector<PixelRays> pixels) {
  RayScheduler scheduler(1, slots, order);
  for (PixelRays& p : pixels) scheduler.add_pixel(0, std::move(p));
  std::vector<Record> out;
  EXPECT_TRUE(scheduler.run(out, true));
  EXPECT_EQ(scheduler.pixels_held(), 0u);
  return names(out);
}

TEST(RayScheduler, OneSlotIsTheSequentialDepthFirstOrder) {
  EXPECT_EQ(schedule(1, ReadyOrder::DepthFirst, {pixel_a(), pixel_b(), pixel_c()}),
            "a0 a1 a2 s0 s1 r0 t0 t1 b0 b1 c0");
}

// Two slots. Step 1: A's and B's primaries (a0 b0); 2: a1 b1, B done;
// 3: slot 1 takes C (the queue has no secondary ray yet): a2 c0, A's primary
// done (its shadow and reflection rays join the queue), C done; 4: s0 r0,
// the reflection done (its shadow ray t joins); 5: s1 t0; 6: t1.
TEST(RayScheduler, TwoSlotsWorkedByHand) {
  EXPECT_EQ(schedule(2, ReadyOrder::DepthFirst, {pixel_a(), pixel_b(), pixel_c()}),
            "a0 b0 a1 b1 a2 c0 s0 r0 s1 t0 t1");
}

// Three slots: 1: a0 b0 c0 (C done, its slot idles: nothing is ready); 2: a1
// b1; 3: a2, then the secondary rays become ready mid-way; 4: s0 r0; 5: s1
// t0; 6: t1.
TEST(RayScheduler, ThreeSlotsWorkedByHand) {
  EXPECT_EQ(schedule(3, ReadyOrder::DepthFirst, {pixel_a(), pixel_b(), pixel_c()}),
            "a0 b0 c0 a1 b1 a2 s0 r0 s1 t0 t1");
}

// D: primary d0; its reflection x0 (whose shadow ray is y0) and refraction
// z0. Depth first, y (made ready by x) goes ahead of z; breadth first, behind.
TEST(RayScheduler, ReadyOrderPlacesNewSecondaryRays) {
  const auto d = [] { return pixel({{kPrimary, {"d0"}}, {0, {"x0"}}, {1, {"y0"}}, {0, {"z0"}}}); };
  EXPECT_EQ(schedule(1, ReadyOrder::DepthFirst, {d(), pixel_c()}), "d0 x0 y0 z0 c0");
  EXPECT_EQ(schedule(1, ReadyOrder::BreadthFirst, {d(), pixel_c()}), "d0 x0 z0 y0 c0");
}

TEST(RayScheduler, RaysWithoutFetchesFinishAsTheyStart) {
  // G's second ray fetches nothing; its own secondary ray h0 still comes.
  const PixelRays g = pixel({{kPrimary, {"g0"}}, {0, {}}, {1, {"h0"}}});
  const PixelRays empty = pixel({{kPrimary, {}}});
  EXPECT_EQ(schedule(1, ReadyOrder::DepthFirst, {g, empty, pixel_c()}), "g0 h0 c0");
  EXPECT_EQ(schedule(2, ReadyOrder::DepthFirst, {empty, g, pixel_c()}), "g0 c0 h0");
}

// Units step together: step s issues unit 0's fetches, then unit 1's.
TEST(RayScheduler, UnitsAreMergedByStepAndEachRecordCarriesItsUnit) {
  RayScheduler scheduler(2, 1, ReadyOrder::DepthFirst);
  scheduler.add_pixel(0, pixel({{kPrimary, {"a0", "a1"}}}));
  std::vector<Record> out;
  // Unit 1 has a free slot and nothing queued: wait for its pixels.
  EXPECT_FALSE(scheduler.run(out, false));
  EXPECT_TRUE(out.empty());
  scheduler.add_pixel(1, pixel_b());
  scheduler.add_pixel(1, pixel_c());
  EXPECT_FALSE(scheduler.run(out, false));  // unit 0's queue runs dry after step 2
  EXPECT_EQ(names(out, true), "a0/0 b0/1 a1/0 b1/1");
  EXPECT_TRUE(scheduler.run(out, true));
  EXPECT_EQ(names(out, true), "a0/0 b0/1 a1/0 b1/1 c0/1");
}

TEST(RayScheduler, RefusesWhatIsNoRayTree) {
  EXPECT_THROW(RayScheduler(0, 1, ReadyOrder::DepthFirst), base::UsageError);
  EXPECT_THROW(RayScheduler(1, 0, ReadyOrder::DepthFirst), base::UsageError);
  RayScheduler scheduler(1, 1, ReadyOrder::DepthFirst);
  EXPECT_THROW(scheduler.add_pixel(0, pixel({{kPrimary, {"a0"}}, {1, {"b0"}}})), base::UsageError);
  EXPECT_THROW(scheduler.add_pixel(0, PixelRays{}), base::UsageError);
  EXPECT_THROW(scheduler.add_pixel(1, pixel_c()), base::UsageError);
}

// Random ray trees: every fetch of every ray appears exactly once, with its
// pixel's unit; each ray's fetches keep their order; no ray issues before
// its parent's last fetch; at most `slots` rays of a unit per step.
TEST(RayScheduler, EveryFetchOnceInOrderAfterItsParent) {
  std::mt19937 engine(24);
  for (int round = 0; round < 40; ++round) {
    const unsigned units = 1 + engine() % 4, slots = 1 + engine() % 9;
    const ReadyOrder order = round % 2 ? ReadyOrder::BreadthFirst : ReadyOrder::DepthFirst;
    RayScheduler scheduler(units, slots, order);
    // Fetch (pixel, ray, i) is the record with address pixel << 32 | ray << 16 | i.
    std::map<std::uint64_t, std::pair<std::uint32_t, std::uint32_t>> parent_and_length;  // (pixel, ray) key
    std::vector<unsigned> unit_of;
    std::uint64_t total = 0;
    std::vector<Record> out;
    for (std::uint32_t p = 0; p < 60; ++p) {
      PixelRays pixel;
      const std::uint32_t rays = 1 + engine() % 8;
      for (std::uint32_t r = 0; r < rays; ++r) {
        const std::uint32_t parent = r == 0 ? kPrimary : static_cast<std::uint32_t>(engine() % r);
        const std::uint32_t length = engine() % 6;
        PixelRays::Ray ray{parent, static_cast<std::uint32_t>(pixel.records.size()), 0};
        for (std::uint32_t i = 0; i < length; ++i) {
          pixel.records.push_back({.address = std::uint64_t{p} << 32 | std::uint64_t{r} << 16 | i, .tag = 1});
        }
        ray.end = static_cast<std::uint32_t>(pixel.records.size());
        pixel.rays.push_back(ray);
        parent_and_length[std::uint64_t{p} << 16 | r] = {parent, length};
        total += length;
      }
      unit_of.push_back(static_cast<unsigned>(engine() % units));
      scheduler.add_pixel(unit_of.back(), std::move(pixel));
      if (engine() % 3 == 0) scheduler.run(out, false);
    }
    ASSERT_TRUE(scheduler.run(out, true));
    ASSERT_EQ(out.size(), total);
    std::map<std::uint64_t, std::uint32_t> issued;     // (pixel, ray) -> fetches so far
    std::map<std::uint64_t, std::size_t> finished_at;  // (pixel, ray) -> position of its last fetch
    for (std::size_t k = 0; k < out.size(); ++k) {
      const std::uint64_t address = out[k].address;
      const auto p = static_cast<std::uint32_t>(address >> 32);
      const auto r = static_cast<std::uint32_t>((address >> 16) & 0xFFFF);
      const std::uint64_t key = std::uint64_t{p} << 16 | r;
      ASSERT_EQ(formats::unit_index(out[k].unit), unit_of[p]);
      ASSERT_EQ(address & 0xFFFF, issued[key]++) << "ray's fetches out of order";
      const auto [parent, length] = parent_and_length[key];
      if (issued[key] == length) finished_at[key] = k;
      if (parent != kPrimary && parent_and_length[std::uint64_t{p} << 16 | parent].second > 0) {
        const auto done = finished_at.find(std::uint64_t{p} << 16 | parent);
        ASSERT_TRUE(done != finished_at.end() && done->second < k) << "a ray issued before its parent finished";
      }
    }
    for (const auto& [key, value] : parent_and_length) ASSERT_EQ(issued[key], value.second);
  }
}

std::vector<Record> render_records(const Scene& scene, const RenderOptions& options, bool in_flight) {
  const KdTree tree = KdTree::build(scene.triangles);
  const Layout layout = make_layout(tree, LayoutKind::Dfl);
  const Renderer renderer(scene, tree, layout, options);
  std::vector<Record> all;
  const auto sink = [&](std::span<const Record> r) { all.insert(all.end(), r.begin(), r.end()); };
  if (in_flight) {
    renderer.render_in_flight(sink, nullptr);
  } else {
    renderer.render(sink, nullptr);
  }
  return all;
}

TEST(RenderInFlight, OneUnitOfOneSlotGivesTheSequentialRecords) {
  const Scene scene = test_scenes::cornell_box();
  RenderOptions options;
  options.width = 40;
  options.height = 30;
  options.pixels_per_chunk = 13;
  options.threads = 2;
  const auto sequential = render_records(scene, options, false);
  ASSERT_GT(sequential.size(), 40u * 30u);
  EXPECT_TRUE(render_records(scene, options, true) == sequential);
}

TEST(RenderInFlight, SameRecordsWhateverTheThreadCountAndEveryFetchOnce) {
  const Scene scene = test_scenes::cornell_box();
  RenderOptions options;
  options.width = 40;
  options.height = 30;
  options.pixel_order = PixelOrder::Tiled;
  const auto sequential = render_records(scene, options, false);
  options.rays_in_flight = 8;
  options.units = 3;
  options.unit_pixels = 16;
  options.threads = 1;
  options.pixels_per_chunk = 50;
  const auto one = render_records(scene, options, false);
  options.threads = 3;
  options.pixels_per_chunk = 7;
  const auto three = render_records(scene, options, false);
  EXPECT_TRUE(one == three);
  ASSERT_EQ(one.size(), sequential.size());
  EXPECT_FALSE(one == sequential);
  // The same fetches, interleaved: equal as multisets once the unit is dropped.
  auto sorted = [](std::vector<Record> records) {
    for (Record& record : records) record.unit = {};
    std::sort(records.begin(), records.end(), [](const Record& a, const Record& b) {
      return std::tie(a.address, a.tag) < std::tie(b.address, b.tag);
    });
    return records;
  };
  EXPECT_TRUE(sorted(one) == sorted(sequential));
  std::vector<std::uint64_t> per_unit(3);
  for (const Record& record : one) ++per_unit.at(formats::unit_index(record.unit));
  for (const auto count : per_unit) EXPECT_GT(count, 0u);
}

}  // namespace
}  // namespace nodetrace::tracer
