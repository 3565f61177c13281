// Scenes built in code for the kd-tree, layout and renderer suites.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "nodetrace/tracer/scene/scene.hpp"

namespace nodetrace::tracer::test_scenes {

// Uniform float in [lo, hi) from a fixed-seed engine (same on every run).
inline float uniform(std::mt19937& engine, float lo, float hi) {
  return lo + (hi - lo) * static_cast<float>(engine() >> 8) / static_cast<float>(1u << 24);
}

inline Scene random_triangles(std::size_t count, std::uint32_t seed, float extent = 10.0f,
                              float size = 1.0f) {
  std::mt19937 engine(seed);
  Scene scene;
  scene.name = "random";
  scene.materials.push_back({});
  for (std::size_t i = 0; i < count; ++i) {
    const Vec3 c{uniform(engine, -extent, extent), uniform(engine, -extent, extent),
                 uniform(engine, -extent, extent)};
    Triangle t;
    t.v0 = c + Vec3{uniform(engine, -size, size), uniform(engine, -size, size), uniform(engine, -size, size)};
    t.v1 = c + Vec3{uniform(engine, -size, size), uniform(engine, -size, size), uniform(engine, -size, size)};
    t.v2 = c + Vec3{uniform(engine, -size, size), uniform(engine, -size, size), uniform(engine, -size, size)};
    scene.triangles.push_back(t);
  }
  return scene;
}

// A closed UV sphere: neighbouring triangles share bit-identical vertices.
inline Scene closed_sphere(int rings, int segments, float radius = 1.0f,
                           Vec3 center = {0.1f, -0.2f, 0.3f}) {
  Scene scene;
  scene.name = "sphere";
  scene.materials.push_back({});
  std::vector<Vec3> grid;
  for (int r = 0; r <= rings; ++r) {
    const double theta = M_PI * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double phi = 2 * M_PI * s / segments;
      Vec3 p{static_cast<float>(std::sin(theta) * std::cos(phi)), static_cast<float>(std::cos(theta)),
             static_cast<float>(std::sin(theta) * std::sin(phi))};
      if (r == 0) p = {0, 1, 0};
      if (r == rings) p = {0, -1, 0};
      grid.push_back(center + p * radius);
    }
  }
  auto at = [&](int r, int s) { return grid[static_cast<std::size_t>(r * segments + (s % segments))]; };
  for (int r = 0; r < rings; ++r) {
    for (int s = 0; s < segments; ++s) {
      if (r != 0) scene.triangles.push_back({at(r, s), at(r, s + 1), at(r + 1, s), 0});
      if (r != rings - 1) scene.triangles.push_back({at(r, s + 1), at(r + 1, s + 1), at(r + 1, s), 0});
    }
  }
  return scene;
}

inline void add_quad(Scene& scene, Vec3 a, Vec3 b, Vec3 c, Vec3 d, std::uint32_t material) {
  scene.triangles.push_back({a, b, c, material});
  scene.triangles.push_back({a, c, d, material});
}

inline void add_box(Scene& scene, Vec3 lo, Vec3 hi, std::uint32_t material) {
  const Vec3 p[8] = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z},
                     {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
  add_quad(scene, p[0], p[3], p[2], p[1], material);
  add_quad(scene, p[4], p[5], p[6], p[7], material);
  add_quad(scene, p[0], p[1], p[5], p[4], material);
  add_quad(scene, p[3], p[7], p[6], p[2], material);
  add_quad(scene, p[0], p[4], p[7], p[3], material);
  add_quad(scene, p[1], p[2], p[6], p[5], material);
}

// Cornell-like box: diffuse walls, a mirror block, a glass block, one light.
inline Scene cornell_box(bool mirror = true, bool glass = true, bool light = true) {
  Scene scene;
  scene.name = "cornell";
  Material white, red, green, shiny, clear;
  red.diffuse = {0.8f, 0.1f, 0.1f};
  green.diffuse = {0.1f, 0.8f, 0.1f};
  shiny.reflectance = 0.8f;
  clear.transmittance = 0.9f;
  clear.ior = 1.5f;
  scene.materials = {white, red, green, shiny, clear};
  add_quad(scene, {0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}, 0);  // floor
  add_quad(scene, {0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}, 0);  // ceiling
  add_quad(scene, {0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}, 1);  // left
  add_quad(scene, {1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}, 2);  // right
  add_quad(scene, {0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}, 0);  // back
  add_box(scene, {0.15f, 0, 0.2f}, {0.45f, 0.6f, 0.5f}, mirror ? 3 : 0);
  add_box(scene, {0.55f, 0, 0.45f}, {0.85f, 0.3f, 0.75f}, glass ? 4 : 0);
  if (light) scene.lights.push_back({{0.5f, 0.95f, 0.6f}, {1, 1, 1}});
  scene.camera = Camera{{0.5f, 0.5f, 2.2f}, {0.5f, 0.5f, 0.0f}, {0, 1, 0}, 40.0f};
  return scene;
}

// The box lit by an emissive quad under its ceiling instead of the point
// light, its white walls glossy too.
inline Scene cornell_box_with_lamp() {
  Scene scene = cornell_box(true, true, false);
  Material lamp;
  lamp.emission = {12, 10, 8};
  scene.materials.push_back(lamp);
  add_quad(scene, {0.35f, 0.99f, 0.4f}, {0.65f, 0.99f, 0.4f}, {0.65f, 0.99f, 0.7f}, {0.35f, 0.99f, 0.7f},
           static_cast<std::uint32_t>(scene.materials.size() - 1));
  scene.materials[0].specular = {0.3f, 0.3f, 0.3f};
  scene.materials[0].shininess = 20;
  return scene;
}

}  // namespace nodetrace::tracer::test_scenes
