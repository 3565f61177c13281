// End to end: tracer -> container -> cachesim / tracetool / dinero-wrap, each
// answer checked against another tool's answer for the same records.
#include <gtest/gtest.h>

#include <sstream>
#include <nlohmann/json.hpp>

#include <regex>
#include <string>

#include "test_support.hpp"

namespace nodetrace::testing {
namespace {

std::string quoted(const std::filesystem::path& path) { return shell_quoted(path); }

// A small rendered trace shared by the tests of this file (rendered once).
class PipelineTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    trace_ = *dir_ / "scene.din.zst";
    const auto result = run_command(quoted(program("tracer")) +
                                    " render sphereflake:1 --width 48 --height 36 --high-size 1k"
                                    " --quiet -o " + quoted(trace_));
    ASSERT_EQ(result.exit_code, 0) << result.err;
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }

  static nlohmann::json cachesim_run(const std::string& options) {
    const auto result = run_command(quoted(program("cachesim")) + " run " + quoted(trace_) + " " +
                                    options + " --format json");
    EXPECT_EQ(result.exit_code, 0) << result.err;
    return nlohmann::json::parse(result.out).at("rows");  // {"columns": [...], "rows": [...]}
  }

  // Total demand misses of the first cache in Dinero IV's output layout.
  static long long dinero_total_misses(const std::string& output) {
    static const std::regex misses_row(R"(Demand Misses\s+(\d+))");
    std::smatch match;
    EXPECT_TRUE(std::regex_search(output, match, misses_row)) << output;
    return match.empty() ? -1 : std::stoll(match[1]);
  }

  static TempDir* dir_;
  static std::filesystem::path trace_;
};

TempDir* PipelineTest::dir_ = nullptr;
std::filesystem::path PipelineTest::trace_;

TEST_F(PipelineTest, RenderedTraceVerifies) {
  const auto result = run_command(quoted(program("tracetool")) + " verify " + quoted(trace_));
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("OK"), std::string::npos) << result.out;
}

TEST_F(PipelineTest, ZstdProgramReadsTheSameRecordsAsTracetool) {
  const auto by_zstd = run_command("zstd -dc " + quoted(trace_));
  const auto by_tracetool = run_command(quoted(program("tracetool")) + " cat " + quoted(trace_));
  ASSERT_EQ(by_zstd.exit_code, 0) << by_zstd.err;
  ASSERT_EQ(by_tracetool.exit_code, 0) << by_tracetool.err;
  EXPECT_GT(by_zstd.out.size(), 1000u);
  EXPECT_TRUE(by_zstd.out == by_tracetool.out);
}

TEST_F(PipelineTest, SingleSchemeEqualsCachesimDineroOnTheSameRecords) {
  for (const std::string size : {"1k", "4k"}) {
    const auto report = cachesim_run("--scheme single --size " + size + " --block 8 --assoc 1");
    ASSERT_EQ(report.size(), 1u);
    // Dinero IV's own reading of the records: the decompressed text on a pipe.
    const auto dinero = run_command("zstd -dc " + quoted(trace_) + " | " +
                                    quoted(program("cachesim")) +
                                    " dinero -informat d -l1-dsize " + size +
                                    " -l1-dbsize 8 -l1-dassoc 1");
    ASSERT_EQ(dinero.exit_code, 0) << dinero.err;
    EXPECT_EQ(report[0]["misses"].get<long long>(), dinero_total_misses(dinero.out)) << size;
    EXPECT_GT(report[0]["misses"].get<long long>(), 0);
  }
}

TEST_F(PipelineTest, SplitLowCacheEqualsDineroOnTheLowLevelRecords) {
  const auto report = cachesim_run("--scheme split --size 2k --split-level 6 --high-policy cache");
  ASSERT_EQ(report.size(), 1u);
  const auto low = run_command(quoted(program("tracetool")) + " cat --tags 6- " + quoted(trace_) +
                               " | " + quoted(program("cachesim")) +
                               " dinero -informat d -l1-dsize 1k -l1-dbsize 8 -l1-dassoc 1");
  ASSERT_EQ(low.exit_code, 0) << low.err;
  EXPECT_EQ(report[0]["low_misses"].get<long long>(), dinero_total_misses(low.out));
  const auto high = run_command(quoted(program("tracetool")) + " cat --tags 0-5 " +
                                quoted(trace_) + " | " + quoted(program("cachesim")) +
                                " dinero -informat d -l1-dsize 1k -l1-dbsize 8 -l1-dassoc 1");
  ASSERT_EQ(high.exit_code, 0) << high.err;
  EXPECT_EQ(report[0]["high_misses"].get<long long>(), dinero_total_misses(high.out));
}

TEST_F(PipelineTest, DineroWrapAgreesWithCachesimRun) {
  const std::string options =
      " --size 1k,2k,4k --block 8 --assoc 1 --scheme single,split --split-level auto --format csv";
  const auto native =
      run_command(quoted(program("cachesim")) + " run " + quoted(trace_) + options);
  const auto wrapped = run_command(quoted(program("dinero-wrap")) + " run " + quoted(trace_) +
                                   options + " --dinero \"" + program("cachesim").string() +
                                   " dinero\"");
  ASSERT_EQ(native.exit_code, 0) << native.err;
  ASSERT_EQ(wrapped.exit_code, 0) << wrapped.err;
  EXPECT_EQ(native.out, wrapped.out);
  EXPECT_NE(native.out.find(",split,"), std::string::npos);
}

TEST(PipelineStreaming, TracerToCachesimThroughAPipe) {
  TempDir dir;
  const auto file = dir / "t.din.zst";
  const std::string render = quoted(program("tracer")) +
                             " render mountain:6 --width 32 --height 24 --quiet --split-level 4";
  ASSERT_EQ(run_command(render + " -o " + quoted(file)).exit_code, 0);
  const std::string simulate = quoted(program("cachesim")) +
                               " run --size 2k --scheme single,split --format csv";
  const auto from_file = run_command(simulate + " " + quoted(file));
  const auto from_pipe = run_command(render + " -o - | " + simulate + " -");
  ASSERT_EQ(from_file.exit_code, 0) << from_file.err;
  ASSERT_EQ(from_pipe.exit_code, 0) << from_pipe.err;
  // Only the trace column differs: a file name against standard input.
  const auto strip_trace_column = [](std::string csv) {
    return std::regex_replace(csv, std::regex("(^|\n)[^,\n]*,"), "$1,");
  };
  EXPECT_EQ(strip_trace_column(from_file.out), strip_trace_column(from_pipe.out));
  EXPECT_NE(from_file.out.find(",split,"), std::string::npos);
}

TEST(PipelineLayouts, OnlyAHybridLayoutsSplitLevelIsComparedWithK) {
  TempDir dir;
  const std::string render = quoted(program("tracer")) +
                             " render mountain:6 --width 16 --height 12 --quiet";
  const std::string simulate = quoted(program("cachesim")) +
                               " run --size 2k --scheme split --format csv ";
  // dfl has no BFL top part: no split level in the header, no note about it.
  const auto dfl = dir / "dfl.din.zst";
  ASSERT_EQ(run_command(render + " --layout dfl -o " + quoted(dfl)).exit_code, 0);
  const auto info = run_command(quoted(program("tracetool")) + " info --format json " + quoted(dfl));
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_FALSE(nlohmann::json::parse(info.out)["header"]["layout"].contains("split_level"));
  const auto dfl_run = run_command(simulate + quoted(dfl));
  ASSERT_EQ(dfl_run.exit_code, 0) << dfl_run.err;
  EXPECT_EQ(dfl_run.err.find("differs from the layout"), std::string::npos) << dfl_run.err;
  // But the split scheme on a layout that does not keep the high levels together is.
  EXPECT_NE(dfl_run.err.find("layout dfl: the split scheme routes levels < K to the high cache, but this "
                             "layout scatters those levels"),
            std::string::npos)
      << dfl_run.err;
  // A hybrid layout built for another high-cache size is noted.
  const auto hybrid = dir / "hybrid.din.zst";
  ASSERT_EQ(run_command(render + " --split-level 1 -o " + quoted(hybrid)).exit_code, 0);
  const auto hybrid_run = run_command(simulate + quoted(hybrid));
  ASSERT_EQ(hybrid_run.exit_code, 0) << hybrid_run.err;
  EXPECT_NE(hybrid_run.err.find("differs from the layout's split_level 1"), std::string::npos)
      << hybrid_run.err;
  // The note says what it means and what to do.
  EXPECT_NE(hybrid_run.err.find("the high-level nodes are not where this layout put them together"),
            std::string::npos)
      << hybrid_run.err;
  EXPECT_NE(hybrid_run.err.find("render one trace per high-cache size (tracer render --layout hybrid --high-size SIZE"),
            std::string::npos)
      << hybrid_run.err;
}

// Din records carry no size: the tracer warns when nodes are larger than
// din's 4 bytes, and tracetool cat --to xdin gives node records the header's
// node size (issue 22 item 12).
TEST(NodeSize, DinWarnsAndCatToXdinUsesTheHeadersNodeSize) {
  TempDir dir;
  const auto din = dir / "n16.din.zst";
  const auto render = run_command(quoted(program("tracer")) + " render mountain:6 --width 8 --height 6 --quiet "
                                  "--node-size 16 -o " + quoted(din));
  ASSERT_EQ(render.exit_code, 0) << render.err;
  EXPECT_NE(render.err.find("tracer render: warning: din records carry no size"), std::string::npos) << render.err;
  EXPECT_NE(render.err.find("xdin records (--records xdin, or a .xdin.zst name) keep the size"), std::string::npos);
  const auto xdin = run_command(quoted(program("tracer")) + " render mountain:6 --width 8 --height 6 --quiet "
                                "--node-size 16 -o " + quoted(dir / "n16.xdin.zst"));
  ASSERT_EQ(xdin.exit_code, 0) << xdin.err;
  EXPECT_EQ(xdin.err, "");  // xdin keeps the size: nothing to warn of
  const auto cat = run_command(quoted(program("tracetool")) + " cat --to xdin " + quoted(din));
  ASSERT_EQ(cat.exit_code, 0) << cat.err;
  const std::string first = cat.out.substr(0, cat.out.find('\n'));
  // TYPE ADDRESS SIZE TAG: the size field is 16 (hex 10), not din's 4.
  std::istringstream fields(first);
  std::string type, address, size, tag;
  fields >> type >> address >> size >> tag;
  EXPECT_EQ(std::stoul(size, nullptr, 16), 16u) << first;
}

}  // namespace
}  // namespace nodetrace::testing
