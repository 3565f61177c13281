// Finding Dinero IV, building its arguments and reading its output.
#include <unistd.h>

#include <fmt/format.h>

#include <cctype>
#include <charconv>
#include <cstdlib>
#include <filesystem>

#include "nodetrace/cachesim/wrap/wrap.hpp"
#include "nodetrace/base/error.hpp"

namespace nodetrace::cachesim::wrap {

std::vector<std::string> split_command(std::string_view command) {
  std::vector<std::string> words;
  std::string word;
  bool in_word = false;
  char quote = 0;
  for (const char c : command) {
    if (quote) {
      if (c == quote) {
        quote = 0;
      } else {
        word += c;
      }
    } else if (c == '\'' || c == '"') {
      quote = c;
      in_word = true;
    } else if (std::isspace(static_cast<unsigned char>(c))) {
      if (in_word) words.push_back(std::move(word));
      word.clear();
      in_word = false;
    } else {
      word += c;
      in_word = true;
    }
  }
  if (quote) {
    throw base::UsageError(fmt::format("unterminated quote in command '{}'", command));
  }
  if (in_word) words.push_back(std::move(word));
  return words;
}

std::vector<std::string> find_dinero(const std::optional<std::string>& option) {
  auto from = [](std::string_view command, std::string_view where) {
    std::vector<std::string> words = split_command(command);
    if (words.empty()) {
      throw base::UsageError(fmt::format("{} is empty: expected a Dinero IV command", where));
    }
    return words;
  };
  if (option) return from(*option, "--dinero");
  if (const char* env = std::getenv("DINEROIV"); env && *env) return from(env, "$DINEROIV");
  if (const char* path = std::getenv("PATH")) {
    std::string_view rest = path;
    while (true) {
      const std::size_t colon = rest.find(':');
      const std::string_view dir = rest.substr(0, colon);
      const std::filesystem::path candidate =
          std::filesystem::path(dir.empty() ? "." : std::string(dir)) / "dineroIV";
      if (::access(candidate.c_str(), X_OK) == 0) return {candidate.string()};
      if (colon == std::string_view::npos) break;
      rest.remove_prefix(colon + 1);
    }
  }
  throw base::UsageError(
      "Dinero IV not found: no --dinero option, no $DINEROIV, no dineroIV on PATH. Point at one "
      "with --dinero CMD or DINEROIV=CMD (CMD may carry arguments, e.g. --dinero \"cachesim "
      "dinero\" for this project's drop-in replacement)");
}

namespace {

bool is_cache_name(std::string_view line) {
  // l1-ucache, l2-icache, ...
  return line.size() == 9 && line[0] == 'l' && line[1] >= '1' && line[1] <= '9' &&
         line[2] == '-' && (line[3] == 'u' || line[3] == 'i' || line[3] == 'd') &&
         line.substr(4) == "cache";
}

std::optional<std::uint64_t> first_number_after(std::string_view line, std::string_view label) {
  std::string_view rest = line.substr(line.find(label) + label.size());
  while (!rest.empty() && std::isspace(static_cast<unsigned char>(rest.front()))) {
    rest.remove_prefix(1);
  }
  std::uint64_t value = 0;
  const auto [next, error] = std::from_chars(rest.data(), rest.data() + rest.size(), value);
  if (error != std::errc{} || next == rest.data()) return std::nullopt;
  if (next != rest.data() + rest.size() && !std::isspace(static_cast<unsigned char>(*next))) {
    return std::nullopt;
  }
  return value;
}

}  // namespace

std::vector<DineroCacheStats> parse_dinero_output(std::string_view output) {
  std::vector<DineroCacheStats> caches;
  bool have_fetches = false;
  bool have_misses = false;
  std::size_t line_number = 0;
  auto check_complete = [&] {
    if (!caches.empty() && (!have_fetches || !have_misses)) {
      throw base::FormatError(fmt::format(
          "Dinero IV output: cache table {} has no {} row", caches.back().name,
          have_fetches ? "Demand Misses" : "Demand Fetches"));
    }
  };
  while (!output.empty()) {
    const std::size_t end = output.find('\n');
    std::string_view line = output.substr(0, end);
    output.remove_prefix(end == std::string_view::npos ? output.size() : end + 1);
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (is_cache_name(line)) {
      check_complete();
      caches.push_back({std::string(line), 0, 0});
      have_fetches = have_misses = false;
      continue;
    }
    if (caches.empty()) continue;
    for (const auto& [label, target, seen] :
         {std::tuple{std::string_view(" Demand Fetches"), &caches.back().demand_fetches, &have_fetches},
          std::tuple{std::string_view(" Demand Misses"), &caches.back().demand_misses, &have_misses}}) {
      if (!line.starts_with(label) || *seen) continue;
      const auto value = first_number_after(line, label);
      if (!value) {
        throw base::FormatError(fmt::format(
            "Dinero IV output line {}: expected a count after '{}' in table {}", line_number,
            label.substr(1), caches.back().name));
      }
      *target = *value;
      *seen = true;
    }
  }
  check_complete();
  if (caches.empty()) {
    throw base::FormatError("Dinero IV output has no cache table (no line like 'l1-ucache')");
  }
  return caches;
}

std::vector<std::string> dinero_cache_arguments(formats::RecordForm form,
                                                const CacheGeometry& geometry, FetchPolicy fetch,
                                                std::uint32_t prefetch_distance) {
  // Binary traces are fed as extended din text, which keeps address and size.
  const char informat = form == formats::RecordForm::Din ? 'd' : 'D';
  std::vector<std::string> arguments{"-informat", std::string(1, informat),
                                     "-l1-usize", std::to_string(geometry.size),
                                     "-l1-ubsize", std::to_string(geometry.block_size),
                                     "-l1-uassoc", std::to_string(geometry.assoc),
                                     "-l1-urepl", std::string(1, dinero_policy_letter(geometry.replacement))};
  if (fetch != FetchPolicy::Demand) {
    arguments.insert(arguments.end(), {"-l1-ufetch", std::string(1, dinero_fetch_letter(fetch)),
                                       "-l1-upfdist", std::to_string(prefetch_distance)});
  }
  return arguments;
}

}  // namespace nodetrace::cachesim::wrap
