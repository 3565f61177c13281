#include "nodetrace/cli/split_words.hpp"

#include <fmt/format.h>

#include "nodetrace/base/error.hpp"

namespace nodetrace::cli {

namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

}  // namespace

std::vector<std::string> split_words(std::string_view text, const char* option) {
  std::vector<std::string> words;
  std::string word;
  bool in_word = false;  // "" is a word
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (is_blank(c)) {
      if (in_word) words.push_back(std::move(word));
      word.clear();
      in_word = false;
      continue;
    }
    in_word = true;
    if (c == '\\') {
      if (++i == text.size()) {
        throw base::UsageError(fmt::format("{}: '{}' ends in a backslash: nothing follows it to keep", option, text));
      }
      word += text[i];
    } else if (c == '\'' || c == '"') {
      const std::size_t open = i;
      for (++i; i < text.size() && text[i] != c; ++i) {
        if (c == '"' && text[i] == '\\' && i + 1 < text.size() && (text[i + 1] == '"' || text[i + 1] == '\\')) ++i;
        word += text[i];
      }
      if (i == text.size()) {
        throw base::UsageError(fmt::format("{}: '{}': the quote {} at character {} is not closed", option, text, c,
                                           open + 1));
      }
    } else {
      word += c;
    }
  }
  if (in_word) words.push_back(std::move(word));
  return words;
}

}  // namespace nodetrace::cli
