// `cachesim run --policy` end to end: the usage errors of the policies
// Dinero IV does not have (exit 2, naming the values allowed), opt on
// standard input (read once, no second pass), dinero-wrap refusing them, and
// random equal to `cachesim dinero` (Dinero IV's draws).
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <sstream>

#include "test_support.hpp"

namespace nodetrace::cachesim {
namespace {

using testing::program;
using testing::run_command;

std::string quoted(const std::filesystem::path& path) { return fmt::format("'{}'", path.string()); }

// A plain level-tagged din trace with reuse at several distances.
std::filesystem::path write_trace(const testing::TempDir& dir) {
  std::string text;
  for (int i = 0; i < 20000; ++i) {
    const int node = (i * 7 + (i / 13) * 31) % 1500;
    text += fmt::format("0 {:08x} {:02d}\n", 8 * node, node % 12);
  }
  const auto path = dir / "t.din";
  testing::write_file(path, text);
  return path;
}

struct RefusedCase {
  const char* options;
  const char* message;  // in standard error
};

TEST(PolicyCommand, RefusesWhatAPolicyCannotAnswerWithExit2) {
  testing::TempDir dir;
  const std::string run = quoted(program("cachesim")) + " run " + quoted(write_trace(dir)) + " --tags-are-levels ";
  const RefusedCase cases[] = {
      {"--policy plru --assoc 3",
       "cachesim run: 8192-byte cache: --policy plru needs a power-of-two number of ways (1, 2, 4, 8, ...), not 3"},
      {"--policy srrip --assoc 4 --fetch always",
       "cachesim run: --policy srrip with --fetch always: prefetching is simulated with Dinero IV's policies only "
       "(lru, fifo, random); give --fetch demand"},
      {"--policy opt --per-level x.csv", "cachesim run: --policy opt: not with --per-level"},
      {"--policy opt --per-frame x.csv", "cachesim run: --policy opt: not with --per-frame"},
      {"--policy opt --sample-windows 1/2 --window-records 100",
       "cachesim run: --policy opt: not with sampling (--sample-windows, --sample-sets)"},
      {"--policy drrip --assoc 2 --sample-sets 1/2 --size 4k",
       "cachesim run: --policy drrip with --sample-sets: its insertion counter (and drrip's selector) belong to "
       "the whole cache; allowed with --sample-sets: lru, fifo, plru, srrip"},
      {"--policy random --assoc 2 --sample-sets 1/2 --size 4k",
       "cachesim run: --policy random with --sample-sets: its draws (Dinero IV's one sequence per cache) belong "
       "to the whole cache"},
      {"--policy plru --assoc 2 --l2-size 64k", "cachesim run: --l2-size: the first level is simulated record by "
                                                "record with lru or fifo, not plru"},
      {"--curve --policy srrip --assoc full",
       "cachesim run: --curve: --assoc full is answered for lru (one LRU stack) and opt"},
      {"--policy belady", "cachesim run: --policy: 'belady' is not one of lru, fifo, random, plru, srrip, brrip, "
                          "drrip, opt"},
  };
  for (const RefusedCase& c : cases) {
    const auto result = run_command(run + c.options);
    EXPECT_EQ(result.exit_code, 2) << c.options << "\n" << result.err;
    EXPECT_NE(result.err.find(c.message), std::string::npos) << c.options << "\n" << result.err;
  }
}

TEST(PolicyCommand, DineroWrapRefusesThePoliciesDineroIvDoesNotHave) {
  testing::TempDir dir;
  const auto trace = write_trace(dir);
  for (const char* policy : {"plru", "srrip", "brrip", "drrip", "opt"}) {
    const auto result = run_command(fmt::format("{} run {} --policy {} --dinero '{} dinero'",
                                                quoted(program("dinero-wrap")), quoted(trace), policy,
                                                program("cachesim").string()));
    EXPECT_EQ(result.exit_code, 2) << policy;
    EXPECT_NE(result.err.find(fmt::format("dinero-wrap run: --policy {}: Dinero IV has lru, fifo and random "
                                          "only; cachesim run simulates {}",
                                          policy, policy)),
              std::string::npos)
        << result.err;
  }
}

TEST(PolicyCommand, OptReadsStandardInputOnceAndEqualsTheFile) {
  testing::TempDir dir;
  const auto trace = write_trace(dir);
  // OPT listed after a policy: it once counted MIN over no fetches there.
  const std::string options = " --size 2k --assoc 4,16,full --policy lru,fifo,opt --scheme single,split "
                              "--split-level 3 --high-policy cache --tags-are-levels --format csv";
  const auto from_file = run_command(quoted(program("cachesim")) + " run " + quoted(trace) + options);
  const auto from_pipe = run_command("cat " + quoted(trace) + " | " + quoted(program("cachesim")) + " run -" + options);
  ASSERT_EQ(from_file.exit_code, 0) << from_file.err;
  ASSERT_EQ(from_pipe.exit_code, 0) << from_pipe.err;
  const auto file_rows = testing::csv_rows(from_file.out);
  const auto pipe_rows = testing::csv_rows(from_pipe.out);
  ASSERT_EQ(file_rows.size(), pipe_rows.size());
  ASSERT_EQ(file_rows.size(), 19u);  // header, 3 ways x 3 policies x 2 schemes
  for (std::size_t r = 1; r < file_rows.size(); ++r) {
    // Every column but the trace's name.
    EXPECT_EQ(std::vector<std::string>(file_rows[r].begin() + 1, file_rows[r].end()),
              std::vector<std::string>(pipe_rows[r].begin() + 1, pipe_rows[r].end()));
  }
  // Rows by ways, then policy (lru, fifo, opt), then scheme: opt misses no
  // more than lru with the same sets, and at least once for each distinct
  // block (a cold cache fetches each), and as many as opt run alone.
  const std::uint64_t distinct_blocks = 1500;  // write_trace's nodes, each its own 8-byte block
  for (std::size_t r = 1; r + 5 < file_rows.size(); r += 6) {
    for (std::size_t scheme = 0; scheme < 2; ++scheme) {
      const auto& lru = file_rows[r + scheme];
      const auto& opt = file_rows[r + 4 + scheme];
      ASSERT_EQ(lru[5], "lru");
      ASSERT_EQ(opt[5], "opt");
      EXPECT_LE(std::stoull(opt[12]), std::stoull(lru[12])) << opt[1] << " " << opt[4];
      EXPECT_LT(std::stoull(opt[12]), std::stoull(lru[12])) << "no room between them: a weak test trace";
      EXPECT_GE(std::stoull(opt[12]), distinct_blocks) << opt[1] << " " << opt[4];
      const auto alone = run_command(fmt::format(
          "{} run {} --size 2k --assoc {} --policy opt --scheme {} --split-level 3 --high-policy cache "
          "--tags-are-levels --format csv",
          quoted(program("cachesim")), quoted(trace), opt[4], opt[1]));
      ASSERT_EQ(alone.exit_code, 0) << alone.err;
      EXPECT_EQ(testing::csv_rows(alone.out).at(1).at(12), opt[12]) << opt[1] << " " << opt[4];
    }
  }
}

// Issue 34 item 6: cachesim run's random replacement draws Dinero IV's
// sequence, so its misses are cachesim dinero's (the real Dinero IV's, as
// the differential test shows) at every associativity.
TEST(PolicyCommand, RandomEqualsCachesimDinero) {
  testing::TempDir dir;
  const auto trace = write_trace(dir);
  for (const std::string assoc : {"2", "4", "32", "256"}) {
    const auto run = run_command(fmt::format("{} run {} --size 2k --assoc {} --policy random --format csv",
                                             quoted(program("cachesim")), quoted(trace), assoc));
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const auto rows = testing::csv_rows(run.out);
    const auto dinero = run_command(fmt::format(
        "{} dinero -informat d -l1-dsize 2k -l1-dbsize 8 -l1-dassoc {} -l1-drepl r {} | grep 'Demand Misses'",
        quoted(program("cachesim")), assoc, quoted(trace)));
    ASSERT_EQ(dinero.exit_code, 0) << dinero.err;
    std::istringstream words(dinero.out);
    std::string demand;
    std::string misses_word;
    std::string total;
    words >> demand >> misses_word >> total;
    EXPECT_EQ(rows.at(1).at(12), total) << "assoc " << assoc;
  }
}

}  // namespace
}  // namespace nodetrace::cachesim
