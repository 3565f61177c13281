// Keyword arguments as the command line's words, so that the programs' own
// option parsers read them: name_with_underscores=VALUE becomes
// --name-with-underscores VALUE; True a flag, False and None nothing, a list
// or tuple one word per element.
#pragma once

#include <pybind11/pybind11.h>

#include <string>
#include <vector>

namespace nodetrace::python {

inline void append_option_words(std::vector<std::string>& words, const std::string& name,
                                 const pybind11::handle& value) {
  std::string option = "--" + name;
  for (char& c : option) {
    if (c == '_') c = '-';
  }
  if (value.is_none() || (pybind11::isinstance<pybind11::bool_>(value) && !value.cast<bool>())) return;
  words.push_back(option);
  if (pybind11::isinstance<pybind11::bool_>(value)) return;
  if (pybind11::isinstance<pybind11::list>(value) || pybind11::isinstance<pybind11::tuple>(value)) {
    for (const auto& item : value) words.push_back(pybind11::str(item).cast<std::string>());
    return;
  }
  words.push_back(pybind11::str(value).cast<std::string>());
}

inline std::vector<std::string> option_words(const pybind11::dict& options) {
  std::vector<std::string> words;
  for (const auto& [name, value] : options) append_option_words(words, name.cast<std::string>(), value);
  return words;
}

}  // namespace nodetrace::python
