#include "scene/mtl_checks.hpp"

#include <fmt/format.h>

#include <array>
#include <cfloat>
#include <charconv>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>

#include "nodetrace/tracer/scene/scene_loader.hpp"

namespace nodetrace::tracer::detail {

namespace {

constexpr std::array<std::string_view, 10> kCheckedKeywords = {"Ka", "Kd", "Ks", "Ke", "Tf", "Ns", "Ni", "d", "Tr",
                                                                "Pr"};

std::optional<double> number(const std::string& word) {
  std::string_view text = word;
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  double value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

}  // namespace

void check_mtl_numbers(std::string_view text, const std::filesystem::path& path) {
  std::istringstream input{std::string(text)};
  std::string line;
  for (int line_number = 1; std::getline(input, line); ++line_number) {
    std::istringstream words(line);
    std::string keyword, word;
    if (!(words >> keyword)) continue;
    bool checked = false;
    for (const auto candidate : kCheckedKeywords) checked = checked || keyword == candidate;
    if (!checked) continue;
    for (bool first = true; words >> word && word[0] != '#'; first = false) {
      const std::optional<double> value = number(word);
      if (!value) {
        if (first) break;  // a form of its own (`Kd spectral ...`): tinyobjloader's
        continue;
      }
      const auto fail = [&](std::string_view expected) {
        throw SceneError(fmt::format("{}:{}: {} {}: expected {}", path.string(), line_number, keyword, word,
                                     expected));
      };
      if (!std::isfinite(*value) || std::fabs(*value) > FLT_MAX) {
        fail(fmt::format("a finite number of at most {:g} in magnitude", FLT_MAX));
      }
      if (*value < 0) fail("a number of at least 0 (a negative one would give negative radiance)");
      if (keyword == "Ni" && *value == 0) fail("an index of refraction above 0");
      if (keyword == "Pr" && !(*value > 0 && *value <= 1)) {
        fail("a roughness above 0 and at most 1 (a smooth mirror is illum 3, not Pr 0)");
      }
    }
  }
}

}  // namespace nodetrace::tracer::detail
