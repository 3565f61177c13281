// The tree cache: a loaded structure equals the built one for every kind;
// a truncated, bit-flipped or other-version file is noticed, rebuilt with a
// note and replaced by a good one; a folder that cannot be used is a warning
// and the structure is built.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <vector>

#include "nodetrace/tracer/accel/tree_cache.hpp"
#include "nodetrace/tracer/scene/scene_loader.hpp"
#include "test_support.hpp"

namespace nodetrace::tracer {
namespace {

using nodetrace::testing::read_file;
using nodetrace::testing::TempDir;
using nodetrace::testing::write_file;

constexpr AccelKind kAllKinds[] = {AccelKind::KdTree, AccelKind::Bvh2, AccelKind::Bvh4, AccelKind::Bvh8,
                                   AccelKind::CwBvh8};

// Field by field (padding bytes may differ).
bool same_bounds(const Bounds& a, const Bounds& b) {
  return std::memcmp(&a.lo, &b.lo, sizeof a.lo) == 0 && std::memcmp(&a.hi, &b.hi, sizeof a.hi) == 0;
}

void expect_same_stats(const KdTreeStats& a, const KdTreeStats& b) {
  EXPECT_EQ(a.nodes, b.nodes);
  EXPECT_EQ(a.interior, b.interior);
  EXPECT_EQ(a.leaves, b.leaves);
  EXPECT_EQ(a.empty_leaves, b.empty_leaves);
  EXPECT_EQ(a.primitive_references, b.primitive_references);
  EXPECT_EQ(a.nodes_per_level, b.nodes_per_level);
  EXPECT_EQ(a.depth, b.depth);
  EXPECT_EQ(a.depth_limit, b.depth_limit);
  EXPECT_EQ(a.mean_leaf_size, b.mean_leaf_size);
  EXPECT_EQ(a.mean_nonempty_leaf_size, b.mean_nonempty_leaf_size);
  EXPECT_EQ(a.sah_cost, b.sah_cost);
}

void expect_same_structure(const AccelerationStructure& a, const AccelerationStructure& b) {
  ASSERT_EQ(a.kind(), b.kind());
  EXPECT_TRUE(same_bounds(a.bounds(), b.bounds()));
  expect_same_stats(a.stats(), b.stats());
  if (const KdTree* x = a.kdtree()) {
    const KdTree* y = b.kdtree();
    ASSERT_NE(y, nullptr);
    ASSERT_EQ(x->nodes().size(), y->nodes().size());
    for (std::size_t i = 0; i < x->nodes().size(); ++i) {
      const KdNode &m = x->nodes()[i], &n = y->nodes()[i];
      ASSERT_TRUE(std::memcmp(&m.split, &n.split, sizeof m.split) == 0 && m.left == n.left && m.right == n.right &&
                  m.first == n.first && m.count == n.count && m.level == n.level && m.axis == n.axis)
          << "node " << i;
    }
    EXPECT_EQ(x->primitives(), y->primitives());
    return;
  }
  const Bvh *x = a.bvh(), *y = b.bvh();
  ASSERT_NE(y, nullptr);
  EXPECT_EQ(x->arity(), y->arity());
  EXPECT_EQ(x->compressed(), y->compressed());
  ASSERT_EQ(x->nodes().size(), y->nodes().size());
  for (std::size_t i = 0; i < x->nodes().size(); ++i) {
    const BvhNode &m = x->nodes()[i], &n = y->nodes()[i];
    ASSERT_TRUE(m.first_child == n.first_child && m.child_count == n.child_count && m.level == n.level) << i;
  }
  ASSERT_EQ(x->children().size(), y->children().size());
  for (std::size_t i = 0; i < x->children().size(); ++i) {
    const BvhChild &m = x->children()[i], &n = y->children()[i];
    ASSERT_TRUE(same_bounds(m.box, n.box) && m.index == n.index && m.count == n.count) << "child " << i;
  }
  ASSERT_EQ(x->exact_child_boxes().size(), y->exact_child_boxes().size());
  for (std::size_t i = 0; i < x->exact_child_boxes().size(); ++i) {
    ASSERT_TRUE(same_bounds(x->exact_child_boxes()[i], y->exact_child_boxes()[i])) << "exact box " << i;
  }
  ASSERT_EQ(x->quantizations().size(), y->quantizations().size());
  for (std::size_t i = 0; i < x->quantizations().size(); ++i) {
    const BvhQuantization &m = x->quantizations()[i], &n = y->quantizations()[i];
    ASSERT_TRUE(std::memcmp(&m.origin, &n.origin, sizeof m.origin) == 0 && m.exponent == n.exponent) << i;
  }
  EXPECT_EQ(x->primitives(), y->primitives());
}

// A cache whose messages are kept for the test to read.
struct RecordedCache {
  std::vector<TreeCacheMessage> messages;
  TreeCache cache;
  explicit RecordedCache(const std::filesystem::path& folder)
      : cache(folder.string(), [this](const TreeCacheMessage& message) { messages.push_back(message); }) {}
};

std::vector<Triangle> scene_triangles() { return open_scene("mountain:6")->at_frame(0).triangles; }

TEST(TreeCacheTest, LoadedStructureEqualsBuiltForEveryKind) {
  TempDir dir;
  const auto triangles = scene_triangles();
  for (const AccelKind kind : kAllKinds) {
    SCOPED_TRACE(std::string(accel_name(kind)));
    const AccelerationStructure built = AccelerationStructure::build(triangles, kind);
    RecordedCache cold(dir.path());
    const AccelerationStructure first = cold.cache.obtain(triangles, kind, {});
    const std::string path = cold.cache.path_for(triangles, kind, {});
    ASSERT_TRUE(std::filesystem::exists(path));
    RecordedCache warm(dir.path());
    const AccelerationStructure loaded = warm.cache.obtain(triangles, kind, {});
    EXPECT_TRUE(cold.messages.empty());
    EXPECT_TRUE(warm.messages.empty());
    expect_same_structure(built, first);
    expect_same_structure(built, loaded);
    EXPECT_TRUE(nodetrace::testing::temporaries(dir.path()).empty());
  }
}

TEST(TreeCacheTest, KeyHoldsOptionsAndTrianglesButNotThreads) {
  TempDir dir;
  RecordedCache recorded(dir.path());
  auto triangles = scene_triangles();
  const TreeCache& cache = recorded.cache;
  const std::string base = cache.path_for(triangles, AccelKind::KdTree, {});
  AccelBuildOptions threads;
  threads.kdtree.threads = 1;
  EXPECT_EQ(cache.path_for(triangles, AccelKind::KdTree, threads), base);
  EXPECT_NE(cache.path_for(triangles, AccelKind::Bvh2, {}), base);
  AccelBuildOptions other;
  other.kdtree.empty_bonus = 0.5f;
  EXPECT_NE(cache.path_for(triangles, AccelKind::KdTree, other), base);
  other = {};
  other.bvh.bins = 8;
  EXPECT_NE(cache.path_for(triangles, AccelKind::KdTree, other), base);
  triangles[5].v1.x += 0.25f;
  EXPECT_NE(cache.path_for(triangles, AccelKind::KdTree, {}), base);
}

// Damages the file of `kind` with `damage`, then expects a note, the built
// structure, and a good file in its place (the next obtain says nothing).
template <class Damage>
void expect_damage_rebuilt(AccelKind kind, const std::string& what, Damage damage) {
  SCOPED_TRACE(what);
  TempDir dir;
  const auto triangles = scene_triangles();
  const AccelerationStructure built = AccelerationStructure::build(triangles, kind);
  std::string path;
  {
    RecordedCache cold(dir.path());
    cold.cache.obtain(triangles, kind, {});
    path = cold.cache.path_for(triangles, kind, {});
  }
  const std::string good = read_file(path);
  std::string bad = good;
  damage(bad);
  ASSERT_NE(bad, good);
  write_file(path, bad);
  RecordedCache damaged(dir.path());
  expect_same_structure(built, damaged.cache.obtain(triangles, kind, {}));
  ASSERT_EQ(damaged.messages.size(), 1u);
  EXPECT_EQ(damaged.messages[0].level, TreeCacheMessage::Level::Note);
  EXPECT_NE(damaged.messages[0].text.find("tree cache " + path + ": "), std::string::npos) << damaged.messages[0].text;
  EXPECT_NE(damaged.messages[0].text.find("; rebuilt"), std::string::npos) << damaged.messages[0].text;
  RecordedCache again(dir.path());
  expect_same_structure(built, again.cache.obtain(triangles, kind, {}));
  EXPECT_TRUE(again.messages.empty()) << again.messages[0].text;
}

TEST(TreeCacheTest, TruncatedFilesAreRebuilt) {
  for (const AccelKind kind : {AccelKind::KdTree, AccelKind::CwBvh8}) {
    for (const double fraction : {0.0, 0.001, 0.01, 0.3, 0.999}) {
      expect_damage_rebuilt(kind, "truncated to " + std::to_string(fraction),
                            [fraction](std::string& bytes) { bytes.resize(std::size_t(double(bytes.size()) * fraction)); });
    }
    expect_damage_rebuilt(kind, "one byte short", [](std::string& bytes) { bytes.pop_back(); });
    expect_damage_rebuilt(kind, "one byte more", [](std::string& bytes) { bytes.push_back('x'); });
  }
}

TEST(TreeCacheTest, FlippedBitsAreRebuilt) {
  for (const AccelKind kind : {AccelKind::KdTree, AccelKind::Bvh4}) {
    // Header: the magic, the format version, the key's length, the key (its
    // version text and its triangle hash), the payload length, the checksum;
    // then the payload: its start, middle and last byte.
    for (const std::size_t position : {0, 9, 13, 20, 60, 112, 120, 130, 150, 200, 400, 5000}) {
      expect_damage_rebuilt(kind, "bit flipped at " + std::to_string(position), [position](std::string& bytes) {
        bytes[position % bytes.size()] ^= 0x10;
      });
    }
    expect_damage_rebuilt(kind, "last bit flipped", [](std::string& bytes) { bytes.back() ^= 1; });
  }
}

TEST(TreeCacheTest, AnotherVersionsFileIsRebuilt) {
  expect_damage_rebuilt(AccelKind::KdTree, "format version 2", [](std::string& bytes) { bytes[8] = 2; });
  // The tracer's version inside the key: the text after the key's own
  // format version and the text's length.
  expect_damage_rebuilt(AccelKind::Bvh2, "tracer version", [](std::string& bytes) {
    const std::size_t version_text = 8 + 4 + 4 + 4 + 4;
    bytes[version_text] = bytes[version_text] == '9' ? '8' : '9';
  });
}

TEST(TreeCacheTest, FolderThatCannotBeCreatedIsAWarning) {
  TempDir dir;
  RecordedCache recorded(dir / "missing/cache");
  EXPECT_FALSE(recorded.cache.usable());
  ASSERT_EQ(recorded.messages.size(), 1u);
  EXPECT_EQ(recorded.messages[0].level, TreeCacheMessage::Level::Warning);
  EXPECT_NE(recorded.messages[0].text.find("cannot create"), std::string::npos) << recorded.messages[0].text;
  const auto triangles = scene_triangles();
  expect_same_structure(AccelerationStructure::build(triangles, AccelKind::KdTree),
                        recorded.cache.obtain(triangles, AccelKind::KdTree, {}));
}

TEST(TreeCacheTest, MissingFolderWithAParentIsCreated) {
  TempDir dir;
  RecordedCache recorded(dir / "cache");
  EXPECT_TRUE(recorded.cache.usable());
  EXPECT_TRUE(recorded.messages.empty());
  EXPECT_TRUE(std::filesystem::is_directory(dir / "cache"));
}

TEST(TreeCacheTest, FolderThatCannotBeWrittenIsOneWarning) {
  // /proc takes no new files, even from root.
  RecordedCache recorded("/proc");
  ASSERT_TRUE(recorded.cache.usable());
  const auto triangles = scene_triangles();
  for (const AccelKind kind : {AccelKind::KdTree, AccelKind::Bvh2}) {
    expect_same_structure(AccelerationStructure::build(triangles, kind), recorded.cache.obtain(triangles, kind, {}));
  }
  ASSERT_EQ(recorded.messages.size(), 1u);
  EXPECT_EQ(recorded.messages[0].level, TreeCacheMessage::Level::Warning);
  EXPECT_NE(recorded.messages[0].text.find("cannot store"), std::string::npos) << recorded.messages[0].text;
}

}  // namespace
}  // namespace nodetrace::tracer
