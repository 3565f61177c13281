// The documentation (README.md and docs/**/*.md) against the tree and the
// programs: the README stays a front page of at most 300 lines that links
// every guide page; every relative link reaches a file, and a heading when
// it names one; every command of a shell block that calls tracer, cachesim,
// tracetool or dinero-wrap names a subcommand and options that subcommand's
// --help lists (Dinero IV's own for `cachesim dinero`), a script's options
// are in its --help, and a make command's targets and variables are in the
// experiment Makefile; every long option the pages name anywhere is one that
// some program, subcommand or script lists; the blocks marked
// `<!-- doc-test: run -->` run, in a fresh folder; and each number the
// README's headline table quotes is in the section its row links to.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "help_text.hpp"
#include "markdown_pages.hpp"
#include "shell_commands.hpp"
#include "test_support.hpp"

namespace nodetrace::testing {
namespace {

namespace fs = std::filesystem;

const fs::path kSource = NODETRACE_SOURCE_DIR;
const std::vector<std::string> kPrograms = {"tracer", "cachesim", "tracetool", "dinero-wrap"};

std::string where(const MarkdownPage& page, int line) {
  return page.path.generic_string() + ":" + std::to_string(line);
}

bool contains(const std::vector<std::string>& list, const std::string& item) {
  return std::find(list.begin(), list.end(), item) != list.end();
}

// `--help` of a program or subcommand, asked once.
const std::string& help_of(const std::string& program, const std::string& subcommand = {}) {
  static std::map<std::string, std::string> helps;
  const std::string key = program + " " + subcommand;
  auto found = helps.find(key);
  if (found != helps.end()) return found->second;
  const auto result =
      run_command(shell_quoted(testing::program(program)) + (subcommand.empty() ? "" : " " + subcommand) + " --help");
  return helps[key] = result.out;
}

// The program a command's first word runs, as the pages write it:
// `$B/tracer`, `build/bin/tracer` or `tracer`; empty for any other word.
std::string program_in(const std::string& word) {
  static const std::regex path(R"((?:\$B/|\$\{B\}/|(?:\./)?build/bin/)?([a-z-]+))");
  std::smatch match;
  if (!std::regex_match(word, match, path)) return {};
  return contains(kPrograms, match[1]) ? match[1].str() : std::string{};
}

// An option word's name (`--size` of `--size=8k`), or empty for a word that is no long option.
std::string long_option(const std::string& word) {
  static const std::regex option(R"((--[A-Za-z][A-Za-z0-9-]*)(=.*)?)");
  std::smatch match;
  return std::regex_match(word, match, option) ? match[1].str() : std::string{};
}

// The command's words after any `NAME=value` before the program.
std::vector<std::string> without_assignments(const std::vector<std::string>& words) {
  static const std::regex assignment(R"([A-Za-z_][A-Za-z0-9_]*=.*)");
  std::size_t first = 0;
  while (first < words.size() && std::regex_match(words[first], assignment)) ++first;
  return {words.begin() + static_cast<std::ptrdiff_t>(first), words.end()};
}

// What is wrong with the options of `--simulate 'OPTIONS'` (cachesim run's).
std::vector<std::string> simulate_problems(std::string value) {
  std::vector<std::string> problems;
  const std::size_t equals = value.find('=');
  if (!value.empty() && value[0] != '-' && equals != std::string::npos && equals < value.find(' ')) {
    value = value.substr(equals + 1);  // LAYOUT=OPTIONS
  }
  const std::vector<std::string> listed = options_in_help(help_of("cachesim", "run")).listed;
  std::istringstream words(value);
  std::string word;
  while (words >> word) {
    const std::string name = long_option(word);
    if (!name.empty() && !contains(listed, name)) {
      problems.push_back("--simulate names " + name + ", an option `cachesim run --help` does not list");
    }
  }
  return problems;
}

// Whether a one-dash word is an option `cachesim dinero --help` lists, its
// cache options written there for any level and kind (`-lN-Tsize`: N 1 to
// 5, T u, i or d).
bool is_dinero_option(const std::string& word) {
  static const std::vector<std::regex> options = [] {
    std::vector<std::regex> made;
    for (const auto& name : options_in_help(help_of("cachesim", "dinero")).listed) {
      std::string pattern;
      for (std::size_t i = 0; i < name.size(); ++i) {
        if (name.compare(i, 3, "lN-") == 0) {
          pattern += "l[1-5]-";
          i += 2;
        } else if (i > 0 && name[i] == 'T' && name[i - 1] == '-') {
          pattern += "[uid]";
        } else {
          pattern += name[i] == '-' ? std::string("-") : std::string(1, name[i]);
        }
      }
      made.emplace_back(pattern);
    }
    return made;
  }();
  return std::any_of(options.begin(), options.end(),
                     [&](const std::regex& option) { return std::regex_match(word, option); });
}

// What is wrong with one call of a program: its subcommand and options
// against its --help (`cachesim dinero`'s, and those after `--`, are Dinero
// IV's one-dash options).
std::vector<std::string> program_problems(const std::string& program, const std::vector<std::string>& args) {
  if (args.empty()) return {"`" + program + "` names no subcommand"};
  if (args[0] == "--help" || args[0] == "-h" || args[0] == "--version") return {};
  const std::vector<std::string> subcommands = subcommands_in_help(program, help_of(program));
  const std::string& subcommand = args[0];
  if (!contains(subcommands, subcommand)) {
    std::string listed;
    for (const auto& name : subcommands) listed += " " + name;
    return {"`" + program + " " + subcommand + "`: no such subcommand (`" + program + " --help` lists" + listed + ")"};
  }
  const std::vector<std::string> listed = options_in_help(help_of(program, subcommand)).listed;
  const bool dinero_options = program == "cachesim" && subcommand == "dinero";
  std::vector<std::string> problems;
  // `dinero-wrap exec TRACE -- OPTIONS`: Dinero IV's options after `--`.
  const auto end_of_options = std::find(args.begin() + 1, args.end(), std::string("--"));
  static const std::regex one_dash_option("-[A-Za-z][A-Za-z0-9-]*");
  for (auto word = end_of_options; word != args.end(); ++word) {
    if (std::regex_match(*word, one_dash_option) && !is_dinero_option(*word)) {
      problems.push_back("Dinero IV has no option " + *word + " (not in `cachesim dinero --help`)");
    }
  }
  for (std::size_t i = 1; i < args.size() && args[i] != "--"; ++i) {
    std::string name = long_option(args[i]);
    static const std::regex short_option("-[A-Za-z]");
    if (dinero_options && name.empty() && std::regex_match(args[i], one_dash_option)) {
      if (!is_dinero_option(args[i])) {
        problems.push_back("`cachesim dinero` has no option " + args[i] + " (not in `cachesim dinero --help`)");
      }
      continue;
    }
    if (name.empty() && std::regex_match(args[i], short_option)) name = args[i];
    if (name.empty()) continue;
    if (!contains(listed, name)) {
      problems.push_back("`" + program + " " + subcommand + "` has no option " + name + " (not in `" + program + " " +
                         subcommand + " --help`)");
    }
    if (name == "--simulate" && i + 1 < args.size()) {
      for (auto& problem : simulate_problems(args[i + 1])) problems.push_back(problem);
    }
  }
  return problems;
}

// A script's --help (run by the interpreter its #! line names), asked once.
const std::string& script_help(const std::string& script) {
  static std::map<std::string, std::string> helps;
  auto found = helps.find(script);
  if (found != helps.end()) return found->second;
  const fs::path path = kSource / script;
  const std::string text = read_file(path);
  const std::string interpreter = text.rfind("#!", 0) == 0 ? text.substr(2, text.find('\n') - 2) : "sh";
  return helps[script] = run_command("cd / && timeout 60 " + interpreter + " " + shell_quoted(path) + " --help").out;
}

// What is wrong with a script's call: the script must exist and its --help
// name every long option given.
std::vector<std::string> script_problems(const std::vector<std::string>& words) {
  const fs::path script = kSource / words[0];
  if (!fs::is_regular_file(script)) return {words[0] + " is not a file of the tree"};
  std::vector<std::string> options;
  for (std::size_t i = 1; i < words.size(); ++i) {
    const std::string name = long_option(words[i]);
    if (!name.empty()) options.push_back(name);
  }
  if (options.empty()) return {};
  const std::vector<std::string> listed = options_in(script_help(words[0]));
  std::vector<std::string> problems;
  for (const auto& name : options) {
    if (!contains(listed, name)) {
      problems.push_back(words[0] + " has no option " + name + " (not in its --help)");
    }
  }
  return problems;
}

// The experiment Makefiles' text and their .PHONY targets.
struct Makefiles {
  std::string text;
  std::set<std::string> targets;
};

const Makefiles& makefiles() {
  static const Makefiles files = [] {
    Makefiles made;
    for (const auto& entry : fs::directory_iterator(kSource / "scripts")) {
      if (entry.path().extension() == ".mk") made.text += read_file(entry.path()) + "\n";
    }
    static const std::regex phony(R"(\.PHONY:((?:[^\n]*\\\n)*[^\n]*))");
    for (auto it = std::sregex_iterator(made.text.begin(), made.text.end(), phony); it != std::sregex_iterator();
         ++it) {
      std::string list = (*it)[1];
      std::replace(list.begin(), list.end(), '\\', ' ');
      std::istringstream names(list);
      std::string name;
      while (names >> name) made.targets.insert(name);
    }
    return made;
  }();
  return files;
}

// What is wrong with `make -f scripts/X.mk ...`: the file, its targets and
// the variables set.
std::vector<std::string> make_problems(const std::vector<std::string>& words) {
  std::vector<std::string> problems;
  for (std::size_t i = 1; i < words.size(); ++i) {
    const std::string& word = words[i];
    if (word == "-f" && i + 1 < words.size()) {
      if (!fs::is_regular_file(kSource / words[i + 1])) problems.push_back(words[i + 1] + " is not a file of the tree");
      ++i;
    } else if (word.empty() || word[0] == '-') {
      continue;  // make's own options: -n, -j2
    } else if (const std::size_t equals = word.find('='); equals != std::string::npos) {
      const std::regex used("\\b" + word.substr(0, equals) + "\\b");
      if (!std::regex_search(makefiles().text, used)) {
        problems.push_back("make variable " + word.substr(0, equals) + " is not in scripts/*.mk");
      }
    } else if (!makefiles().targets.count(word)) {
      problems.push_back("make target " + word + " is not a .PHONY target of scripts/*.mk");
    }
  }
  return problems;
}

bool is_shell(const FencedBlock& block) {
  return block.language == "sh" || block.language == "bash" || block.language == "shell" || block.language == "console";
}

TEST(Documentation, ReadmeIsAFrontPageOfAtMost300Lines) {
  const std::string readme = read_file(kSource / "README.md");
  const auto lines = std::count(readme.begin(), readme.end(), '\n');
  EXPECT_LE(lines, 300) << "README.md has " << lines
                        << " lines: move the detail to its guide page (docs/guide/), figures to docs/PERFORMANCE.md "
                           "or docs/FINDINGS.md";
}

TEST(Documentation, ReadmeLinksEveryGuidePage) {
  const std::string readme = read_file(kSource / "README.md");
  std::set<std::string> linked;
  for (const auto& link : links(readme)) linked.insert(link.target.substr(0, link.target.find('#')));
  for (const auto& entry : fs::directory_iterator(kSource / "docs" / "guide")) {
    const std::string page = entry.path().lexically_relative(kSource).generic_string();
    EXPECT_TRUE(linked.count(page)) << "README.md does not link " << page << ": a new user finds no way to it";
  }
}

TEST(Documentation, EveryRelativeLinkReachesAFileAndItsHeading) {
  static const std::regex scheme("[A-Za-z][A-Za-z0-9+.-]*:.*");
  int checked = 0;
  for (const auto& page : documentation_pages()) {
    for (const auto& link : links(page.text)) {
      if (std::regex_match(link.target, scheme)) continue;  // http:, mailto:
      const std::size_t hash = link.target.find('#');
      const std::string file = link.target.substr(0, hash);
      const std::string anchor = hash == std::string::npos ? std::string{} : link.target.substr(hash + 1);
      const fs::path target = file.empty() ? kSource / page.path : (kSource / page.path).parent_path() / file;
      ++checked;
      if (!fs::exists(target)) {
        ADD_FAILURE() << where(page, link.line) << ": the link " << link.target << " reaches no file ("
                      << target.lexically_relative(kSource).generic_string() << ")";
        continue;
      }
      if (anchor.empty() || target.extension() != ".md") continue;
      const std::vector<Heading> found = headings(read_file(target));
      const bool has = std::any_of(found.begin(), found.end(), [&](const Heading& h) { return h.anchor == anchor; });
      EXPECT_TRUE(has) << where(page, link.line) << ": the link " << link.target << " names #" << anchor
                       << ", a heading " << target.lexically_relative(kSource).generic_string() << " does not have";
    }
  }
  EXPECT_GT(checked, 100) << "too few links found: is the link pattern still right?";
}

TEST(Documentation, EveryCommandNamesSubcommandsOptionsTargetsAndVariablesThatExist) {
  std::map<std::string, int> checked;  // per kind of command
  for (const auto& page : documentation_pages()) {
    for (const auto& block : fenced_blocks(page.text)) {
      if (!is_shell(block)) continue;
      for (const auto& command : shell_commands(block.body, block.first_line)) {
        const std::vector<std::string> words = without_assignments(command.words);
        if (words.empty()) continue;
        std::vector<std::string> problems;
        if (const std::string program = program_in(words[0]); !program.empty()) {
          problems = program_problems(program, {words.begin() + 1, words.end()});
          ++checked[program];
        } else if (words[0].rfind("scripts/", 0) == 0 || words[0].rfind("./scripts/", 0) == 0) {
          problems = script_problems(words);
          ++checked["scripts"];
        } else if (words[0] == "make") {
          problems = make_problems(words);
          ++checked["make"];
        }
        for (const auto& problem : problems) {
          ADD_FAILURE() << where(page, command.line) << ": " << problem << "\n  " << command.text;
        }
      }
    }
  }
  for (const auto& program : kPrograms) {
    EXPECT_GE(checked[program], 3) << "the pages' shell blocks call " << program << " only " << checked[program]
                                   << " times: is the command pattern still right?";
  }
  EXPECT_GE(checked["scripts"], 10);
  EXPECT_GE(checked["make"], 5);
}

// Long options of other tools the pages call, which no --help here lists.
const std::set<std::string> kOtherToolsOptions = {
    "--install",  "--prefix",             // cmake --install build --prefix ~/.local
    "--test-dir", "--output-on-failure",  // ctest
    "--ntasks",   "--cpus-per-task",      // srun, in RUN= for a cluster
    "--path",                             // primary_rays_bench, built only where Embree is
    "--tool",                             // valgrind --tool=callgrind
};

// Every long option any program, subcommand or script lists in its --help.
std::set<std::string> every_listed_option() {
  std::set<std::string> known;
  for (const auto& program : kPrograms) {
    for (const auto& name : options_in(help_of(program))) known.insert(name);
    for (const auto& subcommand : subcommands_in_help(program, help_of(program))) {
      for (const auto& name : options_in(help_of(program, subcommand))) known.insert(name);
    }
  }
  for (const auto& entry : fs::directory_iterator(kSource / "scripts")) {
    if (!entry.is_regular_file() || read_file(entry.path()).rfind("#!", 0) != 0) continue;
    const std::string script = entry.path().lexically_relative(kSource).generic_string();
    for (const auto& name : options_in(script_help(script))) known.insert(name);
  }
  return known;
}

TEST(Documentation, EveryOptionThePagesNameIsOneAProgramOrScriptHas) {
  const std::set<std::string> known = every_listed_option();
  static const std::regex option(R"((^|[^A-Za-z0-9-])(--[A-Za-z][A-Za-z0-9-]*))");
  for (const auto& page : documentation_pages()) {
    const std::vector<std::string> lines = lines_of(page.text);
    for (std::size_t i = 0; i < lines.size(); ++i) {
      for (auto it = std::sregex_iterator(lines[i].begin(), lines[i].end(), option); it != std::sregex_iterator();
           ++it) {
        const std::string name = (*it)[2];
        EXPECT_TRUE(known.count(name) || kOtherToolsOptions.count(name))
            << where(page, static_cast<int>(i) + 1) << " names " << name
            << ", an option no program, subcommand or script lists in its --help";
      }
    }
  }
}

TEST(Documentation, BlocksMarkedRunRunInAFreshFolder) {
  int ran = 0;
  for (const auto& page : documentation_pages()) {
    for (const auto& block : fenced_blocks(page.text)) {
      if (!block.runnable) continue;
      ++ran;
      TempDir dir;
      fs::create_directories(dir / "build");
      fs::create_directory_symlink(NODETRACE_BIN_DIR, dir / "build" / "bin");
      std::string script;
      for (const auto& line : block.body) script += line + "\n";
      write_file(dir / "block.sh", script);
      const auto result = run_command("cd " + shell_quoted(dir.path()) + " && PATH=" + shell_quoted(NODETRACE_BIN_DIR) +
                                      ":\"$PATH\" timeout 300 bash -e -o pipefail block.sh");
      EXPECT_EQ(result.exit_code, 0) << where(page, block.first_line) << ": the block marked run failed:\n"
                                     << script << "standard error:\n"
                                     << result.err;
    }
  }
  EXPECT_GE(ran, 8) << "fewer blocks marked <!-- doc-test: run --> than the guide has";
}

// Numbers as they stand in text: 2.89, 1,289, 16.8 (not the 6 of 16).
std::vector<std::string> numbers_in(const std::string& text) {
  static const std::regex number(R"(\d+(?:[.,]\d+)*)");
  std::vector<std::string> found;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), number); it != std::sregex_iterator(); ++it) {
    found.push_back(it->str());
  }
  return found;
}

bool has_number(const std::string& text, const std::string& number) {
  auto digit = [&](std::size_t i) { return i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])); };
  for (std::size_t at = text.find(number); at != std::string::npos; at = text.find(number, at + 1)) {
    const bool starts = at == 0 || (!digit(at - 1) && !((text[at - 1] == '.' || text[at - 1] == ',') && digit(at - 2)));
    const std::size_t end = at + number.size();
    const bool ends = !digit(end) && !((end < text.size() && (text[end] == '.' || text[end] == ',')) && digit(end + 1));
    if (starts && ends) return true;
  }
  return false;
}

TEST(Documentation, HeadlineFiguresAreThoseOfTheSectionTheyLinkTo) {
  const std::string readme = read_file(kSource / "README.md");
  const std::string table = section_text(readme, "headline-figures");
  ASSERT_FALSE(table.empty()) << "README.md has no \"Headline figures\" section";
  static const std::regex link(R"(\]\(([^)#\s]+)(?:#([^)\s]+))?\))");
  int rows = 0;
  for (const auto& line : lines_of(table)) {
    if (line.rfind("| [", 0) != 0) continue;  // the header, its rule and the prose
    ++rows;
    std::smatch target;
    ASSERT_TRUE(std::regex_search(line, target, link)) << "a headline row links no page: " << line;
    const std::string page = read_file(kSource / target[1].str());
    const std::string section = target[2].matched ? section_text(page, target[2]) : page;
    ASSERT_FALSE(section.empty()) << target[1] << " has no heading #" << target[2];
    // Every cell but the link's own text and the date of the last one.
    static const std::regex link_text(R"(\[[^\]]*\]\([^)]*\))");
    const std::string cells = std::regex_replace(line.substr(0, line.rfind('|', line.size() - 2)), link_text, "");
    for (const auto& number : numbers_in(cells)) {
      EXPECT_TRUE(has_number(section, number)) << "README.md's headline row quotes " << number << ", which "
                                               << target[1] << "#" << target[2] << " does not give:\n  " << line;
    }
  }
  EXPECT_GE(rows, 8) << "the headline table has too few rows";
}

}  // namespace
}  // namespace nodetrace::testing
