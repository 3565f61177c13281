// The body of the scene-loader targets: scene files written into a private
// folder and opened as the tracer opens them; every input must load or be
// rejected with SceneError.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "fuzz_support.hpp"
#include "nodetrace/tracer/scene/scene_loader.hpp"

namespace nodetrace::fuzz {

inline const std::filesystem::path& scene_folder() {
  static const std::filesystem::path folder = [] {
    std::string pattern = (std::filesystem::temp_directory_path() / "nodetrace-fuzz-XXXXXX").string();
    if (!::mkdtemp(pattern.data())) std::abort();
    return std::filesystem::path(pattern);
  }();
  return folder;
}

inline void put_file(const std::string& name, std::string_view bytes) {
  std::ofstream out(scene_folder() / name, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

inline void load_scene(const std::string& name) {
  try {
    const auto source = tracer::open_scene((scene_folder() / name).string());
    const auto& animation = source->animation();
    source->at_time(0.0);
    if (animation.frames > 1) source->at_time(animation.time_of_frame(animation.frames - 1));
  } catch (const tracer::SceneError&) {
  }
}

}  // namespace nodetrace::fuzz
