// dinero-wrap: the Dinero IV output parser on every golden file, finding
// Dinero IV, and run / exec end to end against `cachesim run`, with
// `cachesim dinero` standing in for Dinero IV (and the real Dinero IV when
// there is one: $DINEROIV, PATH, or scripts/build-dinero.sh's build).
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cstdlib>
#include <regex>

#include "nodetrace/cachesim/wrap/wrap.hpp"
#include "nodetrace/base/error.hpp"
#include "nodetrace/formats/write/trace_writer.hpp"
#include "test_support.hpp"

namespace nodetrace::cachesim::wrap {
namespace {

using testing::program;
using testing::run_command;

std::string quoted(const std::filesystem::path& path) { return fmt::format("'{}'", path.string()); }

std::string stand_in() { return fmt::format("--dinero \"{} dinero\"", program("cachesim").string()); }

TEST(WrapParser, ReadsEveryGoldenOutput) {
  NODETRACE_SHARED_OR_SKIP(shared);
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(shared / "dinero-golden")) {
    if (entry.path().extension() != ".out") continue;
    ++files;
    SCOPED_TRACE(entry.path().filename().string());
    const std::string text = testing::read_file(entry.path());
    const auto caches = parse_dinero_output(text);
    ASSERT_FALSE(caches.empty());
    // Cross-check each table against its own "Demand miss rate" row (4 decimals).
    std::size_t from = 0;
    for (const auto& cache : caches) {
      EXPECT_TRUE(std::regex_match(cache.name, std::regex("l[1-5]-[uid]cache")));
      from = text.find("\n" + cache.name + "\n", from);
      ASSERT_NE(from, std::string::npos);
      const auto rate_at = text.find("Demand miss rate", from);
      ASSERT_NE(rate_at, std::string::npos);
      const double rate = std::stod(text.substr(rate_at + 16));
      EXPECT_GE(cache.demand_fetches, cache.demand_misses);
      if (cache.demand_fetches > 0) {
        EXPECT_NEAR(static_cast<double>(cache.demand_misses) / cache.demand_fetches, rate, 5e-5);
      }
      ++from;
    }
  }
  EXPECT_GE(files, 18);
}

TEST(WrapParser, KnownNumbers) {
  NODETRACE_SHARED_OR_SKIP(shared);
  const auto kd = parse_dinero_output(
      testing::read_file(shared / "dinero-golden" / "kd1-d8k-b8-a1.out"));
  ASSERT_EQ(kd.size(), 1u);
  EXPECT_EQ(kd[0].name, "l1-dcache");
  EXPECT_EQ(kd[0].demand_fetches, 200000u);
  EXPECT_EQ(kd[0].demand_misses, 39930u);
  const auto three = parse_dinero_output(
      testing::read_file(shared / "dinero-golden" / "mm32-i8k-d8k-u64k.out"));
  ASSERT_EQ(three.size(), 3u);
  EXPECT_EQ(three[0].name, "l1-icache");
  EXPECT_EQ(three[0].demand_fetches, 188971u);
  EXPECT_EQ(three[0].demand_misses, 563u);
  EXPECT_EQ(three[1].name, "l1-dcache");
  EXPECT_EQ(three[1].demand_misses, 26129u);
  EXPECT_EQ(three[2].name, "l2-ucache");
  EXPECT_EQ(three[2].demand_fetches, 29809u);
  EXPECT_EQ(three[2].demand_misses, 7145u);
}

TEST(WrapParser, RejectsOutputWithoutTables) {
  EXPECT_THROW(parse_dinero_output(""), base::FormatError);
  EXPECT_THROW(parse_dinero_output("dineroIV: usage\n"), base::FormatError);
  EXPECT_THROW(parse_dinero_output("l1-ucache\n Demand Fetches\t\t 10\n"), base::FormatError);
  EXPECT_THROW(parse_dinero_output("l1-ucache\n Demand Fetches\t\t x\n Demand Misses\t\t 1\n"),
               base::FormatError);
}

TEST(WrapCommand, SplitsCommandsWithoutAShell) {
  EXPECT_EQ(split_command("  a  b\tc "), (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_EQ(split_command("'/my dir/cachesim' dinero \"x y\""),
            (std::vector<std::string>{"/my dir/cachesim", "dinero", "x y"}));
  EXPECT_EQ(split_command("a;rm -rf x"), (std::vector<std::string>{"a;rm", "-rf", "x"}));
  EXPECT_THROW(split_command("'open"), base::UsageError);
}

TEST(WrapCommand, FindsDineroByOptionThenEnvironment) {
  EXPECT_EQ(find_dinero(std::string("x y")), (std::vector<std::string>{"x", "y"}));
  ::setenv("DINEROIV", "from-env --flag", 1);
  EXPECT_EQ(find_dinero(std::nullopt), (std::vector<std::string>{"from-env", "--flag"}));
  ::unsetenv("DINEROIV");
  const std::string path = std::getenv("PATH") ? std::getenv("PATH") : "";
  ::setenv("PATH", "/nonexistent", 1);
  try {
    find_dinero(std::nullopt);
    ADD_FAILURE() << "expected an error";
  } catch (const base::UsageError& error) {
    EXPECT_NE(std::string(error.what()).find("--dinero"), std::string::npos);
  }
  ::setenv("PATH", path.c_str(), 1);
}

TEST(WrapCommand, NoDineroIsAClearUsageError) {
  const auto result = run_command("env -u DINEROIV PATH=/nonexistent " +
                                  quoted(program("dinero-wrap")) + " run x.din");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("Dinero IV not found"), std::string::npos) << result.err;
}

// Dinero IV reports totals only: dinero-wrap run does not offer the per-level
// and per-frame tables it could never write.
TEST(WrapCommand, PerLevelAndPerFrameAreNotOffered) {
  const auto help = run_command(quoted(program("dinero-wrap")) + " run --help");
  ASSERT_EQ(help.exit_code, 0);
  EXPECT_EQ(help.out.find("--per-level"), std::string::npos) << help.out;
  EXPECT_EQ(help.out.find("--per-frame"), std::string::npos) << help.out;
  for (const std::string option : {"--per-level", "--per-frame"}) {
    const auto result = run_command(quoted(program("dinero-wrap")) + " run x.din " + option + " out.csv " +
                                    stand_in());
    EXPECT_EQ(result.exit_code, 2) << option;
    EXPECT_NE(result.err.find(option), std::string::npos) << result.err;
  }
}

// `dinero-wrap run` and `cachesim run` with the same options print the same CSV.
void expect_same_csv(const std::string& dinero_option, const std::string& arguments,
                     const std::string& input = {}) {
  const auto ours = run_command(quoted(program("cachesim")) + " run " + arguments, input);
  ASSERT_EQ(ours.exit_code, 0) << ours.err;
  const auto wrapped = run_command(
      quoted(program("dinero-wrap")) + " run " + arguments + " " + dinero_option, input);
  ASSERT_EQ(wrapped.exit_code, 0) << wrapped.err;
  EXPECT_EQ(wrapped.out, ours.out);
  EXPECT_GT(ours.out.size(), 200u);
}

TEST(WrapRun, EqualsCachesimRunOnTheGoldenKdTrace) {
  NODETRACE_SHARED_OR_SKIP(shared);
  expect_same_csv(stand_in(),
                  quoted(shared / "dinero-golden" / "kd-bfl-s1.din.zst") +
                      " --size 4k,16k --assoc 1,2 --policy lru,fifo --scheme single,split "
                      "--split-level 4,6 --high-policy retain,cache --tags-are-levels "
                      "--format csv");
}

TEST(WrapRun, EqualsCachesimRunOnMixedRecordsAndStdin) {
  NODETRACE_SHARED_OR_SKIP(shared);
  const auto xdin = shared / "dinero-golden" / "mm32.xdin.zst";
  // Standard input is the din trace; --jobs 1 runs one process per pass.
  expect_same_csv(stand_in() + " --jobs 1",
                  quoted(xdin) + " - --size 1k,8k --block 4,16 --assoc 1,4 --format csv",
                  testing::read_file(shared / "dinero-golden" / "mm32.din.zst"));
}

// `trees_differ`: each frame's marker gives another tree, so K = auto differs
// between frames.
void write_frames(const std::filesystem::path& path, bool trees_differ = false) {
  formats::WriterOptions options;
  options.form = formats::RecordForm::ExtendedDin;
  options.records_per_data_frame = 100;
  auto writer = formats::TraceWriter::create(
      path.string(), {{"layout", {{"name", "bfl"}, {"split_level", 3}, {"node_size", 8}}}},
      options);
  for (std::uint64_t frame = 0; frame < 3; ++frame) {
    formats::AnimationFrameMarker marker;
    marker.frame = frame;
    marker.nodes_per_level = {1, 2, 4, 8, 16};
    if (trees_differ && frame == 1) marker.nodes_per_level = {1, 2, 8, 8, 16};
    if (trees_differ && frame == 2) marker.nodes_per_level = {1, 4, 4, 8, 16};
    writer->begin_animation_frame(marker);
    for (std::uint64_t ray = 0; ray < 300; ++ray) {
      std::uint64_t slot = 0;
      for (formats::Tag level = 0; level < 5; ++level) {
        formats::Record record;
        record.address = 0x2000 + slot * 8 + (frame == 2 ? 4 : 0);  // frame 2 spans blocks
        record.size = 8;
        record.tag = level;
        writer->write(record);
        slot = 2 * slot + 1 + (((ray * 7 + frame) >> level) & 1);
      }
    }
    formats::Record triangle;
    triangle.address = 0x900000;
    triangle.tag = formats::kTagTriangle;
    writer->write(triangle);
  }
  writer->finish();
}

TEST(WrapRun, EqualsCachesimRunOnAContainerWithFrames) {
  testing::TempDir dir;
  write_frames(dir / "frames.xdin.zst");
  expect_same_csv(stand_in(), quoted(dir / "frames.xdin.zst") +
                                  " --size 64,128 --block 8,16 --scheme single,split "
                                  "--split-level auto,2 --high-policy retain,cache --format csv");
  expect_same_csv(stand_in(), quoted(dir / "frames.xdin.zst") +
                                  " --size 128 --scheme split --count-loads --format csv");
}

TEST(WrapRun, EqualsCachesimRunWhenKChangesPerAnimationFrame) {
  testing::TempDir dir;
  write_frames(dir / "frames.xdin.zst", true);
  const std::string arguments = quoted(dir / "frames.xdin.zst") +
                                " --size 64,128 --scheme split --split-level auto "
                                "--high-policy retain,cache --format csv";
  expect_same_csv(stand_in(), arguments);
  // K did change between frames (cachesim run's per-frame table says so).
  const auto ours = run_command(quoted(program("cachesim")) + " run " + arguments);
  EXPECT_NE(ours.err.find("64-byte high cache: split level (auto) from 2 to 3 over 3 animation frames"),
            std::string::npos)
      << ours.err;
  const auto wrapped = run_command(quoted(program("dinero-wrap")) + " run " + arguments + " " +
                                   stand_in());
  EXPECT_EQ(wrapped.err, ours.err);
}

TEST(WrapRun, HighLevelsThatDoNotFitAreAnError) {
  testing::TempDir dir;
  write_frames(dir / "frames.xdin.zst");
  const auto result =
      run_command(quoted(program("dinero-wrap")) + " run " + quoted(dir / "frames.xdin.zst") +
                  " --size 32 --scheme split --split-level 5 " + stand_in());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("do not fit"), std::string::npos) << result.err;
}

TEST(WrapExec, PrintsDineroOutputUnchanged) {
  NODETRACE_SHARED_OR_SKIP(shared);
  const auto result = run_command(
      quoted(program("dinero-wrap")) + " exec " +
      quoted(shared / "dinero-golden" / "kd-bfl-s1.din.zst") + " " + stand_in() +
      " -- -l1-dsize 8k -l1-dbsize 8 -l1-dassoc 1");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(result.out, testing::read_file(shared / "dinero-golden" / "kd1-d8k-b8-a1.out"));
}

TEST(WrapExec, TakesNoTagsAreLevelsOption) {
  // exec feeds addresses only, so a tag option would do nothing.
  const auto result = run_command(quoted(program("dinero-wrap")) + " exec - --tags-are-levels " +
                                  stand_in() + " -- -l1-dsize 8k -l1-dbsize 8");
  EXPECT_EQ(result.exit_code, 2);
}

// A din trace of `count` reads cycling over 64 KiB, written to `path`.
void write_din_reads(const std::filesystem::path& path, int count) {
  std::string text;
  for (int i = 0; i < count; ++i) text += fmt::format("0 {:x}\n", (i * 40) % 65536);
  testing::write_file(path, text);
}

TEST(WrapExec, MaxCountEndsDinerosReadingAndExecExitsWithItsStatus) {
  // 10 MB of records: far more than the pipe holds when Dinero IV stops.
  testing::TempDir dir;
  write_din_reads(dir / "t.din", 1000000);
  const std::string args = " -- -l1-dsize 8k -l1-dbsize 16 -maxcount 1000";
  const auto result = run_command(quoted(program("dinero-wrap")) + " exec --informat din " +
                                  quoted(dir / "t.din") + " " + stand_in() + args);
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(result.err, "");
  const auto direct = run_command(quoted(program("cachesim")) + " dinero -informat d " +
                                  args.substr(4) + " " + quoted(dir / "t.din"));
  EXPECT_EQ(result.out, direct.out);
  EXPECT_NE(result.out.find("---Maximum address count exceeded."), std::string::npos);
}

TEST(WrapExec, AnOptionDineroRejectsGivesItsStatusAndItsMessageOnly) {
  testing::TempDir dir;
  write_din_reads(dir / "t.din", 1000000);
  const auto result = run_command(quoted(program("dinero-wrap")) + " exec --informat din " +
                                  quoted(dir / "t.din") + " " + stand_in() +
                                  " -- -l1-dsize 8k -l1-dbsize 16 -bogus");
  EXPECT_EQ(result.exit_code, 2);  // cachesim dinero's status for bad usage
  EXPECT_NE(result.err.find("\"-bogus\" option not recognized"), std::string::npos) << result.err;
  EXPECT_EQ(result.err.find("Broken pipe"), std::string::npos) << result.err;
  EXPECT_EQ(result.err.find("dinero-wrap"), std::string::npos) << result.err;
  EXPECT_EQ(result.out, "");
}

TEST(WrapExec, InformatBFeedsBinaryRecords) {
  testing::TempDir dir;
  testing::write_file(dir / "t.xdin", "r 100 4\nw 104 8\ni 2000 4\nr 100 4\nm 3000 2\n");
  const std::string caches = " -l1-usize 8k -l1-ubsize 16";
  const auto binary = run_command(quoted(program("dinero-wrap")) + " exec " + quoted(dir / "t.xdin") +
                                  " " + stand_in() + " -- -informat b" + caches);
  ASSERT_EQ(binary.exit_code, 0) << binary.err;
  EXPECT_NE(binary.out.find("\n-informat b\n"), std::string::npos) << binary.out;
  const auto text = run_command(quoted(program("cachesim")) + " dinero -informat D" + caches + " " +
                                quoted(dir / "t.xdin"));
  ASSERT_EQ(text.exit_code, 0) << text.err;
  std::string expected = text.out;
  expected.replace(expected.find("\n-informat D\n"), 13, "\n-informat b\n");
  EXPECT_EQ(binary.out, expected);
  EXPECT_NE(binary.out.find(" Demand Fetches\t\t           5\t"), std::string::npos) << binary.out;
}

TEST(WrapExec, OutputThatCannotBeWrittenIsAnError) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full on this system";
  testing::TempDir dir;
  write_din_reads(dir / "t.din", 100);
  const auto result = run_command(quoted(program("dinero-wrap")) + " exec --informat din " +
                                  quoted(dir / "t.din") + " " + stand_in() +
                                  " -- -l1-dsize 8k -l1-dbsize 16 > /dev/full");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("cannot write"), std::string::npos) << result.err;
}

TEST(WrapRun, RealDineroIVGivesTheSameRows) {
  NODETRACE_SHARED_OR_SKIP(shared);
  NODETRACE_DINERO_OR_SKIP(dinero);
  expect_same_csv("--dinero " + quoted(dinero),
                  quoted(shared / "dinero-golden" / "kd-bfl-s1.din.zst") +
                      " --size 4k,8k,16k --assoc 1,4 --policy lru,fifo --scheme single,split "
                      "--split-level 6 --high-policy retain,cache --tags-are-levels --format csv");
}

// A BVH trace: 64-byte nodes as extended din records that span blocks of 8
// bytes (8 fetches each) or fill one of 64; Dinero IV reads the same.
TEST(WrapRun, RealDineroIVGivesTheSameRowsOnABvhTrace) {
  NODETRACE_DINERO_OR_SKIP(dinero);
  testing::TempDir dir;
  const auto trace = dir / "bvh2.xdin.zst";
  const auto rendered = run_command(quoted(program("tracer")) + " render mountain:6 --accel bvh2 --width 24 "
                                    "--height 18 --high-size 2k -q -o " + quoted(trace));
  ASSERT_EQ(rendered.exit_code, 0) << rendered.err;
  expect_same_csv("--dinero " + quoted(dinero), quoted(trace) +
                                                    " --size 4k --block 8,64 --assoc 1,4 --scheme single,split "
                                                    "--split-level auto --format csv");
}

TEST(WrapRun, EveryFetchPolicyGivesDinerosDemandMisses) {
  NODETRACE_SHARED_OR_SKIP(shared);
  NODETRACE_DINERO_OR_SKIP(dinero);
  for (const char* fetch : {"always", "miss", "tagged", "load-forward", "subblock"}) {
    SCOPED_TRACE(fetch);
    // Random replacement too: the Dinero engine draws Dinero IV's sequence.
    expect_same_csv("--dinero " + quoted(dinero),
                    quoted(shared / "dinero-golden" / "kd-bfl-s1.din.zst") +
                        " --size 4k,16k --assoc 1,4,full --policy lru,fifo,random --fetch " + fetch +
                        (std::string(fetch) == "always" ? " --prefetch-distance 3" : "") + " --format csv");
  }
}

TEST(WrapRun, PrefetchingIsRefusedWithTheSplitScheme) {
  const auto result = run_command(quoted(program("cachesim")) +
                                  " run - --scheme single,split --fetch tagged --tags-are-levels",
                                  "0 100 3\n");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("--scheme single only"), std::string::npos) << result.err;
}

// Addresses 0 and 2^32 alternating: Dinero IV's 32 bits make them one block
// (1 miss), cachesim run's 64 bits two (2 misses). By design, but said:
// dinero-wrap and cachesim dinero note how many records reach 2^32.
TEST(WrapRun, NotesTheRecordsWhoseAddressesDineroIvWrapsAt2To32) {
  testing::TempDir dir;
  const auto trace = dir / "hi.xdin";
  testing::write_file(trace, "r 0 8\nr 100000000 8\nr 0 8\nr 100000000 8\nr fffffffc 8\n");
  const std::string note =
      trace.string() + ": 3 records reach addresses at or above 2^32; Dinero IV (d4-7) keeps addresses in 32 bits, so they "
      "wrap at 2^32 here as in Dinero IV, where cachesim run keeps 64 bits: the two may count them differently";
  const auto wrapped = run_command(fmt::format("{} run {} {} --size 64 --block 8 --assoc 1 --format csv",
                                               quoted(program("dinero-wrap")), quoted(trace), stand_in()));
  ASSERT_EQ(wrapped.exit_code, 0) << wrapped.err;
  EXPECT_NE(wrapped.out.find(",5,6,2,"), std::string::npos) << wrapped.out;  // refs, fetches, misses
  EXPECT_NE(wrapped.err.find("note: " + note + "\n"), std::string::npos) << wrapped.err;
  const auto ours = run_command(fmt::format("{} run {} --size 64 --block 8 --assoc 1 --format csv",
                                            quoted(program("cachesim")), quoted(trace)));
  EXPECT_NE(ours.out.find(",5,6,5,"), std::string::npos) << ours.out;
  EXPECT_EQ(ours.err.find("2^32"), std::string::npos) << ours.err;
  const auto dinero = run_command(fmt::format("{} dinero -l1-usize 64 -l1-ubsize 8 -informat D {}",
                                              quoted(program("cachesim")), quoted(trace)));
  ASSERT_EQ(dinero.exit_code, 0) << dinero.err;
  EXPECT_EQ(dinero.err, "cachesim dinero note: " + note + "\n");
  // Below 2^32 nothing is noted.
  testing::write_file(trace, "r 0 8\nr fffffff0 8\n");
  EXPECT_EQ(run_command(fmt::format("{} dinero -l1-usize 64 -l1-ubsize 8 -informat D {}",
                                    quoted(program("cachesim")), quoted(trace))).err, "");
}

}  // namespace
}  // namespace nodetrace::cachesim::wrap
