// One vocabulary across the four programs: every subcommand whose --help
// lists --format accepts exactly table, csv and json, and every one that
// lists a record-form option (--records for an output, --informat for an
// input) accepts exactly din, xdin and binary, each run for real. A
// subcommand a program adds must be given a command line here.
#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "help_text.hpp"
#include "test_support.hpp"

namespace nodetrace::testing {
namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kPrograms = {"tracer", "tracetool", "cachesim", "dinero-wrap"};
const std::vector<std::string> kFormats = {"table", "csv", "json"};
const std::vector<std::string> kRecordForms = {"din", "xdin", "binary"};

class OneVocabulary : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto rendered = run_command(shell_quoted(program("tracer")) +
                                      " render mountain --width 16 --height 12 -q --high-size 1k -o " +
                                      shell_quoted(trace()));
    ASSERT_EQ(rendered.exit_code, 0) << rendered.err;
  }
  fs::path trace() const { return dir_ / "t.din.zst"; }

  // A command line that works, to which an option is appended; OUT is
  // replaced by a fresh output name without a form of its own.
  std::string command_line(const std::string& program_name, const std::string& subcommand) const {
    const std::string t = shell_quoted(trace());
    const std::string dinero = shell_quoted(program("cachesim").string() + " dinero");
    const std::map<std::string, std::string> lines = {
        {"tracer render", "mountain --width 8 --height 6 -q -o OUT"},
        {"tracer info", "mountain:6"},
        {"tracer scenes", ""},
        {"tracetool info", t},
        {"tracetool cat", t + " >/dev/null"},
        {"tracetool verify", t},
        {"tracetool convert", t + " OUT"},
        {"cachesim run", t},
        {"cachesim dinero", ""},
        {"dinero-wrap run", t + " --dinero " + dinero},
        {"dinero-wrap exec", t + " --dinero " + dinero + " -- -l1-dsize 8k -l1-dbsize 8 -l1-dassoc 1"},
    };
    const auto found = lines.find(program_name + " " + subcommand);
    if (found == lines.end()) return {};
    return shell_quoted(program(program_name)) + " " + subcommand + " " + found->second;
  }

  CommandResult run_with(const std::string& line, const std::string& option) {
    std::string command = line;
    const std::string out = shell_quoted(dir_ / ("out-" + std::to_string(++outputs_)));
    const auto at = command.find("OUT");
    if (at != std::string::npos) command.replace(at, 3, out);
    // The option goes before any `--` (dinero-wrap exec passes the rest to Dinero IV).
    const auto separator = command.find(" -- ");
    if (separator != std::string::npos) {
      command.insert(separator, " " + option);
    } else {
      const auto redirect = command.find(" >");
      command.insert(redirect == std::string::npos ? command.size() : redirect, " " + option);
    }
    return run_command(command);
  }

  TempDir dir_;
  int outputs_ = 0;
};

bool lists(const HelpOptions& help, const std::string& option) {
  return std::find(help.listed.begin(), help.listed.end(), option) != help.listed.end();
}

TEST_F(OneVocabulary, EverySubcommandAcceptsTheSameFormatAndRecordFormNames) {
  int format_options = 0, record_options = 0;
  for (const std::string& name : kPrograms) {
    const std::string top_help = run_command(shell_quoted(program(name)) + " --help").out;
    const std::vector<std::string> subcommands = subcommands_in_help(name, top_help);
    ASSERT_FALSE(subcommands.empty()) << name;
    for (const std::string& subcommand : subcommands) {
      const std::string line = command_line(name, subcommand);
      ASSERT_FALSE(line.empty()) << "`" << name << " " << subcommand << "`: give it a command line in this test";
      const auto help_run = run_command(shell_quoted(program(name)) + " " + subcommand + " --help");
      const HelpOptions help = options_in_help(help_run.out);
      // Other names for the same things are gone.
      for (const char* other : {"--form", "--output-format", "--informat-name"}) {
        EXPECT_FALSE(lists(help, other)) << name << " " << subcommand << " lists " << other;
      }
      std::vector<std::pair<std::string, std::vector<std::string>>> checks;
      if (lists(help, "--format")) checks.push_back({"--format", kFormats}), ++format_options;
      for (const char* option : {"--records", "--informat"}) {
        if (lists(help, option)) checks.push_back({option, kRecordForms}), ++record_options;
      }
      for (const auto& [option, names] : checks) {
        for (const std::string& value : names) {
          const auto result = run_with(line, option + " " + value);
          EXPECT_EQ(result.exit_code, 0) << name << " " << subcommand << " " << option << " " << value << ": "
                                         << result.err;
        }
        const auto bogus = run_with(line, option + " text");
        EXPECT_EQ(bogus.exit_code, 2) << name << " " << subcommand << " " << option << " text: " << bogus.err;
      }
    }
  }
  // tracer info and scenes, tracetool info, cachesim run, dinero-wrap run.
  EXPECT_EQ(format_options, 5);
  // --records: tracer render, tracetool cat and convert; --informat: tracetool's
  // four, cachesim run, dinero-wrap run and exec.
  EXPECT_EQ(record_options, 10);
}

}  // namespace
}  // namespace nodetrace::testing
