// The AFF grammar (BART's NFF extension): view, lights, materials, polygons,
// meshes, spheres, cones, includes, static and animated transform blocks,
// keyframe blocks and the animation line, into a ParsedAff.
#include <algorithm>
#include <array>
#include <map>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include <fmt/format.h>

#include "scene/aff/scene.hpp"
#include "scene/aff/tokenizer.hpp"
#include "nodetrace/tracer/scene/camera_checks.hpp"
#include "nodetrace/tracer/scene/scene_geometry.hpp"
#include "scene/scene_internal.hpp"
#include "scene/triangle_checks.hpp"

namespace nodetrace::tracer::detail::aff {

namespace {

// An index of refraction of 0 is read as 1: BART's own files write 0.0
// there, for opaque and transmissive materials alike (Kitchen has four
// transmissive ones); a negative one is refused where it is read.
float aff_ior(float ior) { return ior > 0 ? ior : 1; }

Vec3 face_normal(const Vec3& a, const Vec3& b, const Vec3& c) {
  return normalized_or(cross(b - a, c - a), {0, 1, 0});
}

// Include budget: nesting depth, files parsed (each inclusion counts, a file
// included twice is parsed twice) and their bytes, so that files including
// each other many times cannot explode; the BART scenes parse a few hundred
// files and some megabytes.
constexpr int kMaxIncludeDepth = 64;
constexpr std::size_t kMaxIncludedFiles = 100'000;
constexpr std::uint64_t kMaxIncludedBytes = std::uint64_t{1} << 30;
// Triangles a scene may make (spheres and cones make many from few bytes):
// about 2 GB of triangles, normals and kd-tree input.
constexpr std::size_t kMaxTriangles = std::size_t{1} << 24;

class AffParser {
 public:
  explicit AffParser(ParsedAff& out) : out_(out) {
    out_.nodes.push_back({});  // root
    node_stack_.push_back(0);
  }

  void parse_file(const std::filesystem::path& path, const Tokenizer* includer, int depth) {
    if (depth > kMaxIncludeDepth) includer->fail("includes nested too deeply (a cycle?)");
    const std::string key = path.lexically_normal().string();
    auto found = files_.find(key);
    if (found == files_.end()) {
      std::error_code error;
      if (!std::filesystem::is_regular_file(path, error)) {
        if (includer) includer->fail("include file '" + path.string() + "' not found");
        throw SceneError(path.string() + ": cannot open scene file");
      }
      std::string bytes = read_scene_file(path);
      hash_ = fnv1a64(bytes, hash_);
      found = files_.emplace(key, std::move(bytes)).first;
    }
    ++files_parsed_;
    bytes_parsed_ += found->second.size();
    if (includer && (files_parsed_ > kMaxIncludedFiles || bytes_parsed_ > kMaxIncludedBytes)) {
      includer->fail(fmt::format("including '{}' exceeds the include budget of {} files or {} bytes parsed "
                                 "(files including others many times?)",
                                 path.string(), kMaxIncludedFiles, kMaxIncludedBytes));
    }
    Tokenizer tokens(found->second, path.string());
    const std::size_t stack_depth = node_stack_.size();
    parse_commands(tokens, path, depth);
    if (depth == 0 && node_stack_.size() != stack_depth) {
      tokens.fail("end of file inside a transform block: expected '}'");
    }
  }

  std::uint64_t hash() const { return hash_; }
  std::size_t triangles() const { return triangles_; }

 private:
  void parse_commands(Tokenizer& tokens, const std::filesystem::path& path, int depth) {
    for (;;) {
      const std::string_view keyword = tokens.next();
      if (keyword.empty()) return;
      if (keyword == "v") parse_view(tokens);
      else if (keyword == "b") out_.background = tokens.non_negative_vec3("background colour");
      else if (keyword == "am") {
        out_.ambient = tokens.non_negative_vec3("ambient light colour");
        out_.ambient_given = true;
      }
      else if (keyword == "l") parse_light(tokens);
      else if (keyword == "f") parse_nff_material(tokens);
      else if (keyword == "fm") parse_extended_material(tokens);
      else if (keyword == "fe") parse_emission(tokens);
      else if (keyword == "fg") parse_ggx(tokens);
      else if (keyword == "p") parse_polygon(tokens, false, false);
      else if (keyword == "pp") parse_polygon(tokens, true, false);
      else if (keyword == "tpp") parse_polygon(tokens, true, true);
      else if (keyword == "tp") parse_polygon(tokens, false, true);
      else if (keyword == "m") parse_mesh(tokens);
      else if (keyword == "s") parse_sphere(tokens);
      else if (keyword == "c") parse_cone(tokens);
      else if (keyword == "i") parse_include(tokens, path, depth);
      else if (keyword == "xs") parse_static_transform(tokens);
      else if (keyword == "x") parse_animated_transform(tokens);
      else if (keyword == "k") parse_keyframes(tokens);
      else if (keyword == "a") parse_animation(tokens);
      else if (keyword == "}") {
        if (node_stack_.size() <= 1) tokens.fail("'}' without a matching transform block");
        node_stack_.pop_back();
      } else {
        tokens.fail("unknown keyword '" + std::string(keyword) +
                    "' (expected one of v b am l f fm fe fg p pp tpp tp m s c i xs x k a })");
      }
    }
  }

  void parse_view(Tokenizer& tokens) {
    const int view_line = tokens.line();
    View view;
    for (;;) {
      const std::string_view field = tokens.peek();
      if (field == "from") tokens.next(), view.from = tokens.vec3("view 'from' coordinate");
      else if (field == "at") tokens.next(), view.at = tokens.vec3("view 'at' coordinate");
      else if (field == "up") tokens.next(), view.up = tokens.vec3("view 'up' coordinate");
      else if (field == "angle") {
        tokens.next();
        view.angle = tokens.real("view angle in degrees");
        if (!(view.angle > 0 && view.angle < 180)) {
          tokens.fail(fmt::format("expected a view angle between 0 and 180 degrees, got {:g}", view.angle));
        }
      }
      else if (field == "hither") tokens.next(), tokens.number("hither distance");
      else if (field == "resolution") {
        tokens.next();
        const auto width = tokens.count("horizontal resolution", 1 << 20);
        const auto height = tokens.count("vertical resolution", 1 << 20);
        if (width == 0 || height == 0) {
          tokens.fail(fmt::format("expected a resolution of at least 1x1, got {}x{}", width, height));
        }
        out_.width = static_cast<int>(width), out_.height = static_cast<int>(height);
      } else {
        break;
      }
    }
    switch (camera_problem(view.from, view.at, view.up)) {
      case CameraProblem::EyeAtLookAt:
        tokens.fail_at(view_line, "view 'from' and 'at' are the same point: the camera looks nowhere");
      case CameraProblem::UpAlongView:
        tokens.fail_at(view_line, "view 'up' is parallel to the view direction: expected a direction across it");
      case CameraProblem::None: break;
    }
    out_.view = view;
  }

  void parse_light(Tokenizer& tokens) {
    LightDefinition light;
    if (!Tokenizer::parse_number(tokens.peek())) light.name = tokens.word("light name");
    light.position = tokens.vec3("light position");
    if (Tokenizer::parse_number(tokens.peek())) light.color = tokens.non_negative_vec3("light colour");
    out_.lights.push_back(std::move(light));
  }

  std::uint32_t add_material(Material material, const Tokenizer& tokens) {
    // Identical definitions (the BART city includes the same colour files
    // hundreds of times) share one entry.
    auto key = std::array<float, 21>{material.diffuse.x, material.diffuse.y, material.diffuse.z,
                                     material.specular.x, material.specular.y, material.specular.z,
                                     material.shininess, material.reflectance, material.transmittance,
                                     material.ior, 0, 0, 0, 0,
                                     material.emission.x, material.emission.y, material.emission.z,
                                     material.ggx_color.x, material.ggx_color.y, material.ggx_color.z,
                                     material.ggx_roughness};
    if (material.ambient) {
      key[10] = 1, key[11] = material.ambient->x, key[12] = material.ambient->y, key[13] = material.ambient->z;
    }
    const auto found = material_index_.find(key);
    if (found != material_index_.end()) return found->second;
    material.name = std::filesystem::path(tokens.file()).filename().string() + ":" + std::to_string(tokens.line());
    out_.materials.push_back(std::move(material));
    const auto index = static_cast<std::uint32_t>(out_.materials.size() - 1);
    material_index_.emplace(key, index);
    return index;
  }

  void parse_nff_material(Tokenizer& tokens) {
    const Vec3 color = tokens.non_negative_vec3("material colour");
    const float kd = tokens.non_negative("diffuse coefficient Kd");
    const float ks = tokens.non_negative("specular coefficient Ks");
    const float shine = tokens.non_negative("Phong exponent Shine");
    const float transmittance = tokens.non_negative("transmittance T");
    const float ior = tokens.non_negative("index of refraction");
    Material material;
    material.diffuse = color * kd;
    material.specular = {ks, ks, ks};
    material.shininess = shine;
    material.reflectance = std::clamp(ks, 0.0f, 1.0f);  // NFF: Ks also weighs the reflected ray
    material.transmittance = std::clamp(transmittance, 0.0f, 1.0f);
    material.ior = aff_ior(ior);
    current_material_ = add_material(std::move(material), tokens);
  }

  void parse_extended_material(Tokenizer& tokens) {
    Material material;
    material.ambient = tokens.non_negative_vec3("ambient colour");
    material.diffuse = tokens.non_negative_vec3("diffuse colour");
    material.specular = tokens.non_negative_vec3("specular colour");
    material.shininess = tokens.non_negative("Phong exponent Shine");
    material.transmittance = std::clamp(tokens.non_negative("transmittance T"), 0.0f, 1.0f);
    const float ior = tokens.non_negative("index of refraction");
    material.ior = aff_ior(ior);
    const Vec3& s = material.specular;
    material.reflectance = std::clamp((s.x + s.y + s.z) / 3, 0.0f, 1.0f);
    current_material_ = add_material(std::move(material), tokens);
  }

  // `fe R G B` (our extension; BART has no emitters): the current material
  // (the last `f` or `fm`) emitting radiance R G B; the next `f` or `fm`
  // emits nothing again.
  void parse_emission(Tokenizer& tokens) {
    if (current_material_ >= out_.materials.size()) tokens.fail("'fe' needs a material before it ('f' or 'fm')");
    Material material = out_.materials[current_material_];
    material.emission = tokens.non_negative_vec3("emitted radiance");
    current_material_ = add_material(std::move(material), tokens);
  }

  // `fg R G B roughness` (our extension): the current material (the last
  // `f` or `fm`, with its `fe`) gaining a GGX lobe (Cycles' Glossy BSDF with
  // distribution GGX) of colour R G B and roughness above 0 and at most 1;
  // its other lobes stay. The next `f` or `fm` has none again.
  void parse_ggx(Tokenizer& tokens) {
    if (current_material_ >= out_.materials.size()) tokens.fail("'fg' needs a material before it ('f' or 'fm')");
    Material material = out_.materials[current_material_];
    material.ggx_color = tokens.non_negative_vec3("GGX colour");
    material.ggx_roughness = tokens.real("GGX roughness");
    if (!(material.ggx_roughness > 0 && material.ggx_roughness <= 1)) {
      tokens.fail(fmt::format("expected a GGX roughness above 0 and at most 1, got {:g}", material.ggx_roughness));
    }
    current_material_ = add_material(std::move(material), tokens);
  }

  Batch& batch() {
    const int node = node_stack_.back();
    if (out_.batches.empty() || out_.batches.back().node != node ||
        out_.batches.back().material != current_material_) {
      out_.batches.push_back({node, current_material_, {}, {}, false});
    }
    return out_.batches.back();
  }

  void add_triangle(const Tokenizer& tokens, Batch& target, const Vec3& a, const Vec3& b, const Vec3& c,
                    const Vec3* normals) {
    if (++triangles_ > kMaxTriangles) {
      tokens.fail(fmt::format("the scene makes more than {} triangles (the limit of a scene)", kMaxTriangles));
    }
    if (!checks_.keep({a, b, c, 0}, [&] { return tokens.file() + ":" + std::to_string(tokens.line()); })) return;
    target.corners.insert(target.corners.end(), {a, b, c});
    if (normals) {
      target.normals.insert(target.normals.end(), {normals[0], normals[1], normals[2]});
      target.has_vertex_normals = true;
    } else {
      const Vec3 n = face_normal(a, b, c);
      target.normals.insert(target.normals.end(), {n, n, n});
    }
  }

  void parse_polygon(Tokenizer& tokens, bool with_normals, bool with_texture) {
    const std::size_t count =
        tokens.count("polygon vertex count", 100'000'000, 3 + (with_normals ? 3 : 0) + (with_texture ? 2 : 0));
    if (count < 3) tokens.fail("expected a polygon vertex count of at least 3, got " + std::to_string(count));
    std::vector<Vec3> points(count), normals(with_normals ? count : 0);
    for (std::size_t i = 0; i < count; ++i) {
      points[i] = tokens.vec3("polygon vertex coordinate");
      if (with_normals) normals[i] = tokens.vec3("polygon vertex normal");
      if (with_texture) tokens.number("texture coordinate"), tokens.number("texture coordinate");
    }
    Batch& target = batch();
    for (std::size_t i = 1; i + 1 < count; ++i) {
      const Vec3 fan_normals[3] = {with_normals ? normals[0] : Vec3{}, with_normals ? normals[i] : Vec3{},
                                   with_normals ? normals[i + 1] : Vec3{}};
      add_triangle(tokens, target, points[0], points[i], points[i + 1], with_normals ? fan_normals : nullptr);
    }
  }

  void parse_mesh(Tokenizer& tokens) {
    std::vector<Vec3> vertices, normals;
    std::size_t texture_coordinates = 0;
    bool have_vertices = false, have_triangles = false;
    for (;;) {
      const std::string_view part = tokens.peek();
      if (part == "vertices") {
        tokens.next();
        const std::size_t count = tokens.count("mesh vertex count", 100'000'000, 3);
        vertices.resize(count);
        for (auto& v : vertices) v = tokens.vec3("mesh vertex coordinate");
        have_vertices = true;
      } else if (part == "normals") {
        tokens.next();
        const std::size_t count = tokens.count("mesh normal count", 100'000'000, 3);
        normals.resize(count);
        for (auto& n : normals) n = tokens.vec3("mesh normal coordinate");
      } else if (part == "texturecoords") {
        tokens.next();
        texture_coordinates = tokens.count("mesh texture coordinate count", 100'000'000, 2);
        tokens.word("texture image name");  // never loaded: a node trace needs no textures
        for (std::size_t i = 0; i < 2 * texture_coordinates; ++i) tokens.number("texture coordinate");
      } else if (part == "triangles" || part == "txtriangles") {
        tokens.next();
        if (!have_vertices) tokens.fail("expected 'vertices' before '" + std::string(part) + "' in mesh");
        const bool textured = part == "txtriangles" || texture_coordinates > 0;
        parse_mesh_triangles(tokens, vertices, normals, textured, texture_coordinates);
        have_triangles = true;
      } else {
        break;
      }
    }
    if (!have_triangles) tokens.fail("expected 'triangles' in mesh");
  }

  void parse_mesh_triangles(Tokenizer& tokens, const std::vector<Vec3>& vertices,
                            const std::vector<Vec3>& normals, bool textured, std::size_t texture_count) {
    const std::size_t count = tokens.count("mesh triangle count", 100'000'000,
                                           3 + (normals.empty() ? 0 : 3) + (textured ? 3 : 0));
    Batch& target = batch();
    target.corners.reserve(target.corners.size() + 3 * count);
    target.normals.reserve(target.normals.size() + 3 * count);
    auto index = [&](std::size_t limit, const char* what) {
      const std::size_t value = tokens.count(what);
      if (value >= limit) {
        tokens.fail(std::string("expected ") + what + " below " + std::to_string(limit) + ", got " +
                    std::to_string(value));
      }
      return value;
    };
    for (std::size_t t = 0; t < count; ++t) {
      const std::size_t a = index(vertices.size(), "vertex index"), b = index(vertices.size(), "vertex index"),
                        c = index(vertices.size(), "vertex index");
      if (!normals.empty()) {
        const std::size_t na = index(normals.size(), "normal index"), nb = index(normals.size(), "normal index"),
                          nc = index(normals.size(), "normal index");
        const Vec3 corner_normals[3] = {normals[na], normals[nb], normals[nc]};
        add_triangle(tokens, target, vertices[a], vertices[b], vertices[c], corner_normals);
      } else {
        add_triangle(tokens, target, vertices[a], vertices[b], vertices[c], nullptr);
      }
      if (textured) {
        for (int k = 0; k < 3; ++k) index(std::max<std::size_t>(texture_count, 1), "texture coordinate index");
      }
    }
  }

  void add_closed_mesh(const Tokenizer& tokens, const std::vector<Triangle>& triangles) {
    Batch& target = batch();
    for (const auto& t : triangles) add_triangle(tokens, target, t.v0, t.v1, t.v2, nullptr);
  }

  void parse_sphere(Tokenizer& tokens) {
    const Vec3 center = tokens.vec3("sphere centre coordinate");
    const float radius = tokens.real("sphere radius");
    if (!(radius > 0)) tokens.fail("expected a positive sphere radius");
    add_closed_mesh(tokens, make_sphere_mesh(center, radius, 2));
  }

  void parse_cone(Tokenizer& tokens) {
    const Vec3 base = tokens.vec3("cone base coordinate");
    const float base_radius = tokens.real("cone base radius");
    const Vec3 apex = tokens.vec3("cone apex coordinate");
    const float apex_radius = tokens.real("cone apex radius");
    add_closed_mesh(tokens, make_cone_mesh(base, std::fabs(base_radius), apex, std::fabs(apex_radius), 24));
  }

  void parse_include(Tokenizer& tokens, const std::filesystem::path& path, int depth) {
    tokens.number("include detail level");
    const std::string name = tokens.word("include file name");
    const std::filesystem::path included = std::filesystem::path(name).is_absolute()
                                               ? std::filesystem::path(name)
                                               : path.parent_path() / name;
    parse_file(included, &tokens, depth + 1);
  }

  void open_block(Tokenizer& tokens, Node node) {
    tokens.expect("{");
    node.parent = node_stack_.back();
    out_.nodes.push_back(std::move(node));
    node_stack_.push_back(static_cast<int>(out_.nodes.size() - 1));
  }

  void parse_static_transform(Tokenizer& tokens) {
    const Vec3 scale = tokens.vec3("scale factor");
    const Vec3 axis = tokens.vec3("rotation axis coordinate");
    const float degrees = tokens.real("rotation angle in degrees");
    const Vec3 translation = tokens.vec3("translation");
    Node node;
    node.local = Affine::translation(translation.x, translation.y, translation.z) *
                 Affine::rotation(from_axis_angle(axis.x, axis.y, axis.z, degrees)) *
                 Affine::scaling(scale.x, scale.y, scale.z);
    open_block(tokens, std::move(node));
  }

  void parse_animated_transform(Tokenizer& tokens) {
    Node node;
    node.animated = true;
    node.name = tokens.word("animated transform name");
    open_block(tokens, std::move(node));
  }

  std::vector<Key> parse_keys(Tokenizer& tokens, int values) {
    const std::size_t count = tokens.count("keyframe count", 100'000'000, 4 + static_cast<std::size_t>(values));
    if (count == 0) tokens.fail("expected at least one keyframe");
    std::vector<Key> keys(count);
    for (auto& key : keys) {
      key.time = tokens.number("keyframe time");
      for (int i = 0; i < values; ++i) key.value[i] = tokens.number("keyframe value");
      key.tension = tokens.number("keyframe tension");
      key.continuity = tokens.number("keyframe continuity");
      key.bias = tokens.number("keyframe bias");
    }
    // Some BART tracks (Robot1.aff's) run backwards in time after their
    // last useful key; a search from the first key never reaches those, so
    // they are dropped.
    const auto backwards = std::adjacent_find(keys.begin(), keys.end(),
                                              [](const Key& a, const Key& b) { return b.time < a.time; });
    if (backwards != keys.end()) keys.erase(backwards + 1, keys.end());
    return keys;
  }

  void parse_keyframes(Tokenizer& tokens) {
    const std::string name = tokens.word("keyframe block name");
    tokens.expect("{");
    AnimatedTransform transform;
    for (;;) {
      const std::string_view part = tokens.next();
      if (part == "}") break;
      if (part == "transl") transform.translation = parse_keys(tokens, 3);
      else if (part == "scale") transform.scale = parse_keys(tokens, 3);
      else if (part == "rot") transform.rotation.emplace(parse_keys(tokens, 4));
      else {
        tokens.fail("expected 'transl', 'rot', 'scale' or '}' in keyframe block, got " + Tokenizer::describe(part));
      }
    }
    out_.transforms.insert_or_assign(name, std::move(transform));
  }

  void parse_animation(Tokenizer& tokens) {
    Animation animation;
    animation.start = tokens.number("animation start time");
    animation.end = tokens.number("animation end time");
    animation.frames = tokens.count("animation frame count", 100'000'000);
    if (animation.frames == 0) tokens.fail("expected an animation frame count of at least 1");
    if (animation.end < animation.start) tokens.fail("expected an animation end time not before its start");
    out_.animation = animation;
  }

  ParsedAff& out_;
  std::vector<int> node_stack_;
  std::uint32_t current_material_ = 0;
  std::map<std::array<float, 21>, std::uint32_t> material_index_;
  std::unordered_map<std::string, std::string> files_;
  std::uint64_t hash_ = kFnvOffset;
  std::size_t files_parsed_ = 0, triangles_ = 0;
  std::uint64_t bytes_parsed_ = 0;
  TriangleChecks checks_;

 public:
  std::vector<std::string> warnings() const {
    if (auto warning = checks_.warning()) return {*warning};
    return {};
  }
};

}  // namespace

ParsedAff parse_aff(const std::filesystem::path& path) {
  ParsedAff parsed;
  parsed.name = path.filename().string();
  AffParser parser(parsed);
  parser.parse_file(path, nullptr, 0);
  if (parser.triangles() == 0) throw SceneError(path.string() + ": no triangles (expected p, pp, tp, tpp, m, s or c)");
  parsed.hash = format_hash(parser.hash());
  parsed.warnings = parser.warnings();
  return parsed;
}

}  // namespace nodetrace::tracer::detail::aff
