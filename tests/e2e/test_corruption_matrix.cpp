// The corruption matrix: a rendered container (re-framed into many data
// frames) damaged by 200 seeded byte flips and 50 seeded cuts; `tracetool
// verify`, `tracetool cat` and `cachesim run` must reject every damaged copy
// with exit 1 and a message naming the file and where (data frame, record,
// byte, header, trailer). Counted per program: tried, detected, crashed
// (killed by a signal, or an exit code other than 0 and 1) and silently wrong
// (exit 0); the last two must be zero.
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <random>
#include <regex>
#include <string>

#include "test_support.hpp"

namespace nodetrace::testing {
namespace {

std::string quoted(const std::filesystem::path& path) { return shell_quoted(path); }

struct Tally {
  int tried = 0, detected = 0, crashed = 0, silently_wrong = 0, vague = 0;
};

TEST(CorruptionMatrix, EveryDamagedCopyIsRejectedByEveryReader) {
  TempDir dir;
  const auto original_path = dir / "original.din.zst";
  const auto rendered = run_command(quoted(program("tracer")) + " render mountain --width 24 --height 18 -q -o " +
                                    quoted(dir / "rendered.din.zst") + " && " + quoted(program("tracetool")) +
                                    " convert " + quoted(dir / "rendered.din.zst") + " " + quoted(original_path) +
                                    " --frame-records 3000");
  ASSERT_EQ(rendered.exit_code, 0) << rendered.err;
  const std::string original = read_file(original_path);
  ASSERT_GT(original.size(), 10000u);

  std::mt19937_64 random(13);
  std::vector<std::pair<std::string, std::string>> copies;  // what was done, the damaged bytes
  for (int i = 0; i < 200; ++i) {
    const std::size_t at = random() % original.size();
    const auto mask = static_cast<unsigned char>(1 + random() % 255);
    std::string damaged = original;
    damaged[at] = static_cast<char>(static_cast<unsigned char>(damaged[at]) ^ mask);
    copies.emplace_back("flip at byte " + std::to_string(at), std::move(damaged));
  }
  for (int i = 0; i < 50; ++i) {
    const std::size_t keep = random() % original.size();
    copies.emplace_back("cut to " + std::to_string(keep) + " bytes", original.substr(0, keep));
  }

  const auto damaged_path = dir / "damaged.din.zst";
  const std::map<std::string, std::string> readers = {
      {"verify", quoted(program("tracetool")) + " verify " + quoted(damaged_path)},
      {"cat", quoted(program("tracetool")) + " cat " + quoted(damaged_path) + " >/dev/null"},
      {"cachesim run",
       quoted(program("cachesim")) + " run " + quoted(damaged_path) + " --size 1k,4k --scheme single,split"},
  };
  // Where the damage was found: a data frame, a record, a byte offset, the
  // header, the trailer or its index, or the hashes over them.
  const std::regex names_where("(data frame|record|byte|header|trailer|index|hash)");
  std::map<std::string, Tally> tallies;
  for (const auto& [what, bytes] : copies) {
    write_file(damaged_path, bytes);
    for (const auto& [name, command] : readers) {
      Tally& tally = tallies[name];
      ++tally.tried;
      const auto result = run_command(command);
      if (result.exit_code == 0) {
        ++tally.silently_wrong;
        ADD_FAILURE() << name << ": " << what << " went unnoticed";
      } else if (result.exit_code != 1) {
        ++tally.crashed;
        ADD_FAILURE() << name << ": " << what << " gave exit " << result.exit_code << "\n" << result.err;
      } else if (result.err.find(damaged_path.string() + ": ") == std::string::npos ||
                 !std::regex_search(result.err, names_where)) {
        ++tally.vague;
        ADD_FAILURE() << name << ": " << what << ": the message does not say where\n" << result.err;
      } else {
        ++tally.detected;
      }
    }
  }
  for (const auto& [name, tally] : tallies) {
    std::printf("corruption matrix, %s: tried %d, detected %d, crashed %d, silently wrong %d, vague %d\n",
                name.c_str(), tally.tried, tally.detected, tally.crashed, tally.silently_wrong, tally.vague);
    EXPECT_EQ(tally.tried, 250) << name;
    EXPECT_EQ(tally.detected, tally.tried) << name;
    EXPECT_EQ(tally.crashed, 0) << name;
    EXPECT_EQ(tally.silently_wrong, 0) << name;
  }
}

}  // namespace
}  // namespace nodetrace::testing
