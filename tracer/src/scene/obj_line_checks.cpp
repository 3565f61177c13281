#include "scene/obj_line_checks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "nodetrace/tracer/scene/scene_loader.hpp"
#include "scene/obj_chunks.hpp"

namespace nodetrace::tracer::detail {

namespace {

// The next word of `rest` (blank-separated), taken off its front; empty at its end.
std::string_view next_word(std::string_view& rest) {
  const std::size_t begin = rest.find_first_not_of(" \t\r");
  if (begin == std::string_view::npos) return std::string_view{};
  rest.remove_prefix(begin);
  const std::size_t end = std::min(rest.find_first_of(" \t\r"), rest.size());
  const std::string_view word = rest.substr(0, end);
  rest.remove_prefix(end);
  return word;
}

// Calls visit(line_number, keyword, words) for each `v`, `vn`, `vt` and `f`
// line of an OBJ text whose first line is `first_line`; `words` holds what
// follows the keyword up to a comment, and is made only for the lines whose
// keyword `with_words(keyword)` accepts (the others are only counted by a pass).
template <typename WithWords, typename Visit>
void for_each_line(std::string_view text, std::int64_t first_line, WithWords with_words, Visit visit) {
  std::size_t line_start = 0;
  std::vector<std::string_view> words;
  for (std::int64_t line = first_line; line_start < text.size(); ++line) {
    std::size_t line_end = text.find('\n', line_start);
    if (line_end == std::string::npos) line_end = text.size();
    std::string_view rest(text.data() + line_start, line_end - line_start);
    line_start = line_end + 1;
    const std::string_view keyword = next_word(rest);
    if (keyword != "v" && keyword != "vn" && keyword != "vt" && keyword != "f") continue;
    words.clear();
    if (with_words(keyword)) {
      for (std::string_view word = next_word(rest); !word.empty() && word.front() != '#'; word = next_word(rest)) {
        words.push_back(word);
      }
    }
    visit(line, keyword, words);
  }
}

struct ElementCounts {
  std::int64_t vertices = 0, texcoords = 0, normals = 0;
  void count(std::string_view keyword) { (keyword == "v" ? vertices : keyword == "vt" ? texcoords : normals) += 1; }
};

[[noreturn]] void fail(const std::filesystem::path& path, std::int64_t line, const std::string& what) {
  throw SceneError(path.string() + ":" + std::to_string(line) + ": " + what);
}

// The coordinates of a chunk's `v`, `vn` and `vt` lines; returns its counts.
ElementCounts check_numbers(std::string_view chunk, std::int64_t first_line, const std::filesystem::path& path) {
  ElementCounts counts;
  const auto coordinates = [](std::string_view keyword) { return keyword != "f"; };
  for_each_line(chunk, first_line, coordinates, [&](std::int64_t line, std::string_view keyword, const std::vector<std::string_view>& words) {
    if (keyword == "f") return;
    counts.count(keyword);
    for (std::string_view word : words) {
      if (word.front() == '+') word.remove_prefix(1);
      double value = 0;
      const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
      // tinyobjloader stores floats: beyond FLT_MAX a value becomes inf.
      if (error != std::errc() || end != word.data() + word.size() || !(std::fabs(value) <= FLT_MAX)) {
        fail(path, line, fmt::format("expected a finite number of at most {:g} in magnitude in '{}' line, got '{}'",
                                     FLT_MAX, keyword, word));
      }
    }
  });
  return counts;
}

// The indices of a chunk's `f` lines; `before`: the elements above the chunk.
void check_faces(std::string_view chunk, std::int64_t first_line, ElementCounts before, const ElementCounts& total,
                 const std::filesystem::path& path) {
  const auto faces = [](std::string_view keyword) { return keyword == "f"; };
  for_each_line(chunk, first_line, faces, [&](std::int64_t line, std::string_view keyword, const std::vector<std::string_view>& words) {
    if (keyword != "f") {
      before.count(keyword);
      return;
    }
    if (words.size() < 3) {
      fail(path, line, "expected a face of at least 3 vertices, got " + std::to_string(words.size()));
    }
    for (const std::string_view word : words) {
      // v, v/vt, v//vn or v/vt/vn
      std::string_view parts[3];
      std::size_t part_count = 0;
      bool too_many_parts = false;
      for (std::size_t start = 0;;) {
        const std::size_t slash = word.find('/', start);
        if (part_count == 3) {
          too_many_parts = true;
          break;
        }
        parts[part_count++] = word.substr(start, slash == std::string_view::npos ? std::string_view::npos : slash - start);
        if (slash == std::string_view::npos) break;
        start = slash + 1;
      }
      if (too_many_parts || parts[0].empty()) {
        fail(path, line, "expected a face vertex such as 3, 3/1, 3//2 or 3/1/2, got '" + std::string(word) + "'");
      }
      static const char* const kWhat[3] = {"vertex", "texture coordinate", "normal"};
      const std::int64_t totals[3] = {total.vertices, total.texcoords, total.normals};
      const std::int64_t above[3] = {before.vertices, before.texcoords, before.normals};
      for (std::size_t k = 0; k < part_count; ++k) {
        if (k > 0 && parts[k].empty()) continue;  // 3//2: no texture coordinate
        std::int64_t index = 0;
        const auto [end, error] = std::from_chars(parts[k].data(), parts[k].data() + parts[k].size(), index);
        if (error != std::errc() || end != parts[k].data() + parts[k].size()) {
          fail(path, line, std::string("expected an integer ") + kWhat[k] + " index in face vertex '" + std::string(word) +
                               "', got '" + std::string(parts[k]) + "'");
        }
        if (index > 0 ? index > totals[k] : (index == 0 || -index > above[k])) {
          fail(path, line, fmt::format("{} index {} is out of range ({} {})", kWhat[k], index,
                                       index > 0 ? totals[k] : above[k],
                                       std::string(k == 0 ? "vertices" : k == 1 ? "texture coordinates" : "normals") +
                                           (index > 0 ? "" : " before this line")));
        }
      }
    }
  });
}

}  // namespace

// Three passes over the chunks, each on the threads: the lines (for their
// numbers), the coordinates (all of them come before any face in the order
// of errors, as in one pass over the file), the faces. The first chunk's
// error in a pass is the first line's.
void check_obj_lines(std::span<const std::string_view> chunks, const std::filesystem::path& path, unsigned threads) {
  std::vector<std::int64_t> first_lines(chunks.size() + 1, 1);
  for_each_chunk(chunks.size(), threads, [&](std::size_t i) {
    first_lines[i + 1] = std::count(chunks[i].begin(), chunks[i].end(), '\n');
  });
  for (std::size_t i = 0; i < chunks.size(); ++i) first_lines[i + 1] += first_lines[i];
  std::vector<ElementCounts> counts(chunks.size());
  for_each_chunk(chunks.size(), threads,
                 [&](std::size_t i) { counts[i] = check_numbers(chunks[i], first_lines[i], path); });
  std::vector<ElementCounts> before(chunks.size());
  ElementCounts total;
  for (std::size_t i = 0; i < chunks.size(); ++i) {
    before[i] = total;
    total.vertices += counts[i].vertices;
    total.texcoords += counts[i].texcoords;
    total.normals += counts[i].normals;
  }
  for_each_chunk(chunks.size(), threads,
                 [&](std::size_t i) { check_faces(chunks[i], first_lines[i], before[i], total, path); });
}

}  // namespace nodetrace::tracer::detail
