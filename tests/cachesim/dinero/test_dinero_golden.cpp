// `cachesim dinero` against real Dinero IV output: one test per line of
// ../shared/dinero-golden/MANIFEST.tsv, run through formats::TraceReader and
// compared byte for byte with NAME.out.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "nodetrace/cachesim/dinero/command_line.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"
#include "test_support.hpp"

namespace nodetrace::cachesim {
namespace {

struct GoldenCase {
  std::string name;
  std::string trace;
  std::vector<std::string> args;
};

// Manifest lines, or one placeholder when ../shared is absent so that the
// test skips (or fails in CI) with the usual message.
std::vector<GoldenCase> golden_cases() {
  std::vector<GoldenCase> cases;
  if (const auto shared = testing::shared_dir()) {
    std::ifstream manifest(*shared / "dinero-golden" / "MANIFEST.tsv");
    std::string line;
    while (std::getline(manifest, line)) {
      if (line.empty() || line[0] == '#') continue;
      std::istringstream fields(line);
      GoldenCase c;
      std::string args;
      std::getline(fields, c.name, '\t');
      std::getline(fields, c.trace, '\t');
      std::getline(fields, args);
      std::istringstream words(args);
      for (std::string word; words >> word;) c.args.push_back(word);
      cases.push_back(c);
    }
  }
  if (cases.empty()) cases.push_back({"shared_data_absent", "", {}});
  return cases;
}

std::string test_name(const ::testing::TestParamInfo<GoldenCase>& info) {
  std::string name = info.param.name;
  for (char& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return name;
}

// The first line where two texts differ, for a readable failure.
std::string first_difference(const std::string& expected, const std::string& actual) {
  std::istringstream a(expected), b(actual);
  std::string la, lb;
  for (int line = 1;; ++line) {
    const bool more_a = static_cast<bool>(std::getline(a, la));
    const bool more_b = static_cast<bool>(std::getline(b, lb));
    if (!more_a && !more_b) return "texts differ only in their last newline";
    if (la != lb || more_a != more_b) {
      return "line " + std::to_string(line) + ":\n  dinero:   " + (more_a ? la : "<end>") +
             "\n  cachesim: " + (more_b ? lb : "<end>");
    }
  }
}

class DineroGolden : public ::testing::TestWithParam<GoldenCase> {};

TEST_P(DineroGolden, MatchesDineroIVOutputByteForByte) {
  NODETRACE_SHARED_OR_SKIP(shared);
  const GoldenCase& c = GetParam();
  const auto dir = shared / "dinero-golden";
  const DineroOptions options = parse_dinero_options(c.args);
  formats::ReaderOptions reader_options;
  reader_options.form = options.form;
  auto reader = formats::TraceReader::open((dir / c.trace).string(), reader_options);
  std::ostringstream out, warnings;
  run_dinero(options, *reader, out, warnings);
  const std::string expected = testing::read_file(dir / (c.name + ".out"));
  ASSERT_FALSE(expected.empty()) << c.name << ".out is missing";
  EXPECT_TRUE(out.str() == expected) << first_difference(expected, out.str());
  EXPECT_EQ(warnings.str(), "");
}

INSTANTIATE_TEST_SUITE_P(Manifest, DineroGolden, ::testing::ValuesIn(golden_cases()), test_name);

}  // namespace
}  // namespace nodetrace::cachesim
