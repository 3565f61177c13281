// A scene at one instant: what the kd-tree is built over and the renderer
// shades. Loaders (OBJ, BART AFF, built-in procedural scenes) produce it.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "nodetrace/tracer/geometry/vec3.hpp"

namespace nodetrace::tracer {

// Whitted material (NFF/AFF style): local colour plus mirror and transmission.
struct Material {
  std::string name;
  Vec3 diffuse{0.8f, 0.8f, 0.8f};  // Kd
  Vec3 specular{0, 0, 0};          // Ks (Phong highlight colour)
  float shininess = 0;             // Phong exponent
  float reflectance = 0;           // mirror weight, 0..1 (casts reflection rays when > 0)
  float transmittance = 0;         // transmission weight, 0..1 (casts refraction rays when > 0)
  float ior = 1;                   // index of refraction
  // Emitted radiance (OBJ `Ke`, AFF `fe`): a triangle of a material that
  // emits is an area light, emitting from both faces.
  Vec3 emission{0, 0, 0};
  // A GGX microfacet lobe (OBJ `Pr` with `Ks` its colour, AFF `fg`): Blender
  // Cycles' Glossy BSDF with distribution GGX, of this colour and roughness
  // (the node's Roughness, 0 to 1; alpha is its square). Roughness 0: no
  // such lobe.
  Vec3 ggx_color{0, 0, 0};
  float ggx_roughness = 0;
  // Ambient reflectance (AFF `fm`), multiplied by Scene::ambient; nullopt:
  // use `diffuse`.
  std::optional<Vec3> ambient;
};

struct PointLight {
  Vec3 position;
  Vec3 color{1, 1, 1};
};

struct Camera {
  Vec3 eye{0, 0, 1};
  Vec3 look_at{0, 0, 0};
  Vec3 up{0, 1, 0};
  float fov_y_degrees = 45;  // vertical field of view
};

// The largest coordinate magnitude of a triangle vertex the loaders accept:
// 2^62 (about 4.6e18). Up to it, the squared length of any difference of two
// points (a scene diagonal, a light direction) stays within float, and the
// kd-tree's SAH areas (in double) are far from overflow.
inline constexpr float kMaxSceneCoordinate = 0x1p62f;

struct Triangle {
  Vec3 v0, v1, v2;
  std::uint32_t material = 0;
};

struct Bounds {
  Vec3 lo{std::numeric_limits<float>::max(), std::numeric_limits<float>::max(),
          std::numeric_limits<float>::max()};
  Vec3 hi{std::numeric_limits<float>::lowest(), std::numeric_limits<float>::lowest(),
          std::numeric_limits<float>::lowest()};
  void extend(const Vec3& p) { lo = min(lo, p); hi = max(hi, p); }
  bool empty() const { return lo.x > hi.x; }
};

struct Scene {
  std::string name;  // file name without directories, or built-in scene name
  std::vector<Triangle> triangles;
  // Per-vertex normals for smooth shading, parallel to `triangles` (three per
  // triangle); empty when the scene has none or shading does not use them.
  std::vector<Vec3> vertex_normals;
  std::vector<Material> materials;  // at least one
  std::vector<PointLight> lights;
  std::optional<Camera> camera;     // nullopt: frame the bounds by default
  Vec3 background{0, 0, 0};
  Vec3 ambient{0.1f, 0.1f, 0.1f};
  // The light the scene has that its file does not give (OBJ's default
  // lights, AFF's default ambient), in words for the trace header and a
  // note; empty when all its light is the file's.
  std::string default_light;
  // Resolution suggested by the scene file (AFF `v` resolution), if any.
  std::optional<int> suggested_width, suggested_height;

  Bounds bounds() const;
};

// Animation range of a scene source: frame N is at time
// start + N * (end - start) / (frames - 1). Static scenes have frames == 1.
struct Animation {
  double start = 0, end = 0;
  std::uint64_t frames = 1;
  double time_of_frame(std::uint64_t frame) const;
};

// Something that yields a Scene at any instant: a parsed file or a built-in
// generator. Parsing happens once; instantiation evaluates animation.
class SceneSource {
 public:
  virtual ~SceneSource() = default;
  virtual const std::string& name() const = 0;
  virtual const Animation& animation() const = 0;
  virtual Scene at_time(double time) const = 0;
  // The scene at `time`, shared: a source whose scene does not change hands
  // over its own instead of a copy (a large scene's triangles once, not twice).
  virtual std::shared_ptr<const Scene> shared_at_time(double time) const {
    return std::make_shared<const Scene>(at_time(time));
  }
  Scene at_frame(std::uint64_t frame) const { return at_time(animation().time_of_frame(frame)); }
  // Content hash of the source (file bytes including includes, or generator
  // name and parameters), for the trace header.
  virtual std::string content_hash() const = 0;
  // What loading noticed but did not reject (e.g. zero-area triangles
  // dropped), for the front end to show; the library prints nothing.
  virtual std::vector<std::string> warnings() const { return {}; }
};

}  // namespace nodetrace::tracer
