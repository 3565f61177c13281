// An OBJ file read in chunks on several threads gives what LoadObj gives on
// one: at every split, for every thread count, or the chunks decline and the
// file is read on one thread.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "nodetrace/tracer/scene/scene_loader.hpp"
#include "scene/obj_chunks.hpp"
#include "scene/obj_mesh.hpp"
#include "test_support.hpp"

namespace {

using nodetrace::testing::run_command;
using nodetrace::testing::shell_quoted;
using nodetrace::testing::TempDir;
using nodetrace::testing::write_file;
using nodetrace::tracer::open_scene;
using nodetrace::tracer::Scene;
using nodetrace::tracer::SceneError;
using namespace nodetrace::tracer::detail;

constexpr const char* kMaterials = "newmtl red\nKd 1 0 0\nnewmtl green\nKd 0 1 0\nnewmtl blue\nKd 0 0 1\n";
constexpr const char* kMoreMaterials = "newmtl grey\nKd 0.5 0.5 0.5\nnewmtl red\nKd 0.9 0.1 0.1\n";

// Negative indices (vertices and normals), forward references from
// triangles, material changes (to an unknown name too, and a trailing
// comment), a second material library in the middle, groups, objects,
// smoothing groups, quads of both splits, comments, blank lines, CRLF.
constexpr const char* kCrafted =
    "# crafted for the chunk splits\n"
    "mtllib first.mtl\n"
    "v 0 0 0\n"
    "v 1 0 0\n"
    "v 1 1 0\n"
    "   v 0 1.2 0\n"
    "vn 0 0 1\n"
    "vt 0 0\n"
    "\n"
    "g first part\n"
    "usemtl red\n"
    "f 1 2 3\n"
    "f -4 -3 -1\n"
    "# a comment between faces\n"
    "f 1//1 2//1 3//-1 4//1\n"
    "usemtl blue # trailing comment\n"
    "f 1/1 2/1 9/1\n"
    "o second\n"
    "v 2 0 0\r\n"
    "v 2 3 0\r\n"
    "v 0 3 0\r\n"
    "v 3 1 1\n"
    "s 1\n"
    "usemtl nowhere\n"
    "f -4 -3 -2 -1\n"
    "f 2 5 6 3\n"
    "mtllib second.mtl\n"
    "usemtl grey\n"
    "\tf 5 6 7\n"
    "usemtl red\n"
    "f 5 -3 -2\n"
    "g\tthird\n"
    "usemtl green\n"
    "f 8 7 6\n"
    "v 5 5 5\n"
    "vn 0 1 0\n"
    "f -1//-1 1//-2 2//-1\n"
    "s off\n"
    "f 1 2 -1";  // no newline at the end

void expect_same_mesh(const ObjMesh& expected, const ObjMesh& actual, const std::string& what) {
  SCOPED_TRACE(what);
  EXPECT_EQ(expected.vertices, actual.vertices);
  EXPECT_EQ(expected.normals, actual.normals);
  ASSERT_EQ(expected.corners.size(), actual.corners.size());
  for (std::size_t i = 0; i < expected.corners.size(); ++i) {
    EXPECT_EQ(expected.corners[i].vertex, actual.corners[i].vertex) << "corner " << i;
    EXPECT_EQ(expected.corners[i].normal, actual.corners[i].normal) << "corner " << i;
  }
  EXPECT_EQ(expected.material_ids, actual.material_ids);
  ASSERT_EQ(expected.materials.size(), actual.materials.size());
  for (std::size_t i = 0; i < expected.materials.size(); ++i) {
    EXPECT_EQ(expected.materials[i].name, actual.materials[i].name);
    EXPECT_EQ(0, std::memcmp(expected.materials[i].diffuse, actual.materials[i].diffuse, sizeof(float) * 3));
  }
  EXPECT_EQ(expected.warnings, actual.warnings);
  EXPECT_EQ(expected.errors, actual.errors);
}

// Where each line starts, after the first.
std::vector<std::size_t> line_starts(std::string_view text) {
  std::vector<std::size_t> starts;
  for (std::size_t i = 0; i + 1 < text.size(); ++i) {
    if (text[i] == '\n') starts.push_back(i + 1);
  }
  return starts;
}

// `text` cut at `cuts` (ascending line starts).
std::vector<std::string_view> cut(std::string_view text, const std::vector<std::size_t>& cuts) {
  std::vector<std::string_view> chunks;
  std::size_t start = 0;
  for (const std::size_t at : cuts) {
    chunks.push_back(text.substr(start, at - start));
    start = at;
  }
  chunks.push_back(text.substr(start));
  return chunks;
}

// Every split in two, every pair of cuts, every line a chunk of its own and
// the whole text as one chunk, each on 1 and 2 threads, give LoadObj's mesh.
void expect_every_split_reads_as_load_obj(const std::string& text, const TempDir& dir) {
  tinyobj::MaterialFileReader reader(dir.path().string() + "/");
  const ObjMesh expected = read_obj_one_thread(text, reader);
  ASSERT_TRUE(expected.errors.empty()) << expected.errors;
  ASSERT_FALSE(expected.corners.empty());
  const std::vector<std::size_t> starts = line_starts(text);
  std::vector<std::vector<std::size_t>> splits = {{}, starts};
  for (std::size_t a = 0; a < starts.size(); ++a) {
    splits.push_back({starts[a]});
    for (std::size_t b = a + 1; b < starts.size(); ++b) splits.push_back({starts[a], starts[b]});
  }
  for (const auto& cuts : splits) {
    const std::vector<std::string_view> chunks = cut(text, cuts);
    for (const unsigned threads : {1u, 2u}) {
      const std::optional<ObjMesh> chunked = read_obj_chunks(chunks, reader, threads);
      std::string what = std::to_string(chunks.size());
      what += " chunks on ";
      what += std::to_string(threads);
      what += " threads, cut at";
      for (const std::size_t at : cuts) {
        what += ' ';
        what += std::to_string(at);
      }
      ASSERT_TRUE(chunked.has_value()) << what;
      expect_same_mesh(expected, *chunked, what);
      if (::testing::Test::HasFailure()) return;
    }
  }
}

TEST(ObjChunks, EverySplitOfACraftedFileReadsAsLoadObj) {
  TempDir dir;
  write_file(dir / "first.mtl", kMaterials);
  write_file(dir / "second.mtl", kMoreMaterials);
  expect_every_split_reads_as_load_obj(kCrafted, dir);
}

TEST(ObjChunks, EverySplitReadsAsLoadObjWithoutMaterialFiles) {
  TempDir dir;  // mtllib names no file here: warnings, default materials
  expect_every_split_reads_as_load_obj(kCrafted, dir);
}

TEST(ObjChunks, SplitAtLinesEndsEveryChunkButTheLastAfterANewline) {
  const std::string text = kCrafted;
  for (std::size_t count = 1; count < 60; ++count) {
    const std::vector<std::string_view> chunks = split_at_lines(text, count);
    ASSERT_LE(chunks.size(), count);
    std::string joined;
    for (std::size_t i = 0; i < chunks.size(); ++i) {
      ASSERT_FALSE(chunks[i].empty());
      if (i + 1 < chunks.size()) {
        ASSERT_EQ('\n', chunks[i].back());
      }
      joined += chunks[i];
    }
    EXPECT_EQ(text, joined);
  }
  EXPECT_TRUE(split_at_lines("", 4).empty());
}

// What the chunks cannot read as LoadObj does is declined, and the file
// loads on one thread all the same.
TEST(ObjChunks, FeaturesLeftToLoadObjAreDeclined) {
  TempDir dir;
  tinyobj::MaterialFileReader reader(dir.path().string() + "/");
  const std::string vertices = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 1.5 0\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"a pentagon", vertices + "f 1 2 3 5 4\n"},
      {"a line element", vertices + "l 1 2\nf 1 2 3\n"},
      {"a point element", vertices + "p 1\nf 1 2 3\n"},
      {"a nameless group", vertices + "g \nf 1 2 3\n"},
      {"a lone carriage return", vertices + "# one\r# two\nf 1 2 3\n"},
      {"a quad referring ahead", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3 4\nv 0 1 0\n"},
      {"a square (a tie between its diagonals)", vertices + "f 1 2 3 4\n"},
  };
  for (const auto& [what, text] : cases) {
    const std::vector<std::string_view> whole = {text};
    EXPECT_FALSE(read_obj_chunks(whole, reader, 2).has_value()) << what;
    const auto path = dir / "declined.obj";
    write_file(path, text);
    const Scene one = open_scene(path.string(), {.threads = 1})->at_time(0);
    const Scene two = open_scene(path.string(), {.threads = 2})->at_time(0);
    ASSERT_EQ(one.triangles.size(), two.triangles.size()) << what;
    EXPECT_EQ(0, std::memcmp(one.triangles.data(), two.triangles.data(), one.triangles.size() * sizeof(one.triangles[0])))
        << what;
  }
}

// An empty index after a slash: LoadObj fails on it, or (atoi skipping
// blanks) reads the next corner's number there, while the callback API
// reads no index; a comment after the corners, which LoadObj reads as a
// corner of index 0. Declined by the chunks: LoadObj's outcome on every
// thread count.
TEST(ObjChunks, IndicesLoadObjReadsApartAreLeftToIt) {
  TempDir dir;
  for (const std::string face : {"f 1/ 2/ 3/\n", "f 1//1 2//1 3//\n", "f 1/1/ 2/1/1 3/1/1\n", "f 1 2 3 # a comment\n"}) {
    const std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n" + face;
    tinyobj::MaterialFileReader reader(dir.path().string() + "/");
    const std::vector<std::string_view> whole = {text};
    EXPECT_FALSE(read_obj_chunks(whole, reader, 2).has_value()) << face;
    const auto path = dir / "slash.obj";
    write_file(path, text);
    std::vector<std::string> outcomes;
    for (const unsigned threads : {1u, 2u}) {
      try {
        outcomes.push_back(std::to_string(open_scene(path.string(), {.threads = threads})->at_time(0).triangles.size()));
      } catch (const SceneError& error) {
        outcomes.push_back(error.what());
      }
    }
    EXPECT_EQ(outcomes[0], outcomes[1]) << face;
    EXPECT_NE(outcomes[0], "1") << face;  // LoadObj's error, or ours on the normal it read
  }
}

// A bad line is the same error whatever the threads: the first in the file.
TEST(ObjChunks, TheFirstBadLineIsReportedWhateverTheThreads) {
  TempDir dir;
  std::string text;
  for (int i = 0; i < 400; ++i) text += "v " + std::to_string(i) + " 0 " + std::to_string(i % 7) + "\n";
  for (int i = 1; i + 2 <= 400; ++i) text += "f " + std::to_string(i) + " " + std::to_string(i + 1) + " -1\n";
  for (const auto& [bad, expected] : std::vector<std::pair<std::string, std::string>>{
           {"f 1 2 401\n", "vertex index 401 is out of range (400 vertices)"},
           {"v 1 x 2\n", "expected a finite number"}}) {
    // The bad line about the middle of the file, a later one at its end.
    std::string file = text.substr(0, text.size() / 2);
    file = file.substr(0, file.rfind('\n') + 1);
    const std::size_t line = std::count(file.begin(), file.end(), '\n') + 1;
    file += bad + text.substr(file.size()) + "f 1 2 0\n";
    const auto path = dir / "bad.obj";
    write_file(path, file);
    for (const unsigned threads : {1u, 2u, 7u}) {
      try {
        open_scene(path.string(), {.threads = threads});
        ADD_FAILURE() << "no error on " << threads << " threads";
      } catch (const SceneError& error) {
        EXPECT_NE(std::string(error.what()).find(":" + std::to_string(line) + ": " + expected), std::string::npos)
            << error.what();
      }
    }
  }
}

// scripts/make-large-scene.py's terrain and spheres, a few thousand
// triangles: the same scene on 1 and 2 threads, and LoadObj's mesh.
TEST(ObjChunks, AGeneratedSceneLoadsTheSameOnOneAndTwoThreads) {
  TempDir dir;
  const auto path = dir / "large.obj";
  const auto script = std::filesystem::path(NODETRACE_SOURCE_DIR) / "scripts" / "make-large-scene.py";
  const auto made = run_command("python3 " + shell_quoted(script) + " --triangles 5000 " + shell_quoted(path));
  ASSERT_EQ(0, made.exit_code) << made.err;
  const auto one = open_scene(path.string(), {.threads = 1});
  const auto two = open_scene(path.string(), {.threads = 2});
  const Scene a = one->at_time(0), b = two->at_time(0);
  ASSERT_GT(a.triangles.size(), 4000u);
  ASSERT_EQ(a.triangles.size(), b.triangles.size());
  EXPECT_EQ(0, std::memcmp(a.triangles.data(), b.triangles.data(), a.triangles.size() * sizeof(a.triangles[0])));
  EXPECT_EQ(a.materials.size(), b.materials.size());
  EXPECT_EQ(one->content_hash(), two->content_hash());
  EXPECT_EQ(one->warnings(), two->warnings());

  const std::string text = nodetrace::testing::read_file(path);
  tinyobj::MaterialFileReader reader(dir.path().string() + "/");
  const ObjMesh expected = read_obj_one_thread(text, reader);
  for (const std::size_t count : {1u, 2u, 3u, 8u, 64u}) {
    const std::vector<std::string_view> chunks = split_at_lines(text, count);
    const std::optional<ObjMesh> chunked = read_obj_chunks(chunks, reader, 2);
    ASSERT_TRUE(chunked.has_value());
    expect_same_mesh(expected, *chunked, std::to_string(count) + " chunks");
  }
}

}  // namespace
