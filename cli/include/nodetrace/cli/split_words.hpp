// An option's text that holds a command line of its own (tracer render
// --simulate "OPTIONS") split into words as a POSIX shell splits them, with
// no expansion: blanks separate words; '...' keeps everything; "..." keeps
// everything but \" and \\ (a backslash and the next character); a
// backslash outside quotes keeps the next character.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace nodetrace::cli {

// The words of `text`; base::UsageError naming `option` on a quote left open
// or a trailing backslash.
std::vector<std::string> split_words(std::string_view text, const char* option);

}  // namespace nodetrace::cli
