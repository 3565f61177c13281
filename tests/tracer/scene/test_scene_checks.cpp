// What the loaders check of every triangle (issue 9, item 2): zero-area
// triangles dropped with one summary warning (how many, the first file and
// line), coordinates beyond +-2^62 and non-finite ones rejected naming the
// line.
#include <gtest/gtest.h>

#include "nodetrace/tracer/scene/scene_loader.hpp"
#include "test_support.hpp"

namespace nodetrace::tracer {
namespace {

std::string error_of(const std::string& path) {
  try {
    open_scene(path);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

TEST(SceneChecks, ObjZeroAreaTrianglesAreDroppedWithOneWarning) {
  nodetrace::testing::TempDir dir;
  const auto path = dir.path() / "zero.obj";
  nodetrace::testing::write_file(path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 1 2\nf 1 2 4\nf 1 2 3\n");
  // Without the default lights' note, this test's subject is the only warning.
  const auto source = open_scene(path.string(), {.default_lights = false});
  EXPECT_EQ(source->at_time(0).triangles.size(), 2u);
  const auto warnings = source->warnings();
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], "2 zero-area triangles dropped (the first at " + path.string() + ":6)");
}

TEST(SceneChecks, ObjTinyTrianglesAreKept) {
  nodetrace::testing::TempDir dir;
  const auto path = dir.path() / "tiny.obj";
  nodetrace::testing::write_file(path, "v 0 0 0\nv 1e-30 0 0\nv 0 1e-30 0\nf 1 2 3\n");
  const auto source = open_scene(path.string(), {.default_lights = false});
  EXPECT_EQ(source->at_time(0).triangles.size(), 1u);
  EXPECT_TRUE(source->warnings().empty());
}

TEST(SceneChecks, ObjCoordinateBeyondTheRangeIsAnErrorNamingTheLine) {
  nodetrace::testing::TempDir dir;
  const auto path = dir.path() / "far.obj";
  nodetrace::testing::write_file(path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 5e18\nf 1 2 3\nf 1 2 4\n");
  EXPECT_EQ(error_of(path.string()), path.string() + ":6: triangle vertex coordinate 4.99999999e+18 is beyond the "
                                     "supported range of -2^62 to 2^62 (about +-4.6e18)");
  nodetrace::testing::write_file(path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 4e18\nf 1 2 3\nf 1 2 4\n");
  EXPECT_EQ(error_of(path.string()), "");
}

TEST(SceneChecks, AffOverflowingAndZeroAreaTriangles) {
  nodetrace::testing::TempDir dir;
  const auto path = dir.path() / "big.aff";
  nodetrace::testing::write_file(path, "p 3\n0 0 0\n1 0 0\n0 1e39 0\n");
  // The tokenizer refuses a number that overflows single precision before any triangle is made.
  EXPECT_EQ(error_of(path.string()), path.string() + ":4: expected polygon vertex coordinate (a number of at most "
                                     "3.40282e+38 in magnitude), got '1e39'");
  nodetrace::testing::write_file(path, "p 3\n0 0 0\n1 0 0\n0 5e18 0\n");
  EXPECT_EQ(error_of(path.string()), path.string() + ":4: triangle vertex coordinate 4.99999999e+18 is beyond the "
                                     "supported range of -2^62 to 2^62 (about +-4.6e18)");
  nodetrace::testing::write_file(path, "p 3\n0 0 0\n1 0 0\n0 1 0\np 3\n0 0 0\n1 0 0\n2 0 0\np 3\n0 0 0\n0 0 0\n0 0 0\n");
  const auto source = open_scene(path.string());
  EXPECT_EQ(source->at_time(0).triangles.size(), 1u);
  const auto warnings = source->warnings();
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], "2 zero-area triangles dropped (the first at " + path.string() + ":8)");
}

}  // namespace
}  // namespace nodetrace::tracer
