// Every script in scripts/ and scripts/reports/ (a file that begins with #!)
// answers --help: exit 0, its usage on standard output, nothing run. Each is
// run by the interpreter its #! line names, so the test needs no execute bit.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace nodetrace::testing {
namespace {

namespace fs = std::filesystem;

// The scripts and their #! lines.
std::vector<std::pair<fs::path, std::string>> scripts() {
  std::vector<std::pair<fs::path, std::string>> found;
  for (const char* folder : {"scripts", "scripts/reports"}) {
    for (const auto& entry : fs::directory_iterator(fs::path(NODETRACE_SOURCE_DIR) / folder)) {
      if (!entry.is_regular_file()) continue;
      const std::string text = read_file(entry.path());
      if (text.rfind("#!", 0) != 0) continue;  // a module (reports/common.py) or a Makefile
      found.emplace_back(entry.path(), text.substr(2, text.find('\n') - 2));
    }
  }
  return found;
}

TEST(ScriptsHelp, EveryScriptAnswersHelpWithItsUsage) {
  const auto found = scripts();
  EXPECT_GE(found.size(), 15u);
  for (const auto& [path, interpreter] : found) {
    const std::string name = path.filename().string();
    // From another folder: a script that finds its files from its own path.
    const auto result = run_command("cd / && timeout 60 " + interpreter + " " + shell_quoted(path) + " --help");
    EXPECT_EQ(result.exit_code, 0) << name << " --help: " << result.err;
    EXPECT_NE(result.out.find(name), std::string::npos) << name << " --help does not name it:\n" << result.out;
    EXPECT_EQ(result.err.find("unknown option"), std::string::npos) << name << ": " << result.err;
  }
}

}  // namespace
}  // namespace nodetrace::testing
