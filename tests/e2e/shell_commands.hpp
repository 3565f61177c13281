// The simple commands of a documentation page's shell block, as the
// documentation tests check them: lines joined at a trailing backslash,
// comments dropped, words split as sh splits them (quotes group and are
// removed, `$B` is left as written), commands cut at `|`, `;`, `&&`, `||`
// and `&`, redirections and their files left out, and the words `do` and
// `then` that begin a loop's or a condition's body dropped.
#pragma once

#include <string>
#include <vector>

namespace nodetrace::testing {

struct ShellCommand {
  int line = 0;                    // 1-based line of the page where it starts
  std::vector<std::string> words;  // quotes removed
  std::string text;                // the logical line it comes from, for messages
};

// The commands of a block whose first body line is line `first_line` of its page.
inline std::vector<ShellCommand> shell_commands(const std::vector<std::string>& body, int first_line) {
  std::vector<ShellCommand> commands;
  for (std::size_t i = 0; i < body.size(); ++i) {
    const int line = first_line + static_cast<int>(i);
    std::string logical = body[i];
    while (!logical.empty() && logical.back() == '\\' && i + 1 < body.size()) {
      logical.pop_back();
      logical += " " + body[++i];
    }
    ShellCommand command{line, {}, logical};
    std::string word;
    bool in_word = false, redirect = false;
    auto end_word = [&] {
      if (in_word && !redirect) command.words.push_back(word);
      if (in_word) redirect = false;
      word.clear();
      in_word = false;
    };
    auto end_command = [&] {
      end_word();
      redirect = false;
      while (!command.words.empty() && (command.words.front() == "do" || command.words.front() == "then")) {
        command.words.erase(command.words.begin());
      }
      if (!command.words.empty()) commands.push_back(command);
      command.words.clear();
    };
    for (std::size_t c = 0; c < logical.size(); ++c) {
      const char ch = logical[c];
      if (ch == '\'' || ch == '"') {
        const std::size_t close = logical.find(ch, c + 1);
        word += logical.substr(c + 1, close == std::string::npos ? std::string::npos : close - c - 1);
        in_word = true;
        if (close == std::string::npos) break;
        c = close;
      } else if (ch == '#' && !in_word) {
        break;  // a comment, to the end of the line
      } else if (ch == ' ' || ch == '\t') {
        end_word();
      } else if (ch == '|' || ch == ';' || ch == '&') {
        end_command();
        if (c + 1 < logical.size() && logical[c + 1] == ch) ++c;
      } else if (ch == '>' || ch == '<') {
        // A descriptor before it (`2>`) is no word; `>&1` names no file.
        if (in_word && word != "1" && word != "2") end_word();
        word.clear();
        in_word = false;
        redirect = true;
        if (c + 1 < logical.size() && (logical[c + 1] == ch || logical[c + 1] == '&')) ++c;
      } else {
        word += ch;
        in_word = true;
      }
    }
    end_command();
  }
  return commands;
}

}  // namespace nodetrace::testing
