// The GGX lobe (Cycles' Glossy BSDF, distribution GGX): its directional
// albedo is at most 1 and matches values computed apart from this code,
// losing the known share at high roughness; the density of its sampled
// directions integrates to 1 and is the density they have; sampling the lobe
// and sampling a light agree on the light it reflects; it is reciprocal.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>

#include "render/ggx.hpp"

namespace nodetrace::tracer::detail {
namespace {

constexpr double kPi = 3.14159265358979323846;

Vec3 unit(float x, float y, float z) { return normalize(Vec3{x, y, z}); }

// A view at angle acos(mu) from the normal +z.
Vec3 view_at(float mu) { return {std::sqrt(1 - mu * mu), 0, mu}; }

// The integral of f over the directions of the sphere (or its upper half,
// z > 0) by the midpoint rule in (theta, phi), n x 2n cells a half.
template <typename F>
double integral(F f, bool upper_only, int n = 500) {
  double sum = 0;
  const int rows = upper_only ? n : 2 * n;
  for (int i = 0; i < rows; ++i) {
    const double theta = (i + 0.5) * kPi / (2 * n);
    const double cell = std::sin(theta) * (kPi / (2 * n)) * (kPi / n);
    for (int j = 0; j < 2 * n; ++j) {
      const double phi = (j + 0.5) * kPi / n;
      const Vec3 d{float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
                   float(std::cos(theta))};
      sum += f(d) * cell;
    }
  }
  return sum;
}

// The mean of f(sampled direction) over an n x n grid of (u1, u2) midpoints.
template <typename F>
double sampled_mean(const GgxLobe& lobe, F f, int n = 512) {
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) sum += f(lobe.sample((i + 0.5f) / float(n), (j + 0.5f) / float(n)));
  }
  return sum / (double(n) * n);
}

// Directional albedo (colour 1): the integral of BRDF x cos over the
// directions above the surface.
double albedo_by_quadrature(float roughness, float mu) {
  const GgxLobe lobe(ggx_alpha(roughness), {0, 0, 1}, view_at(mu));
  return integral([&](const Vec3& l) { return lobe.brdf_cos(l); }, true);
}

// The same from the lobe's samples: each carries G1 of its direction.
double albedo_by_sampling(float roughness, float mu) {
  const GgxLobe lobe(ggx_alpha(roughness), {0, 0, 1}, view_at(mu));
  return sampled_mean(lobe, [&](const Vec3& l) { return l.z > 0 ? double(lobe.masking(l)) : 0.0; });
}

TEST(GgxLobe, AlphaIsTheRoughnessSquaredAboveAFloor) {
  EXPECT_FLOAT_EQ(ggx_alpha(0.3f), 0.09f);
  EXPECT_FLOAT_EQ(ggx_alpha(1.0f), 1.0f);
  EXPECT_EQ(ggx_alpha(0.001f), kMinGgxAlpha);
}

TEST(GgxLobe, WhiteFurnaceReflectsAtMostAllAndLosesTheKnownShareAtHighRoughness) {
  // Albedos from a quadrature of Walter et al.'s formulas written apart
  // from this code (NumPy, 3000 x 6000 cells): single-scattering GGX loses
  // energy, most at high roughness (69% at roughness 1 seen head on).
  struct Known {
    float roughness, mu;
    double albedo;
  };
  for (const Known& k : {Known{1.0f, 1.0f, 0.30685}, Known{1.0f, 0.3f, 0.47208}, Known{0.6f, 1.0f, 0.82453},
                         Known{0.6f, 0.3f, 0.7793}, Known{0.3f, 0.7f, 0.98514}}) {
    const double quadrature = albedo_by_quadrature(k.roughness, k.mu);
    EXPECT_NEAR(quadrature, k.albedo, 5e-4) << k.roughness << " " << k.mu;
    EXPECT_NEAR(albedo_by_sampling(k.roughness, k.mu), k.albedo, 5e-4) << k.roughness << " " << k.mu;
  }
  for (const float roughness : {0.05f, 0.2f, 0.5f, 0.8f, 1.0f}) {
    for (const float mu : {1.0f, 0.6f, 0.2f, 0.05f}) {
      EXPECT_LE(albedo_by_sampling(roughness, mu), 1.0) << roughness << " " << mu;
    }
  }
  EXPECT_GT(1 - albedo_by_sampling(1.0f, 1.0f), 0.6);  // the loss at roughness 1 is real
  EXPECT_GT(albedo_by_sampling(0.05f, 1.0f), 0.999);     // and vanishes for a smooth lobe
}

TEST(GgxLobe, SampledDensityIntegratesToOneAndIsTheDensityOfTheSamples) {
  for (const float roughness : {0.3f, 0.6f, 1.0f}) {
    for (const float mu : {0.9f, 0.5f, 0.15f}) {
      const GgxLobe lobe(ggx_alpha(roughness), {0, 0, 1}, view_at(mu));
      const auto pdf = [&](const Vec3& l) { return double(lobe.pdf(l)); };
      EXPECT_NEAR(integral(pdf, false), 1.0, 1e-3) << roughness << " " << mu;
      // Over the upper half: the share of samples above the surface (the
      // rest, reflected below, the bounce drops).
      const double above = sampled_mean(lobe, [](const Vec3& l) { return l.z > 0 ? 1.0 : 0.0; });
      EXPECT_NEAR(integral(pdf, true), above, 1e-3) << roughness << " " << mu;
      // The samples' moments are the density's: their z and their x.
      EXPECT_NEAR(sampled_mean(lobe, [](const Vec3& l) { return double(l.z); }),
                  integral([&](const Vec3& l) { return l.z * pdf(l); }, false), 1e-3)
          << roughness << " " << mu;
      EXPECT_NEAR(sampled_mean(lobe, [](const Vec3& l) { return double(l.x); }),
                  integral([&](const Vec3& l) { return l.x * pdf(l); }, false), 1e-3)
          << roughness << " " << mu;
    }
  }
}

// A uniform float in [0, 1) from a fixed generator: the same numbers everywhere.
class Uniform {
 public:
  explicit Uniform(std::uint32_t seed) : engine_(seed) {}
  float operator()() { return float(engine_() >> 8) * 0x1p-24f; }

 private:
  std::mt19937 engine_;
};

// Radiance 1 from a square of side `side` at height h centred over (cx, cy),
// facing down, reflected towards the view by the lobe at the origin.
struct SquareLight {
  float cx, cy, h, side;
};

struct Estimate {
  double mean, standard_error;
};

Estimate estimate(const std::vector<double>& values) {
  double sum = 0, sum2 = 0;
  for (const double v : values) sum += v, sum2 += v * v;
  const double n = double(values.size()), mean = sum / n;
  return {mean, std::sqrt((sum2 / n - mean * mean) / (n - 1))};
}

// Sampling the lobe alone: a sample's G1 where its ray meets the square.
Estimate lobe_sampling(const GgxLobe& lobe, const SquareLight& light, int n, Uniform& u) {
  std::vector<double> values;
  for (int i = 0; i < n; ++i) {
    const Vec3 l = lobe.sample(u(), u());
    double value = 0;
    if (l.z > 0) {
      const Vec3 p = l * (light.h / l.z);
      if (std::fabs(p.x - light.cx) <= light.side / 2 && std::fabs(p.y - light.cy) <= light.side / 2) {
        value = lobe.masking(l);
      }
    }
    values.push_back(value);
  }
  return estimate(values);
}

// Sampling the light alone: points uniform on the square, BRDF x cos x the
// geometry term over the density of a point (1 / area).
Estimate light_sampling(const GgxLobe& lobe, const SquareLight& light, int n, Uniform& u) {
  std::vector<double> values;
  for (int i = 0; i < n; ++i) {
    const Vec3 p{light.cx + (u() - 0.5f) * light.side, light.cy + (u() - 0.5f) * light.side, light.h};
    const float distance2 = dot(p, p);
    const Vec3 l = p / std::sqrt(distance2);
    values.push_back(double(lobe.brdf_cos(l)) * l.z * light.side * light.side / distance2);
  }
  return estimate(values);
}

TEST(GgxLobe, SamplingTheLobeAloneAndTheLightAloneAgreeOnALitPoint) {
  Uniform u(49);
  const Vec3 view = unit(-1, 0.2f, 1);
  for (const float roughness : {0.3f, 0.6f, 1.0f}) {
    const GgxLobe lobe(ggx_alpha(roughness), {0, 0, 1}, view);
    // One square over the mirror direction, one off it.
    for (const SquareLight& light : {SquareLight{1.0f, -0.2f, 1.0f, 0.6f}, SquareLight{-0.4f, 0.5f, 0.8f, 0.5f}}) {
      const Estimate by_lobe = lobe_sampling(lobe, light, 200000, u);
      const Estimate by_light = light_sampling(lobe, light, 200000, u);
      ASSERT_GT(by_lobe.mean, 0);
      const double se = std::hypot(by_lobe.standard_error, by_light.standard_error);
      EXPECT_NEAR(by_lobe.mean, by_light.mean, 3 * se)
          << "roughness " << roughness << " square at " << light.cx << "," << light.cy;
    }
  }
}

TEST(GgxLobe, IsReciprocalAndZeroBelowTheSurface) {
  Uniform u(7);
  const Vec3 n = unit(0.3f, -0.5f, 0.8f);
  for (int i = 0; i < 200; ++i) {
    const float roughness = 0.05f + 0.95f * u();
    const Vec3 a = unit(u() - 0.5f, u() - 0.5f, u() - 0.5f), b = unit(u() - 0.5f, u() - 0.5f, u() - 0.5f);
    const float cos_a = dot(a, n), cos_b = dot(b, n);
    const GgxLobe from_a(ggx_alpha(roughness), n, a), from_b(ggx_alpha(roughness), n, b);
    if (cos_a > 0.01f && cos_b > 0.01f) {
      // The BRDF itself, f(a, b) = f(b, a).
      const float f_ab = from_a.brdf_cos(b) / cos_b, f_ba = from_b.brdf_cos(a) / cos_a;
      EXPECT_NEAR(f_ab, f_ba, 1e-4f * std::max(1.0f, f_ab)) << i;
    } else if (cos_a <= 0 || cos_b <= 0) {
      EXPECT_EQ(from_a.brdf_cos(b), 0.0f) << i;  // either below: nothing
      EXPECT_EQ(from_b.brdf_cos(a), 0.0f) << i;
    }
  }
}

}  // namespace
}  // namespace nodetrace::tracer::detail
