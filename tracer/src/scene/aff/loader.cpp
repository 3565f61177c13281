// BART AFF (Animated File Format, an NFF extension) scene source: the parsed
// file (aff_parser.cpp) evaluated at an instant, every keyframed transform
// (aff_keyframes) applied down the transform tree (aff_affine) to the
// triangles, normals, lights and camera.
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "scene/aff/scene.hpp"
#include "scene/scene_internal.hpp"
#include "scene/triangle_checks.hpp"

namespace nodetrace::tracer::detail {

namespace {

using namespace aff;

class AffSceneSource final : public SceneSource {
 public:
  explicit AffSceneSource(ParsedAff parsed) : parsed_(std::move(parsed)) {}

  const std::string& name() const override { return parsed_.name; }
  const Animation& animation() const override { return parsed_.animation; }
  std::string content_hash() const override { return parsed_.hash; }
  std::vector<std::string> warnings() const override { return parsed_.warnings; }

  Scene at_time(double time) const override {
    // A NaN time would make the key search run off its keys.
    if (!std::isfinite(time)) throw SceneError(parsed_.name + ": scene time " + std::to_string(time) + " is not finite");
    Scene scene;
    scene.name = parsed_.name;
    scene.materials = parsed_.materials;
    scene.background = parsed_.background;
    scene.ambient = parsed_.ambient;
    scene.default_light = parsed_.default_light;
    scene.suggested_width = parsed_.width;
    scene.suggested_height = parsed_.height;

    std::vector<Affine> world(parsed_.nodes.size()), normal(parsed_.nodes.size());
    for (std::size_t i = 0; i < parsed_.nodes.size(); ++i) {
      const Node& node = parsed_.nodes[i];
      const Affine local = node.animated ? transform_at(node.name, time) : node.local;
      world[i] = node.parent < 0 ? local : world[node.parent] * local;
      normal[i] = world[i].normal_matrix();
    }

    std::size_t total = 0;
    bool any_vertex_normals = false;
    for (const Batch& batch : parsed_.batches) {
      total += batch.corners.size() / 3;
      any_vertex_normals = any_vertex_normals || batch.has_vertex_normals;
    }
    scene.triangles.reserve(total);
    if (any_vertex_normals) scene.vertex_normals.reserve(3 * total);
    for (const Batch& batch : parsed_.batches) {
      const Affine& m = world[batch.node];
      for (std::size_t c = 0; c + 2 < batch.corners.size(); c += 3) {
        scene.triangles.push_back({m.point(batch.corners[c]), m.point(batch.corners[c + 1]),
                                   m.point(batch.corners[c + 2]), batch.material});
        // Transforms may carry a vertex out of range (or to inf).
        check_coordinates_in_range(scene.triangles.back(),
                                   [&] { return parsed_.name + " at time " + std::to_string(time); });
      }
      if (any_vertex_normals) {
        const Affine& n = normal[batch.node];
        for (const Vec3& v : batch.normals) scene.vertex_normals.push_back(normalized_or(n.direction(v), {0, 1, 0}));
      }
    }
    if (scene.materials.empty()) {
      Material fallback;
      fallback.name = "default";
      scene.materials.push_back(fallback);
    }

    for (const auto& light : parsed_.lights) {
      const Vec3 position = light.name.empty() ? light.position : transform_at(light.name, time).point(light.position);
      scene.lights.push_back({position, light.color});
    }

    std::optional<Camera> camera;
    if (parsed_.view) {
      const View& view = *parsed_.view;
      camera = Camera{view.from, view.at, view.up, view.angle};
    }
    if (const auto found = parsed_.transforms.find("camera"); found != parsed_.transforms.end()) {
      // BART's camera path: the eye follows `transl`, and `rot` turns the
      // default view (looking down -z, y up).
      if (!camera) camera = Camera{};
      const AnimatedTransform& path = found->second;
      if (!path.translation.empty()) {
        const auto t = evaluate_vector(path.translation, time);
        const Vec3 offset = camera->look_at - camera->eye;
        camera->eye = {static_cast<float>(t[0]), static_cast<float>(t[1]), static_cast<float>(t[2])};
        camera->look_at = camera->eye + offset;
      }
      if (path.rotation) {
        const Affine rotation = Affine::rotation(path.rotation->at(time));
        camera->look_at = camera->eye + rotation.direction({0, 0, -1});
        camera->up = rotation.direction({0, 1, 0});
      }
    }
    scene.camera = camera;
    return scene;
  }

 private:
  Affine transform_at(const std::string& name, double time) const {
    const auto found = parsed_.transforms.find(name);
    return found == parsed_.transforms.end() ? Affine{} : found->second.at(time);
  }

  ParsedAff parsed_;
};

}  // namespace

std::unique_ptr<SceneSource> open_aff(const std::filesystem::path& path, bool default_lights) {
  ParsedAff parsed = parse_aff(path);
  if (!parsed.ambient_given) {
    if (default_lights) {
      parsed.default_light = "no 'am' line: ambient light 0.1 0.1 0.1 (the AFF default; --default-lights none: 0)";
    } else {
      parsed.ambient = {0, 0, 0};
    }
  }
  return std::make_unique<AffSceneSource>(std::move(parsed));
}

}  // namespace nodetrace::tracer::detail
