// An AFF file as parsed, before any instant is evaluated: the transform
// nodes, triangle batches in local coordinates, materials, lights, view and
// keyframe tracks. Internal to the AFF loader.
#pragma once

#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "scene/aff/affine.hpp"
#include "scene/aff/keyframes.hpp"
#include "nodetrace/tracer/scene/scene_loader.hpp"

namespace nodetrace::tracer::detail::aff {

struct Node {
  int parent = -1;
  bool animated = false;
  std::string name;  // animated: the `k` block giving its transform
  Affine local;      // static
};

// Triangles under one transform node with one material, in local coordinates.
struct Batch {
  int node = 0;
  std::uint32_t material = 0;
  std::vector<Vec3> corners;  // three per triangle
  std::vector<Vec3> normals;  // parallel to corners (face normals where the file gave none)
  bool has_vertex_normals = false;
};

struct LightDefinition {
  std::string name;  // animated: moved by the transform of `k name`
  Vec3 position;
  Vec3 color{1, 1, 1};
};

struct View {
  Vec3 from{0, 0, 1}, at{0, 0, 0}, up{0, 1, 0};
  float angle = 45;
};

struct ParsedAff {
  std::string name;
  std::string hash;
  Animation animation;
  std::vector<Node> nodes;
  std::vector<Batch> batches;
  std::vector<Material> materials;
  std::vector<LightDefinition> lights;
  std::optional<View> view;
  std::optional<int> width, height;
  Vec3 background{0, 0, 0};
  Vec3 ambient{0.1f, 0.1f, 0.1f};
  bool ambient_given = false;  // an `am` line
  std::string default_light;   // Scene::default_light
  std::map<std::string, AnimatedTransform, std::less<>> transforms;
  std::vector<std::string> warnings;
};

inline Vec3 normalized_or(const Vec3& v, const Vec3& fallback) {
  const float len = length(v);
  return len > 0 && std::isfinite(len) ? v / len : fallback;
}

// Parses `path` and the files it includes; throws SceneError naming the file
// and line of what is wrong, or when the scene has no triangle.
ParsedAff parse_aff(const std::filesystem::path& path);

}  // namespace nodetrace::tracer::detail::aff
