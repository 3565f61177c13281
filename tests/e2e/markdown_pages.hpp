// The documentation's Markdown pages as the documentation tests read them:
// README.md and every docs/**/*.md, their headings (and the anchors GitHub
// makes of them), their links, and their fenced code blocks.
#pragma once

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace nodetrace::testing {

struct MarkdownPage {
  std::filesystem::path path;  // relative to the source folder
  std::string text;
};

// README.md, then every .md under docs/, in name order.
inline std::vector<MarkdownPage> documentation_pages() {
  namespace fs = std::filesystem;
  const fs::path source = NODETRACE_SOURCE_DIR;
  std::vector<fs::path> found{"README.md"};
  std::vector<fs::path> docs;
  for (const auto& entry : fs::recursive_directory_iterator(source / "docs")) {
    if (entry.is_regular_file() && entry.path().extension() == ".md") {
      docs.push_back(entry.path().lexically_relative(source));
    }
  }
  std::sort(docs.begin(), docs.end());
  found.insert(found.end(), docs.begin(), docs.end());
  std::vector<MarkdownPage> pages;
  for (const auto& path : found) pages.push_back({path, read_file(source / path)});
  return pages;
}

inline std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) lines.push_back(line);
  return lines;
}

inline bool is_fence(const std::string& line) { return line.rfind("```", 0) == 0; }

// A fenced code block: its info string (`sh`), the line number of its first
// body line (1-based), its body, and whether the line before it (blank lines
// skipped) is the marker `<!-- doc-test: run -->`.
struct FencedBlock {
  std::string language;
  int first_line = 0;
  std::vector<std::string> body;
  bool runnable = false;
};

inline std::vector<FencedBlock> fenced_blocks(const std::string& text) {
  std::vector<FencedBlock> blocks;
  const std::vector<std::string> lines = lines_of(text);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (!is_fence(lines[i])) continue;
    FencedBlock block;
    block.language = lines[i].substr(3);
    block.first_line = static_cast<int>(i) + 2;
    std::size_t before = i;
    while (before > 0 && lines[before - 1].empty()) --before;
    block.runnable = before > 0 && lines[before - 1] == "<!-- doc-test: run -->";
    for (++i; i < lines.size() && !is_fence(lines[i]); ++i) block.body.push_back(lines[i]);
    blocks.push_back(block);
  }
  return blocks;
}

// The text outside fenced code blocks, each line kept in place (a block's
// lines become empty) so that line numbers hold.
inline std::vector<std::string> prose_lines(const std::string& text) {
  std::vector<std::string> lines = lines_of(text);
  bool in_block = false;
  for (std::string& line : lines) {
    const bool fence = is_fence(line);
    if (fence || in_block) line.clear();
    if (fence) in_block = !in_block;
  }
  return lines;
}

// A heading's level (1 to 6), or 0 for a line that is none.
inline int heading_level(const std::string& line) {
  std::size_t hashes = 0;
  while (hashes < line.size() && line[hashes] == '#') ++hashes;
  return hashes >= 1 && hashes <= 6 && hashes < line.size() && line[hashes] == ' ' ? static_cast<int>(hashes) : 0;
}

// GitHub's anchor for a heading's text: the rendered text (link targets
// and backquotes gone) in lower case, without punctuation other than '-'
// and '_', blanks made '-'.
inline std::string heading_anchor(const std::string& heading) {
  static const std::regex link(R"(\[([^\]]*)\]\([^)]*\))");
  const std::string rendered = std::regex_replace(heading, link, "$1");
  std::string anchor;
  for (const char c : rendered) {
    const auto u = static_cast<unsigned char>(c);
    if (std::isalnum(u) || c == '-' || c == '_') {
      anchor += static_cast<char>(std::tolower(u));
    } else if (c == ' ') {
      anchor += '-';
    }
  }
  return anchor;
}

struct Heading {
  int level = 0;
  int line = 0;  // 1-based
  std::string anchor;
};

// The page's headings with their anchors, a repeated anchor numbered as
// GitHub numbers it (`name`, `name-1`, `name-2`).
inline std::vector<Heading> headings(const std::string& text) {
  std::vector<Heading> found;
  std::map<std::string, int> seen;
  const std::vector<std::string> lines = prose_lines(text);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const int level = heading_level(lines[i]);
    if (level == 0) continue;
    std::string anchor = heading_anchor(lines[i].substr(static_cast<std::size_t>(level) + 1));
    const int repeats = seen[anchor]++;
    if (repeats > 0) {
      anchor += '-';
      anchor += std::to_string(repeats);
    }
    found.push_back({level, static_cast<int>(i) + 1, anchor});
  }
  return found;
}

// The text of the section an anchor names: its heading to the next heading
// of the same or a higher level. Empty when no heading has that anchor.
inline std::string section_text(const std::string& text, const std::string& anchor) {
  const std::vector<Heading> all = headings(text);
  const std::vector<std::string> lines = lines_of(text);
  for (std::size_t h = 0; h < all.size(); ++h) {
    if (all[h].anchor != anchor) continue;
    std::size_t end = lines.size();
    for (std::size_t next = h + 1; next < all.size(); ++next) {
      if (all[next].level <= all[h].level) {
        end = static_cast<std::size_t>(all[next].line - 1);
        break;
      }
    }
    std::string section;
    for (std::size_t i = static_cast<std::size_t>(all[h].line - 1); i < end; ++i) section += lines[i] + "\n";
    return section;
  }
  return {};
}

struct MarkdownLink {
  int line = 0;  // 1-based
  std::string target;
};

// The inline links and images of the prose, inline code left out.
inline std::vector<MarkdownLink> links(const std::string& text) {
  static const std::regex code("`[^`]*`");
  static const std::regex link(R"(\]\(([^)\s]+)\))");
  std::vector<MarkdownLink> found;
  const std::vector<std::string> lines = prose_lines(text);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string line = std::regex_replace(lines[i], code, "``");
    for (auto it = std::sregex_iterator(line.begin(), line.end(), link); it != std::sregex_iterator(); ++it) {
      found.push_back({static_cast<int>(i) + 1, (*it)[1]});
    }
  }
  return found;
}

}  // namespace nodetrace::testing
