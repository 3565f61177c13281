// open_scene: dispatch a scene spec to the OBJ, AFF or built-in loader.
#include "nodetrace/tracer/scene/scene_loader.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "nodetrace/base/huge_pages.hpp"
#include "scene/scene_internal.hpp"

namespace nodetrace::tracer {

namespace detail {

std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t state) {
  for (const unsigned char byte : bytes) {
    state ^= byte;
    state *= 0x100000001b3ULL;
  }
  return state;
}

std::string format_hash(std::uint64_t hash) {
  char text[32];
  std::snprintf(text, sizeof text, "fnv1a64:%016llx", static_cast<unsigned long long>(hash));
  return text;
}

std::string read_scene_file(const std::filesystem::path& path, unsigned threads) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path.string() + ": cannot open scene file");
  std::string contents;
  // A regular file in one read into memory of its size (on huge pages when
  // large): copied through a growing stream buffer, a 100 MB OBJ file's pages
  // were touched three times over.
  std::error_code error;
  if (std::filesystem::is_regular_file(path, error)) {
    const std::uintmax_t size = std::filesystem::file_size(path, error);
    if (!error && size > 0) {
      contents.reserve(size);
      base::ask_for_huge_pages(contents.data(), contents.capacity());
      base::touch_pages_in_parallel(contents.data(), contents.capacity(), threads);
      contents.resize(size);
      in.read(contents.data(), static_cast<std::streamsize>(size));
      contents.resize(static_cast<std::size_t>(in.gcount()));
    }
  }
  // The rest: all of a pipe's bytes, or what a file gained since its size was taken.
  if (!in.eof() && !in.bad()) {
    std::ostringstream rest;
    rest << in.rdbuf();
    contents += std::move(rest).str();
  }
  if (in.bad()) throw SceneError(path.string() + ": read error");
  return contents;
}

}  // namespace detail

namespace {

std::string lowercase_extension(const std::string& spec) {
  std::string extension = std::filesystem::path(spec).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

}  // namespace

std::unique_ptr<SceneSource> open_scene(const std::string& spec, const SceneLoadOptions& options) {
  const std::string extension = lowercase_extension(spec);
  if (extension == ".obj") return detail::open_obj(spec, options.threads, options.default_lights);
  if (extension == ".aff") return detail::open_aff(spec, options.default_lights);

  std::string name = spec;
  std::optional<int> size;
  if (options.builtin_size != 0) size = options.builtin_size;
  if (const auto colon = spec.find(':'); colon != std::string::npos) {
    name = spec.substr(0, colon);
    const std::string size_text = spec.substr(colon + 1);
    size.emplace();
    const auto [end, error] = std::from_chars(size_text.data(), size_text.data() + size_text.size(), *size);
    if (error != std::errc() || end != size_text.data() + size_text.size() || size_text.empty()) {
      throw SceneError("scene '" + spec + "': expected NAME:SIZE with an integer size, got '" +
                       size_text + "'");
    }
  }
  if (detail::is_builtin_name(name)) return detail::open_builtin(name, size);
  if (std::filesystem::is_directory(spec)) {
    throw SceneError(spec + ": is a directory, not a scene file (expected an .obj or .aff file, or a built-in "
                     "scene: " + detail::builtin_names() + ")");
  }
  if (std::filesystem::exists(spec)) {
    throw SceneError(spec + ": unsupported scene file type '" + extension +
                     "' (expected .obj or .aff)");
  }
  throw SceneError("scene '" + spec + "': no such file, and not a built-in scene (built-in: " +
                   detail::builtin_names() + ")");
}

}  // namespace nodetrace::tracer
