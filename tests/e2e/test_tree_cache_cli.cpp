// `--tree-cache DIR` and NODETRACE_TREE_CACHE end to end: traces are the same
// bytes without the cache, with a cold one and with a warm one; a damaged
// file is a note, rebuilt and replaced; two renders started at once on one
// folder both succeed with the same trace; a folder that cannot be used is a
// warning and the render goes on.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "test_support.hpp"

namespace nodetrace::testing {
namespace {

namespace fs = std::filesystem;

// Two animation frames whose trees differ, so a render stores two files.
struct TreeCacheRender {
  TempDir dir;
  std::string scene = write_two_frame_scene(dir.path(), 12).string();

  std::string command(const std::string& accel, const std::string& trace, const std::string& extra) const {
    return program("tracer").string() + " render " + shell_quoted(scene) +
           " --frames 0-1 --width 48 --height 36 -q --high-size 2k --accel " + accel + " -o " +
           shell_quoted(dir / trace) + " " + extra;
  }
  // Renders into `trace`; the standard error.
  std::string render(const std::string& accel, const std::string& trace, const std::string& extra = "") const {
    const CommandResult result = run_command(command(accel, trace, extra));
    EXPECT_EQ(result.exit_code, 0) << result.err;
    return result.err;
  }
  std::string trace(const std::string& name) const { return read_file(dir / name); }
};

std::size_t files_in(const fs::path& folder) {
  std::size_t count = 0;
  for (const auto& entry : fs::directory_iterator(folder)) count += entry.is_regular_file();
  return count;
}

TEST(TreeCacheCliTest, ColdAndWarmCacheGiveTheTraceWithoutIt) {
  for (const std::string accel : {"kdtree", "bvh2", "bvh4", "bvh8", "cwbvh8"}) {
    SCOPED_TRACE(accel);
    TreeCacheRender r;
    const std::string cache = shell_quoted(r.dir / "cache");
    r.render(accel, "none.zst");
    EXPECT_EQ(r.render(accel, "cold.zst", "--tree-cache " + cache), "");
    EXPECT_EQ(files_in(r.dir / "cache"), 2u);  // one tree per animation frame
    EXPECT_EQ(r.render(accel, "warm.zst", "--tree-cache " + cache), "");
    const std::string none = r.trace("none.zst");
    ASSERT_GT(none.size(), 1000u);
    EXPECT_TRUE(none == r.trace("cold.zst"));
    EXPECT_TRUE(none == r.trace("warm.zst"));
    EXPECT_TRUE(temporaries(r.dir / "cache").empty());
  }
}

TEST(TreeCacheCliTest, EnvironmentNamesTheFolderAndTheOptionWins) {
  TreeCacheRender r;
  r.render("kdtree", "none.zst");
  const std::string environment = "NODETRACE_TREE_CACHE=" + shell_quoted(r.dir / "from-env") + " ";
  const CommandResult by_environment = run_command(environment + r.command("kdtree", "env.zst", ""));
  ASSERT_EQ(by_environment.exit_code, 0) << by_environment.err;
  EXPECT_EQ(files_in(r.dir / "from-env"), 2u);
  const CommandResult by_option =
      run_command(environment + r.command("kdtree", "option.zst", "--tree-cache " + shell_quoted(r.dir / "opt")));
  ASSERT_EQ(by_option.exit_code, 0) << by_option.err;
  EXPECT_EQ(files_in(r.dir / "opt"), 2u);
  EXPECT_EQ(files_in(r.dir / "from-env"), 2u);
  // An empty --tree-cache turns the variable's cache off.
  const CommandResult off = run_command(environment + r.command("kdtree", "off.zst", "--tree-cache ''"));
  ASSERT_EQ(off.exit_code, 0) << off.err;
  for (const char* name : {"env.zst", "option.zst", "off.zst"}) EXPECT_TRUE(r.trace("none.zst") == r.trace(name)) << name;
}

TEST(TreeCacheCliTest, DamagedFileIsNotedRebuiltAndReplaced) {
  TreeCacheRender r;
  const fs::path cache = r.dir / "cache";
  r.render("kdtree", "cold.zst", "--tree-cache " + shell_quoted(cache));
  for (const auto& entry : fs::directory_iterator(cache)) {
    std::string bytes = read_file(entry.path());
    bytes.resize(bytes.size() / 2);
    write_file(entry.path(), bytes);
  }
  const std::string err = r.render("kdtree", "damaged.zst", "--tree-cache " + shell_quoted(cache));
  EXPECT_NE(err.find("tracer render: note: tree cache " + cache.string() + "/"), std::string::npos) << err;
  EXPECT_NE(err.find("; rebuilt\n"), std::string::npos) << err;
  EXPECT_TRUE(r.trace("cold.zst") == r.trace("damaged.zst"));
  EXPECT_EQ(r.render("kdtree", "again.zst", "--tree-cache " + shell_quoted(cache)), "");
  EXPECT_TRUE(r.trace("cold.zst") == r.trace("again.zst"));
}

TEST(TreeCacheCliTest, TwoRendersStartedAtOnceShareOneFolder) {
  for (int round = 0; round < 3; ++round) {
    SCOPED_TRACE(round);
    TreeCacheRender r;
    r.render("kdtree", "none.zst");
    const std::string option = "--tree-cache " + shell_quoted(r.dir / "cache");
    const std::string a = r.command("kdtree", "a.zst", option), b = r.command("kdtree", "b.zst", option);
    const CommandResult both = run_command("(" + a + "; echo a $?) & (" + b + "; echo b $?) & wait");
    EXPECT_NE(both.out.find("a 0\n"), std::string::npos) << both.out << both.err;
    EXPECT_NE(both.out.find("b 0\n"), std::string::npos) << both.out << both.err;
    EXPECT_EQ(both.err, "");
    EXPECT_TRUE(r.trace("none.zst") == r.trace("a.zst"));
    EXPECT_TRUE(r.trace("none.zst") == r.trace("b.zst"));
    EXPECT_EQ(files_in(r.dir / "cache"), 2u);
    EXPECT_TRUE(temporaries(r.dir / "cache").empty());
  }
}

TEST(TreeCacheCliTest, FolderThatCannotBeUsedIsAWarning) {
  TreeCacheRender r;
  r.render("kdtree", "none.zst");
  // /proc takes no new files, even from root.
  const std::string unwritable = r.render("kdtree", "unwritable.zst", "--tree-cache /proc");
  EXPECT_NE(unwritable.find("tracer render: warning: tree cache /proc: cannot store a built tree"), std::string::npos)
      << unwritable;
  const std::string missing = r.render("kdtree", "missing.zst", "--tree-cache " + shell_quoted(r.dir / "no/cache"));
  EXPECT_NE(missing.find("tracer render: warning: tree cache "), std::string::npos) << missing;
  EXPECT_NE(missing.find("cannot create the folder"), std::string::npos) << missing;
  EXPECT_TRUE(r.trace("none.zst") == r.trace("unwritable.zst"));
  EXPECT_TRUE(r.trace("none.zst") == r.trace("missing.zst"));
}

// Issue 47: a tree loaded from the cache was reported as "built in 0.01 s".
TEST(TreeCacheCliTest, ALoadedTreeIsReportedAsLoadedNotBuilt) {
  TreeCacheRender r;
  const std::string cache = "--tree-cache " + shell_quoted(r.dir / "cache");
  const auto tree_line = [](const std::string& err) {
    const auto at = err.find("  kd-tree: ");
    return at == std::string::npos ? err : err.substr(at, err.find('\n', at) - at);
  };
  // Not -q: the summary.
  const std::string cold = run_command(r.command("kdtree", "cold.zst", cache) + " --quiet=false").err;
  const std::string warm = run_command(r.command("kdtree", "warm.zst", cache) + " --quiet=false").err;
  EXPECT_NE(tree_line(cold).find(", built in "), std::string::npos) << cold;
  EXPECT_NE(tree_line(warm).find(", loaded from the tree cache in "), std::string::npos) << warm;
  EXPECT_EQ(tree_line(warm).find("built"), std::string::npos) << warm;
  const std::string info = program("tracer").string() + " info " + shell_quoted(r.scene) + " ";
  EXPECT_NE(run_command(info + cache).out.find(", loaded from the tree cache in "), std::string::npos);
  EXPECT_NE(run_command(info).out.find(", built in "), std::string::npos);
}

TEST(TreeCacheCliTest, InfoLoadsTheTreeARenderStored) {
  TreeCacheRender r;
  const std::string cache = shell_quoted(r.dir / "cache");
  r.render("bvh4", "trace.zst", "--tree-cache " + cache);
  const std::string info = program("tracer").string() + " info " + shell_quoted(r.scene) + " --accel bvh4 --format json";
  const CommandResult built = run_command(info);
  const CommandResult loaded = run_command(info + " --tree-cache " + cache);
  ASSERT_EQ(built.exit_code, 0) << built.err;
  ASSERT_EQ(loaded.exit_code, 0) << loaded.err;
  EXPECT_EQ(loaded.err, "");
  EXPECT_EQ(files_in(r.dir / "cache"), 2u);  // loaded, not stored again under another name
  // What differs from run to run: the times and the peak memory.
  auto without_times = [](const std::string& text) {
    nlohmann::json j = nlohmann::json::parse(text);
    j.erase("peak_memory");
    j["accel"].erase("build_seconds");
    j["accel"].erase("build_cpu_seconds");
    j["accel"].erase("loaded_from_tree_cache");
    return j;
  };
  EXPECT_EQ(without_times(built.out), without_times(loaded.out));
  EXPECT_EQ(nlohmann::json::parse(built.out)["accel"]["loaded_from_tree_cache"], false);
  EXPECT_EQ(nlohmann::json::parse(loaded.out)["accel"]["loaded_from_tree_cache"], true);
}

}  // namespace
}  // namespace nodetrace::testing
