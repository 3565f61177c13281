// What a program's --help says, as the tests that hold the programs to one
// vocabulary and to their manual pages read it: the options it lists and
// names, and the subcommands it lists.
#pragma once

#include <algorithm>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace nodetrace::testing {

inline void add_unique(std::vector<std::string>& list, const std::string& item) {
  if (std::find(list.begin(), list.end(), item) == list.end()) list.push_back(item);
}

// Options named in a help text: a word of one or two dashes and a letter
// (`--size`, `-o`, Dinero IV's `-lN-Tsize`), after a blank, comma, bracket
// or parenthesis. `-` alone and negative numbers are no options.
inline std::vector<std::string> options_in(const std::string& text) {
  static const std::regex option(R"((^|[\s,\[(])(--?[A-Za-z][A-Za-z0-9-]*))");
  std::vector<std::string> found;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), option); it != std::sregex_iterator(); ++it) {
    add_unique(found, (*it)[2]);
  }
  return found;
}

// A help text's options: `listed`, those of its option column (a line that
// begins, after blanks, with a dash: the part before the description, which
// stands two or more blanks further on), and `mentioned`, the others it names
// (in descriptions, usage lines and examples).
struct HelpOptions {
  std::vector<std::string> listed, mentioned;
};

inline HelpOptions options_in_help(const std::string& help) {
  HelpOptions options;
  std::istringstream lines(help);
  std::string line;
  while (std::getline(lines, line)) {
    const std::size_t start = line.find_first_not_of(' ');
    if (start == std::string::npos) continue;
    const std::size_t column_end = line[start] == '-' ? std::min(line.find("  ", start), line.size()) : start;
    for (const auto& name : options_in(line.substr(start, column_end - start))) add_unique(options.listed, name);
  }
  for (const auto& name : options_in(help)) {
    if (std::find(options.listed.begin(), options.listed.end(), name) == options.listed.end()) {
      options.mentioned.push_back(name);
    }
  }
  return options;
}

// Subcommands a program's --help lists: usage lines `  PROGRAM NAME ...`
// (tracer, cachesim, dinero-wrap), or the lines under CLI11's `Subcommands:`
// (tracetool).
inline std::vector<std::string> subcommands_in_help(const std::string& program, const std::string& help) {
  std::vector<std::string> found;
  const std::regex usage_line("^\\s+" + program + " ([a-z][a-z0-9-]*)");
  const std::regex listed_line(R"(^\s+([a-z][a-z0-9-]*)\s)");
  std::istringstream lines(help);
  std::string line;
  bool in_subcommands = false;
  while (std::getline(lines, line)) {
    std::smatch match;
    if (line == "Subcommands:") {
      in_subcommands = true;
    } else if (std::regex_search(line, match, usage_line)) {
      add_unique(found, match[1]);
    } else if (in_subcommands && std::regex_search(line, match, listed_line)) {
      add_unique(found, match[1]);
    } else if (line.empty()) {
      in_subcommands = false;
    }
  }
  return found;
}

}  // namespace nodetrace::testing
