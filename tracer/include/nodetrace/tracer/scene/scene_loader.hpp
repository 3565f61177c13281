// Opening scenes: Wavefront OBJ + MTL, BART AFF, and built-in procedural
// scenes, all behind SceneSource.
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "nodetrace/tracer/scene/scene.hpp"

namespace nodetrace::tracer {

// Bad scene input: what() names the file and line and what was expected.
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct BuiltinSceneInfo {
  std::string name;         // e.g. "sphereflake"
  std::string description;  // one line
  int default_size;         // size parameter used when none is given
  std::uint64_t triangles;  // triangle count at default_size
  int min_size = 0, max_size = 0;  // accepted size parameters
  std::uint64_t min_triangles = 0, max_triangles = 0;  // counts at min_size and max_size
};

// The built-in procedural scenes, in listing order.
std::vector<BuiltinSceneInfo> builtin_scenes();
// The scene rendered when the user names none.
std::string default_scene_name();

struct SceneLoadOptions {
  // Size parameter of a built-in scene (0: its default).
  int builtin_size = 0;
  // Threads reading an OBJ file (0: one per core); the scene does not depend on it.
  unsigned threads = 0;
  // false (--default-lights none): a scene gets only the light its file
  // gives: an OBJ file without light no default lights, an AFF file
  // without `am` ambient 0 instead of 0.1.
  bool default_lights = true;
};

// `spec` is a path ending in .obj or .aff, or a built-in scene's name
// (optionally "name:size"). Throws SceneError for bad input, and for a spec
// that is neither a readable file nor a built-in name.
//
// AFF (BART): v b am l f fm p pp tp tpp m s c i xs x k a, `#`/`%` comments.
// `f` maps NFF-style (diffuse = colour * Kd, Ks is both highlight and mirror
// weight); `fm` gives ambient (Material::ambient), diffuse and specular
// colours, the mirror weight being the mean specular. Spheres are 320-triangle
// icospheres, cones 24-sided open frusta. `x name` and `l name ...` follow
// the `k name` keyframes (transl, rot as quaternion squad, scale; KB splines
// with tension, continuity, bias); `k camera` moves the eye (transl) and
// turns the default view (-z, y up) by `rot`. Texture images are never read.
// Keys after a track runs backwards in time (as in Robot1.aff) are ignored.
// AFF without `am`: ambient 0.1 (the default), said in Scene::default_light.
// OBJ: camera nullopt; OBJ has no lights, so two point lights outside the
// bounds (key and fill), said in Scene::default_light and a warning.
// Content hash: FNV-1a 64 of every file read (includes, MTL), or of a
// built-in scene's name, size and generated content.
std::unique_ptr<SceneSource> open_scene(const std::string& spec,
                                        const SceneLoadOptions& options = {});

}  // namespace nodetrace::tracer
