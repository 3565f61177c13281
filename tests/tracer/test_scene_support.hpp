// Helpers for the scene loader suites.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>

#include "nodetrace/tracer/scene/scene.hpp"
#include "nodetrace/tracer/scene/scene_loader.hpp"

namespace nodetrace::tracer::testing {

// FNV-1a 64 over the raw bytes of every vertex coordinate and material index,
// in triangle order: changes if any generated triangle changes by one bit.
inline std::uint64_t vertex_data_hash(const Scene& scene) {
  std::uint64_t hash = 0xcbf29ce484222325ULL;
  auto feed = [&](const void* data, std::size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) {
      hash ^= bytes[i];
      hash *= 0x100000001b3ULL;
    }
  };
  for (const auto& t : scene.triangles) {
    for (const Vec3* v : {&t.v0, &t.v1, &t.v2}) {
      const float xyz[3] = {v->x, v->y, v->z};
      feed(xyz, sizeof xyz);
    }
    feed(&t.material, sizeof t.material);
  }
  return hash;
}

inline void expect_near(const Vec3& actual, const Vec3& expected, float tolerance = 1e-4f) {
  EXPECT_NEAR(actual.x, expected.x, tolerance);
  EXPECT_NEAR(actual.y, expected.y, tolerance);
  EXPECT_NEAR(actual.z, expected.z, tolerance);
}

// The message of the SceneError that `load` throws, or "" when none.
template <typename Load>
std::string scene_error_of(Load&& load) {
  try {
    load();
  } catch (const SceneError& error) {
    return error.what();
  }
  return "";
}

}  // namespace nodetrace::tracer::testing
