// Treelet maps in the tracer's traces (FORMAT.md 2.2.2): a `--layout
// treelet` render of any structure carries, per animation frame, a map that
// tiles the frame's node addresses with treelets of at most the budget and
// holds every node record; other layouts carry none; the bytes do not depend
// on the thread count.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "nodetrace/formats/read/trace_reader.hpp"
#include "test_support.hpp"

namespace nodetrace::tracer {
namespace {

using nodetrace::testing::program;
using nodetrace::testing::read_file;
using nodetrace::testing::run_command;
using nodetrace::testing::TempDir;

std::string tracer() { return program("tracer").string(); }

struct Frame {
  formats::AnimationFrameMarker marker;
  std::vector<formats::Record> records;
};

std::vector<Frame> frames_of(const std::string& path) {
  auto reader = formats::TraceReader::open(path);
  std::vector<Frame> frames;
  formats::RecordBatch batch;
  while (reader->next(batch)) {
    if (batch.marker) frames.push_back({*batch.marker, {}});
    if (!frames.empty()) frames.back().records.insert(frames.back().records.end(), batch.records.begin(), batch.records.end());
  }
  return frames;
}

TEST(TreeletMapTraces, EveryStructuresTreeletTraceCarriesAMapPerFrameThatTilesItsNodes) {
  TempDir dir;
  const auto scene = nodetrace::testing::write_two_frame_scene(dir.path(), 16);
  const struct {
    const char* accel;
    std::uint64_t node_size;
    std::uint64_t treelet_bytes;
  } cases[] = {{"kdtree", 8, 64}, {"bvh2", 64, 256}, {"cwbvh8", 80, 256}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.accel);
    const auto path = dir / (std::string(c.accel) + ".xdin.zst");
    const auto result = run_command(tracer() + " render " + scene.string() + " --frames 0-1 --width 24 --height 16 -q" +
                                    " --accel " + c.accel + " --layout treelet --treelet-bytes " +
                                    std::to_string(c.treelet_bytes) + " --records xdin -o " + path.string());
    ASSERT_EQ(result.exit_code, 0) << result.err;
    auto reader = formats::TraceReader::open(path.string());
    EXPECT_TRUE(reader->header().carries_treelet_maps());
    const formats::LayoutInfo layout = reader->header().layout();
    const auto frames = frames_of(path.string());
    ASSERT_EQ(frames.size(), 2u);
    for (const Frame& frame : frames) {
      ASSERT_TRUE(frame.marker.treelets);
      const auto& treelets = frame.marker.treelets->treelets;
      ASSERT_FALSE(treelets.empty());
      // One after another from node_base to the last node's end.
      std::uint64_t end = layout.node_base;
      for (const auto& t : treelets) {
        ASSERT_EQ(t.first, end);
        ASSERT_GE(t.bytes, c.node_size);
        ASSERT_LE(t.bytes, c.treelet_bytes);
        ASSERT_EQ(t.bytes % c.node_size, 0u);
        end = t.first + t.bytes;
      }
      EXPECT_EQ(end, layout.node_base + frame.marker.nodes * c.node_size);
      // Treelets of several nodes, not one per node.
      EXPECT_LT(treelets.size(), frame.marker.nodes);
      std::uint64_t node_records = 0;
      for (const auto& record : frame.records) {
        if (!formats::is_level(record.tag)) continue;
        ++node_records;
        const auto holder = frame.marker.treelets->treelet_of(record.address);
        ASSERT_TRUE(holder) << std::hex << record.address;
        EXPECT_LE(record.address + record.size, treelets[*holder].first + treelets[*holder].bytes);
      }
      EXPECT_GT(node_records, 100u);
    }
  }
}

TEST(TreeletMapTraces, OtherLayoutsCarryNoMap) {
  TempDir dir;
  const auto result = run_command(tracer() + " render mountain:6 --width 24 --height 16 -q --layout dfl,bfl,veb,hybrid" +
                                  " --split-level 3 -o " + (dir / "{layout}.din.zst").string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  for (const char* name : {"dfl", "bfl", "veb", "hybrid-k3"}) {
    SCOPED_TRACE(name);
    const auto path = (dir / (std::string(name) + ".din.zst")).string();
    EXPECT_FALSE(formats::TraceReader::open(path)->header().json.contains("treelet_map"));
    for (const Frame& frame : frames_of(path)) EXPECT_FALSE(frame.marker.treelets);
  }
}

TEST(TreeletMapTraces, ATreeletTraceIsTheSameBytesForAnyThreadCount) {
  TempDir dir;
  const auto scene = nodetrace::testing::write_two_frame_scene(dir.path(), 6);
  std::vector<std::string> files;
  for (const char* threads : {"1", "2", "3"}) {
    const auto path = dir / (std::string("t") + threads + ".din.zst");
    const auto result = run_command(tracer() + " render " + scene.string() +
                                    " --frames 0-1 --width 24 --height 16 -q --layout treelet --threads " + threads +
                                    " -o " + path.string());
    ASSERT_EQ(result.exit_code, 0) << result.err;
    files.push_back(read_file(path));
  }
  EXPECT_TRUE(files[0] == files[1]);
  EXPECT_TRUE(files[0] == files[2]);
}

}  // namespace
}  // namespace nodetrace::tracer
