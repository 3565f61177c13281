// Internal pieces shared by the scene loaders (not a public API).
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "nodetrace/tracer/scene/scene_loader.hpp"

namespace nodetrace::tracer::detail {

// FNV-1a 64-bit, continued from `state` so several buffers hash as one.
constexpr std::uint64_t kFnvOffset = 0xcbf29ce484222325ULL;
std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t state = kFnvOffset);
std::string format_hash(std::uint64_t hash);  // "fnv1a64:<16 hex digits>"

// Reads a whole file; throws SceneError naming `path` when it cannot. A
// large regular file's memory is first touched by `threads` threads.
std::string read_scene_file(const std::filesystem::path& path, unsigned threads = 1);

// A scene that does not change with time.
class StaticSceneSource final : public SceneSource {
 public:
  StaticSceneSource(Scene scene, std::string hash, std::vector<std::string> warnings = {})
      : scene_(std::make_shared<const Scene>(std::move(scene))), hash_(std::move(hash)), warnings_(std::move(warnings)) {}
  const std::string& name() const override { return scene_->name; }
  const Animation& animation() const override { return animation_; }
  Scene at_time(double) const override { return *scene_; }
  std::shared_ptr<const Scene> shared_at_time(double) const override { return scene_; }
  std::string content_hash() const override { return hash_; }
  std::vector<std::string> warnings() const override { return warnings_; }

 private:
  std::shared_ptr<const Scene> scene_;
  std::string hash_;
  std::vector<std::string> warnings_;
  Animation animation_;
};

// `default_lights`: SceneLoadOptions::default_lights.
std::unique_ptr<SceneSource> open_aff(const std::filesystem::path& path, bool default_lights = true);
// `threads`: threads reading the file (0: one per core); the scene does not depend on it.
std::unique_ptr<SceneSource> open_obj(const std::filesystem::path& path, unsigned threads = 0,
                                      bool default_lights = true);
// Throws SceneError for an unknown name or a size out of range.
// `size` nullopt: the scene's default size.
std::unique_ptr<SceneSource> open_builtin(const std::string& name, std::optional<int> size);
bool is_builtin_name(const std::string& name);
std::string builtin_names();  // comma-separated, for messages

}  // namespace nodetrace::tracer::detail
