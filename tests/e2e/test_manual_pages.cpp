// The manual pages (tracer/man, cachesim/man, formats/man): every option in
// the option column of a program's --help, and of each subcommand's, has a
// .TP paragraph in the program's page under a heading that names the
// subcommand (options only named in a help's text are mentioned there); each
// page has the sections a manual page needs and renders without groff
// warnings; --version prints the version trace headers record; `cmake
// --install` puts the pages in share/man/man1.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <iterator>
#include <map>
#include <ostream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "nodetrace/formats/read/trace_reader.hpp"
#include "help_text.hpp"
#include "test_support.hpp"

namespace nodetrace::testing {
namespace {

namespace fs = std::filesystem;

struct ManualPage {
  std::string program;
  std::string page;  // relative to the source folder
};

const std::vector<ManualPage> kPages = {{"tracer", "tracer/man/tracer.1"},
                                        {"cachesim", "cachesim/man/cachesim.1"},
                                        {"dinero-wrap", "cachesim/man/dinero-wrap.1"},
                                        {"tracetool", "formats/man/tracetool.1"}};

// Names the test by its program, not by the struct's bytes.
void PrintTo(const ManualPage& page, std::ostream* out) { *out << page.program; }

fs::path source_path(const std::string& relative) { return fs::path(NODETRACE_SOURCE_DIR) / relative; }

// What a reader sees of one line of the man(7) subset the pages use.
std::string resolve_escapes(const std::string& roff) {
  std::string text;
  for (std::size_t i = 0; i < roff.size(); ++i) {
    if (roff[i] != '\\' || i + 1 == roff.size()) {
      text += roff[i];
      continue;
    }
    const char next = roff[++i];
    if (next == 'f') {  // font: \fB, \fI, \fR, \fP
      ++i;
    } else if (next == '(') {  // \(xx: a special character, never part of an option
      text += ' ';
      i += 2;
    } else if (next == '-') {
      text += '-';
    } else if (next == 'e') {
      text += '\\';
    } else if (next != '&' && next != '%') {
      text += next;
    }
  }
  return text;
}

// The arguments of a request line, quotes grouping words.
std::vector<std::string> request_arguments(const std::string& rest) {
  std::vector<std::string> arguments;
  std::size_t i = 0;
  while (i < rest.size()) {
    while (i < rest.size() && rest[i] == ' ') ++i;
    if (i == rest.size()) break;
    std::string argument;
    if (rest[i] == '"') {
      const std::size_t end = rest.find('"', i + 1);
      argument = rest.substr(i + 1, end == std::string::npos ? std::string::npos : end - i - 1);
      i = end == std::string::npos ? rest.size() : end + 1;
    } else {
      const std::size_t end = std::min(rest.find(' ', i), rest.size());
      argument = rest.substr(i, end - i);
      i = end;
    }
    arguments.push_back(argument);
  }
  return arguments;
}

// A page split at its .SH and .SS headings, as text; `entries` holds the
// tags of its .TP paragraphs (the lines that name what each paragraph
// documents).
struct Section {
  std::string heading;
  std::string text;
  std::string entries;
};

std::vector<Section> page_sections(const std::string& roff) {
  std::vector<Section> sections(1);
  std::istringstream lines(roff);
  std::string line;
  bool tag_next = false;  // after .TP
  const auto add_text = [&](const std::string& text) {
    sections.back().text += text + "\n";
    if (tag_next) sections.back().entries += text + "\n";
    tag_next = false;
  };
  while (std::getline(lines, line)) {
    if (line.rfind(".\\\"", 0) == 0) continue;  // a comment
    if (line.empty() || line[0] != '.') {
      add_text(resolve_escapes(line));
      continue;
    }
    const std::size_t blank = std::min(line.find(' '), line.size());
    const std::string request = line.substr(1, blank - 1);
    std::vector<std::string> arguments = request_arguments(line.substr(blank));
    for (auto& argument : arguments) argument = resolve_escapes(argument);
    std::string joined;
    if (request == "SH" || request == "SS" || request == "B" || request == "I") {
      for (const auto& argument : arguments) joined += (joined.empty() ? "" : " ") + argument;
    } else if (request.size() == 2 && std::string("BIR").find(request[0]) != std::string::npos &&
               std::string("BIR").find(request[1]) != std::string::npos) {
      for (const auto& argument : arguments) joined += argument;  // .BR, .IB, ...: no blank between
    }
    if (request == "SH" || request == "SS") {
      sections.push_back({joined, "", ""});
      tag_next = false;
    } else if (request == "TP") {
      tag_next = true;
    } else if (!joined.empty()) {
      add_text(joined);
    }
  }
  return sections;
}

// True when `word` stands in `text` on its own: not inside a longer option
// or word (`--frame` is not found in `--frames`).
bool has_word(const std::string& text, const std::string& word) {
  const auto part_of_word = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '-'; };
  for (std::size_t at = text.find(word); at != std::string::npos; at = text.find(word, at + 1)) {
    const bool starts = at == 0 || !part_of_word(text[at - 1]);
    const bool ends = at + word.size() == text.size() || !part_of_word(text[at + word.size()]);
    if (starts && ends) return true;
  }
  return false;
}

std::string page_source(const ManualPage& page) {
  const fs::path path = source_path(page.page);
  EXPECT_TRUE(fs::exists(path)) << path << " is missing";
  return read_file(path);
}

std::string help_of(const std::string& command) {
  const auto result = run_command(command + " --help");
  EXPECT_EQ(result.exit_code, 0) << command << " --help: " << result.err;
  EXPECT_FALSE(result.out.empty()) << command << " --help printed nothing";
  return result.out;
}

class ManualPageTest : public ::testing::TestWithParam<ManualPage> {};

// Checks one help text against the sections that must document it: each
// listed option as the tag of a .TP paragraph, each mentioned one anywhere.
void expect_documented(const ManualPage& page, const std::string& command, const std::string& help,
                       const std::vector<Section>& sections, const std::string& where) {
  std::string text, entries;
  for (const auto& section : sections) {
    text += section.heading + "\n" + section.text;
    entries += section.entries;
  }
  const HelpOptions options = options_in_help(help);
  for (const std::string& option : options.listed) {
    EXPECT_TRUE(has_word(entries, option))
        << page.page << " does not document " << option << ", which `" << command
        << " --help` lists: add a .TP paragraph for it " << where;
  }
  for (const std::string& option : options.mentioned) {
    EXPECT_TRUE(has_word(text, option))
        << page.page << " does not mention " << option << ", which `" << command
        << " --help` names: mention it " << where;
  }
}

TEST_P(ManualPageTest, DocumentsEveryOptionOfEveryHelpUnderItsSubcommandsHeading) {
  const ManualPage& page = GetParam();
  const std::vector<Section> sections = page_sections(page_source(page));
  const std::string top_help = help_of(shell_quoted(program(page.program)));
  expect_documented(page, page.program, top_help, sections, "(anywhere in the page)");

  const std::vector<std::string> subcommands = subcommands_in_help(page.program, top_help);
  EXPECT_FALSE(subcommands.empty()) << "`" << page.program << " --help` lists no subcommands:\n" << top_help;
  for (const std::string& subcommand : subcommands) {
    std::vector<Section> named;  // the sections whose heading names the subcommand
    std::copy_if(sections.begin(), sections.end(), std::back_inserter(named),
                 [&](const Section& section) { return has_word(section.heading, subcommand); });
    EXPECT_FALSE(named.empty()) << page.page << " has no .SH or .SS heading that names `" << page.program << " "
                                << subcommand << "`";
    const std::string command = page.program + " " + subcommand;
    const std::string help = help_of(shell_quoted(program(page.program)) + " " + subcommand);
    EXPECT_FALSE(options_in_help(help).listed.empty()) << "`" << command << " --help` lists no options:\n" << help;
    expect_documented(page, command, help, named, "under a .SH or .SS heading that names " + subcommand);
  }
}

// The other way round: every option a subcommand's section documents in a
// .TP paragraph is one its --help lists, so a page cannot document options
// the program refuses (the check above missed `dinero-wrap run --per-level`).
TEST_P(ManualPageTest, DocumentsNoOptionItsSubcommandsHelpDoesNotList) {
  const ManualPage& page = GetParam();
  const std::vector<Section> sections = page_sections(page_source(page));
  const std::string top_help = help_of(shell_quoted(program(page.program)));
  const std::vector<std::string> subcommands = subcommands_in_help(page.program, top_help);
  std::map<std::string, std::string> helps;
  for (const std::string& subcommand : subcommands) {
    helps[subcommand] = help_of(shell_quoted(program(page.program)) + " " + subcommand);
  }
  for (const Section& section : sections) {
    // What the subcommands the heading names (`render, info`: both) say.
    std::string named, said;
    for (const std::string& subcommand : subcommands) {
      if (!has_word(section.heading, subcommand)) continue;
      named += (named.empty() ? "`" : ", `") + page.program + " " + subcommand + " --help`";
      said += helps[subcommand];
    }
    if (named.empty()) continue;
    const HelpOptions help = options_in_help(said);
    for (const std::string& option : options_in(section.entries)) {
      const bool in_help = std::find(help.listed.begin(), help.listed.end(), option) != help.listed.end() ||
                           std::find(help.mentioned.begin(), help.mentioned.end(), option) != help.mentioned.end();
      EXPECT_TRUE(in_help) << page.page << " documents " << option << " under \"" << section.heading
                           << "\", but " << named << " does not name it";
    }
  }
}

TEST_P(ManualPageTest, HasTheSectionsOfAManualPage) {
  const ManualPage& page = GetParam();
  const std::vector<Section> sections = page_sections(page_source(page));
  for (const char* heading : {"NAME", "SYNOPSIS", "DESCRIPTION", "OPTIONS", "EXIT STATUS", "FILES", "EXAMPLES",
                              "SEE ALSO"}) {
    const bool found = std::any_of(sections.begin(), sections.end(),
                                   [&](const Section& section) { return section.heading == heading; });
    EXPECT_TRUE(found) << page.page << " has no .SH " << heading;
  }
  const auto name = std::find_if(sections.begin(), sections.end(),
                                 [](const Section& section) { return section.heading == "NAME"; });
  ASSERT_NE(name, sections.end());
  EXPECT_EQ(name->text.rfind(page.program + " - ", 0), 0u)
      << page.page << ": the NAME line should begin `" << page.program << " \\- `, not: " << name->text;
  const auto exit_status = std::find_if(sections.begin(), sections.end(),
                                        [](const Section& section) { return section.heading == "EXIT STATUS"; });
  ASSERT_NE(exit_status, sections.end());
  for (const char* status : {"0", "1", "2"}) {
    EXPECT_TRUE(has_word(exit_status->text, status)) << page.page << ": EXIT STATUS does not give status " << status;
  }
}

TEST_P(ManualPageTest, RendersWithoutGroffWarnings) {
  if (run_command("command -v groff").exit_code != 0) {
    GTEST_SKIP() << "groff is not installed (Debian groff-base; scripts/setup.sh installs it): "
                    "the pages' rendering is not checked";
  }
  const ManualPage& page = GetParam();
  const auto result =
      run_command("groff -ww -man -Tutf8 " + shell_quoted(source_path(page.page)) + " >/dev/null");
  EXPECT_EQ(result.exit_code, 0) << page.page << ": " << result.err;
  EXPECT_EQ(result.err, "") << page.page << ": groff -ww -man warns";
}

// A request line's arguments lose their double quotes to roff: the JSON
// shape `{"columns": ..., "rows": ...}` must reach the reader with them.
TEST_P(ManualPageTest, JsonShapeKeepsItsQuotes) {
  if (run_command("command -v groff").exit_code != 0) GTEST_SKIP() << "groff is not installed";
  const ManualPage& page = GetParam();
  if (page_source(page).find("columns") == std::string::npos) GTEST_SKIP() << page.page << " shows no JSON shape";
  const auto rendered =
      run_command("groff -man -Tutf8 " + shell_quoted(source_path(page.page)) + " 2>/dev/null | sed 's/.\\x08//g'");
  std::string text;
  for (const char c : rendered.out) {
    if (c == '\n') {
      text += ' ';
    } else if (c != ' ' || (!text.empty() && text.back() != ' ')) {
      text += c;  // blanks squeezed: justification and line breaks do not matter
    }
  }
  if (text.find("columns\": [...],") == std::string::npos) return;  // no JSON shape shown
  EXPECT_NE(text.find("{\"columns\": [...], \"rows\": [...]}"), std::string::npos)
      << page.page << " does not show the JSON shape with its quotes";
}

// The version a trace's header records as producer.version, from a small render.
std::string recorded_version() {
  TempDir dir;
  const fs::path trace = dir / "t.din.zst";
  const auto rendered = run_command(shell_quoted(program("tracer")) + " render mountain --width 8 --height 6 -q -o " +
                                    shell_quoted(trace));
  EXPECT_EQ(rendered.exit_code, 0) << rendered.err;
  const auto reader = formats::TraceReader::open(trace.string(), {});
  return reader->header().json.at("producer").at("version").get<std::string>();
}

TEST_P(ManualPageTest, VersionIsTheOneTraceHeadersRecord) {
  static const std::string version = recorded_version();
  ASSERT_FALSE(version.empty());
  const ManualPage& page = GetParam();
  const auto result = run_command(shell_quoted(program(page.program)) + " --version");
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(result.out, page.program + " " + version + "\n");
  EXPECT_EQ(result.err, "");
}

TEST_P(ManualPageTest, VersionOnAFullStandardOutputIsExit1) {
  const ManualPage& page = GetParam();
  const auto result = run_command(shell_quoted(program(page.program)) + " --version >/dev/full");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("<stdout>: cannot write: No space left on device"), std::string::npos) << result.err;
}

INSTANTIATE_TEST_SUITE_P(Programs, ManualPageTest, ::testing::ValuesIn(kPages),
                         [](const ::testing::TestParamInfo<ManualPage>& info) {
                           std::string name = info.param.program;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

TEST(ManualPageInstall, PutsEveryPageInShareManMan1AndTheProgramsInBin) {
  TempDir prefix;
  const auto result = run_command(shell_quoted(NODETRACE_CMAKE_COMMAND) + " --install " +
                                  shell_quoted(NODETRACE_BUILD_DIR) + " --prefix " + shell_quoted(prefix.path()));
  ASSERT_EQ(result.exit_code, 0) << result.out << result.err;
  for (const ManualPage& page : kPages) {
    const fs::path installed = prefix / ("share/man/man1/" + page.program + ".1");
    ASSERT_TRUE(fs::exists(installed)) << installed << " was not installed";
    EXPECT_EQ(read_file(installed), read_file(source_path(page.page))) << installed;
    EXPECT_TRUE(fs::exists(prefix / ("bin/" + page.program))) << page.program << " was not installed in bin";
  }
}

}  // namespace
}  // namespace nodetrace::testing
