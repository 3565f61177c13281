// The path tracer's parts: its random numbers (Random123's Philox, keyed as
// path_random.hpp says, pinned to the bit) and its lobes (the directions
// they draw have the densities they claim; weights of hostile materials are 0).
#include <gtest/gtest.h>

#include <Random123/philox.h>

#include <cmath>
#include <limits>

#include "render/path_lobes.hpp"
#include "render/path_random.hpp"

namespace nodetrace::tracer::detail {
namespace {

TEST(PathRandom, PhiloxGivesRandom123sKnownAnswer) {
  // Random123's known-answer vector for philox4x32_10, counter and key zero.
  const r123::Philox4x32 philox;
  const auto words = philox({{0, 0, 0, 0}}, {{0, 0}});
  EXPECT_EQ(words[0], 0x6627e8d5u);
  EXPECT_EQ(words[1], 0xe169c58du);
  EXPECT_EQ(words[2], 0xbc57ac4cu);
  EXPECT_EQ(words[3], 0x9b00dbd8u);
}

TEST(PathRandom, NumbersArePinnedToTheBitAndDependOnEveryKey) {
  // The same bits on every machine: these decide the rays of every path trace.
  const PathRandom zero(0, 0, 0), other(7, 12345, 3), far_frame(std::uint64_t{1} << 40, 5, 1);
  EXPECT_EQ(zero.uniform(0, 0), 0x1.cf2002p-1f);
  EXPECT_EQ(zero.uniform(0, 5), 0x1.abf508p-2f);
  EXPECT_EQ(other.uniform(2, 1), 0x1.1286p-3f);
  EXPECT_EQ(other.uniform(4, 4), 0x1.9efeb4p-1f);
  EXPECT_EQ(far_frame.uniform(1, 3), 0x1.83ae84p-2f);
  // Each of frame, pixel, sample, bounce and dimension changes the number.
  const float base = PathRandom(3, 4, 5).uniform(6, 2);
  EXPECT_NE(PathRandom(std::uint64_t{3} + (std::uint64_t{1} << 32), 4, 5).uniform(6, 2), base);
  EXPECT_NE(PathRandom(3, 9, 5).uniform(6, 2), base);
  EXPECT_NE(PathRandom(3, 4, 6).uniform(6, 2), base);
  EXPECT_NE(PathRandom(3, 4, 5).uniform(7, 2), base);
  EXPECT_NE(PathRandom(3, 4, 5).uniform(6, 6), base);
  for (std::uint32_t d = 0; d < 16; ++d) {
    const float u = PathRandom(1, 2, 3).uniform(1, d);
    EXPECT_GE(u, 0.0f);
    EXPECT_LT(u, 1.0f);
  }
}

// The mean of f(direction) over an n x n grid of (u1, u2) midpoints.
template <typename Draw, typename F>
double grid_mean(int n, Draw draw, F f) {
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) sum += f(draw((float(i) + 0.5f) / float(n), (float(j) + 0.5f) / float(n)));
  }
  return sum / (double(n) * n);
}

TEST(PathLobes, CosineDirectionsHaveDensityCosineOverPi) {
  const Vec3 n = normalize(Vec3{0.3f, -0.5f, 0.8f});
  const auto draw = [&](float u1, float u2) { return sample_cosine(n, u1, u2); };
  // E[cos] = 2/3 and E[cos^2] = 1/2 under cos(theta) / pi; every direction unit and above.
  EXPECT_NEAR(grid_mean(200, draw, [&](const Vec3& d) { return dot(d, n); }), 2.0 / 3.0, 1e-4);
  EXPECT_NEAR(grid_mean(200, draw, [&](const Vec3& d) { return dot(d, n) * dot(d, n); }), 0.5, 1e-4);
  EXPECT_EQ(grid_mean(50, draw, [&](const Vec3& d) { return std::fabs(length(d) - 1) < 1e-5f && dot(d, n) > 0; }), 1.0);
  // Directions spread around the normal: the mean direction is along it.
  const Vec3 across = normalize(cross(n, Vec3{1, 0, 0}));
  EXPECT_NEAR(grid_mean(200, draw, [&](const Vec3& d) { return dot(d, across); }), 0.0, 1e-4);
}

TEST(PathLobes, PhongDirectionsHaveDensityCosinePowerAboutTheAxis) {
  const Vec3 axis = normalize(Vec3{-0.2f, 0.9f, 0.1f});
  for (const float exponent : {1.0f, 20.0f, 500.0f}) {
    const auto draw = [&](float u1, float u2) { return sample_phong(axis, exponent, u1, u2); };
    // E[cos alpha] = (e + 1) / (e + 2) under (e + 1) / (2 pi) cos^e(alpha).
    EXPECT_NEAR(grid_mean(200, draw, [&](const Vec3& d) { return dot(d, axis); }),
                (exponent + 1.0) / (exponent + 2.0), 1e-4)
        << exponent;
  }
  // An absurd exponent is the mirror direction, not a NaN.
  const Vec3 sharp = sample_phong(axis, 1e30f, 0.3f, 0.7f);
  EXPECT_NEAR(dot(sharp, axis), 1.0f, 1e-6f);
}

TEST(PathLobes, WeightsAreTheMaterialsAndHostileOnesCountAsZero) {
  Material m;
  m.diffuse = {0.3f, 0.6f, 0.9f};
  m.specular = {0.5f, 0.5f, 0.5f};
  m.reflectance = 0.25f;
  m.transmittance = 0.125f;
  LobeWeights w = lobe_weights(m);
  EXPECT_FLOAT_EQ(w.diffuse, 0.6f);
  EXPECT_EQ(w.glossy, 0.0f);  // no shininess: no glossy lobe
  EXPECT_EQ(w.mirror, 0.25f);
  EXPECT_EQ(w.dielectric, 0.125f);
  m.shininess = 10;
  EXPECT_EQ(lobe_weights(m).glossy, 0.5f);
  m.ggx_color = {0.2f, 0.4f, 0.6f};
  EXPECT_EQ(lobe_weights(m).ggx, 0.0f);  // no roughness: no GGX lobe
  m.ggx_roughness = 0.5f;
  EXPECT_FLOAT_EQ(lobe_weights(m).ggx, 0.4f);
  Material ggx_only;
  ggx_only.diffuse = {0, 0, 0};
  ggx_only.ggx_color = {1, 1, 1};
  ggx_only.ggx_roughness = 0.3f;
  EXPECT_TRUE(lobe_weights(ggx_only).lit());  // next-event estimation serves it
  EXPECT_FLOAT_EQ(lobe_weights(ggx_only).total(), 1.0f);
  m.diffuse = {std::numeric_limits<float>::quiet_NaN(), 0, 0};
  m.reflectance = -1;
  w = lobe_weights(m);
  EXPECT_EQ(w.diffuse, 0.0f);
  EXPECT_EQ(w.mirror, 0.0f);
}

}  // namespace
}  // namespace nodetrace::tracer::detail
