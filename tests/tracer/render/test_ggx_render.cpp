// The GGX lobe in the renders: the path tracer's estimate of a GGX plane
// under an emitter is the same with light sampling alone and with light and
// lobe sampling combined by MIS (so the lobe's density is the one its bounce
// rays have); a diffuse and GGX plane in a white furnace reflects the sum of
// the lobes' albedos (so a bounce carries the lobe's BRDF x cos over its
// density); a point light lights a GGX plane the same way in both
// integrators, Whitted casting no rays for the lobe; the header describes
// the lobe only for a scene that has one.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <string>

#include "nodetrace/formats/read/trace_reader.hpp"
#include "nodetrace/tracer/render/render.hpp"
#include "path_render_support.hpp"
#include "render/ggx.hpp"
#include "test_render_scenes.hpp"
#include "test_support.hpp"

namespace nodetrace::tracer {
namespace {

using path_testing::expect_means;
using path_testing::path_options;
using path_testing::render;
using path_testing::Rendered;

Material ggx_material(Vec3 color, float roughness) {
  Material m;
  m.diffuse = {0, 0, 0};
  m.ggx_color = color;
  m.ggx_roughness = roughness;
  return m;
}

// A GGX plane at z = 0 and, at z = 1, a black rectangle emitting downward
// and upward, its reflection in view.
Scene plane_under_emitter() {
  Scene scene;
  scene.ambient = {0, 0, 0};
  Material lamp;
  lamp.diffuse = {0, 0, 0};
  lamp.emission = {4.0f, 3.0f, 2.0f};
  scene.materials = {ggx_material({0.9f, 0.7f, 0.5f}, 0.35f), lamp};
  test_scenes::add_quad(scene, {-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}, 0);
  test_scenes::add_quad(scene, {0.6f, -0.3f, 1}, {1.2f, -0.3f, 1}, {1.2f, 0.3f, 1}, {0.6f, 0.3f, 1}, 1);
  scene.camera = Camera{{-1.5f, 0.1f, 0.9f}, {0.4f, 0, 0}, {0, 0, 1}, 30.0f};
  return scene;
}

TEST(GgxPathTracer, LightSamplingAloneAndMisAgreeOnAGgxPlaneUnderAnEmitter) {
  const Scene scene = plane_under_emitter();
  const int side = 10;
  const std::uint32_t spp = 512;
  // Light sampling alone: no bounce ray, the emitter's estimate weighs 1.
  const Rendered alone = render(scene, path_options(side, spp, 0));
  // Both, weighted by the power heuristic; another frame's random numbers,
  // so the two estimates are independent.
  RenderOptions both_options = path_options(side, spp, 1);
  both_options.animation_frame = 1;
  const Rendered both = render(scene, both_options);
  EXPECT_GT(both.stats.rays[static_cast<int>(RayKind::Glossy)], 0u);
  int pixels_beyond3 = 0, lit = 0;
  double difference_sum = 0, variance_sum = 0;
  for (std::size_t i = 0; i < alone.image.pixels.size(); ++i) {
    bool beyond3 = false;
    for (int c = 0; c < 3; ++c) {
      const double difference = double(alone.image.pixels[i][c]) - double(both.image.pixels[i][c]);
      const double variance = (double(alone.image.variance[i][c]) + double(both.image.variance[i][c])) / spp;
      difference_sum += difference;
      variance_sum += variance;
      lit += alone.image.pixels[i][c] > 0.01f;
      if (variance == 0) {
        EXPECT_EQ(difference, 0) << "pixel " << i << " channel " << c;  // the lamp seen directly
        continue;
      }
      const double z = difference / std::sqrt(variance);
      EXPECT_LT(std::fabs(z), 5) << "pixel " << i << " channel " << c;
      beyond3 = beyond3 || std::fabs(z) > 3;
    }
    pixels_beyond3 += beyond3;
  }
  EXPECT_GT(lit, side * side);  // the reflection covers much of the image
  // Of 100 pixels (whose channels move together: colours in proportion),
  // 0.3 expected beyond 3 by chance; the sum over the image has no bias.
  EXPECT_LE(pixels_beyond3, 2);
  const double z_sum = difference_sum / std::sqrt(variance_sum);
  EXPECT_LT(std::fabs(z_sum), 3) << z_sum;
}

// The lobe's directional albedo (colour 1) by the midpoint rule over the
// upper hemisphere, 400 x 800 cells.
double ggx_albedo(float roughness, const Vec3& view) {
  const detail::GgxLobe lobe(detail::ggx_alpha(roughness), {0, 0, 1}, view);
  const int n = 400;
  const double pi = 3.14159265358979323846;
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const double theta = (i + 0.5) * pi / (2 * n);
    for (int j = 0; j < 2 * n; ++j) {
      const double phi = (j + 0.5) * pi / n;
      const Vec3 l{float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
                   float(std::cos(theta))};
      sum += lobe.brdf_cos(l) * std::sin(theta) * (pi / (2 * n)) * (pi / n);
    }
  }
  return sum;
}

TEST(GgxPathTracer, WhiteFurnaceAPlaneReflectsTheSumOfItsDiffuseAndGgxAlbedosTimesTheSky) {
  // Seen at 60 degrees through a narrow field of view, so every pixel sees
  // the plane at nearly that angle; each bounce escapes to the sky.
  const Vec3 view{0, -0.8660254f, 0.5f};
  for (const float roughness : {1.0f, 0.5f}) {
    Scene scene;
    scene.ambient = {0, 0, 0};
    Material m = ggx_material({0.7f, 0.6f, 0.5f}, roughness);
    m.diffuse = {0.2f, 0.1f, 0.05f};
    scene.materials = {m};
    test_scenes::add_quad(scene, {-100, -100, 0}, {100, -100, 0}, {100, 100, 0}, {-100, 100, 0}, 0);
    scene.background = {1, 1, 1};
    scene.camera = Camera{view * 2.0f, {0, 0, 0}, {0, 0, 1}, 2.0f};
    // Many samples a pixel: a pixel's samples are skewed (a bounce below
    // the surface gives 0), which fattens the tails of its z score at few.
    const std::uint32_t spp = 1024;
    const Rendered r = render(scene, path_options(6, spp, 3));
    const double albedo = ggx_albedo(roughness, view);
    path_testing::expect_means_within_noise(r.image, spp, [&](int, int) { return m.diffuse + m.ggx_color * float(albedo); });
    EXPECT_GT(r.stats.rays[static_cast<int>(RayKind::Glossy)], 0u);
  }
}

// A GGX plane at z = 0 under one point light, black around it.
Scene plane_under_point_light() {
  Scene scene;
  scene.ambient = {0, 0, 0};
  scene.materials = {ggx_material({0.8f, 0.6f, 0.4f}, 0.4f)};
  test_scenes::add_quad(scene, {-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}, 0);
  scene.lights = {PointLight{{0.5f, 0.1f, 1.5f}, {0.9f, 1.0f, 0.8f}}};
  scene.camera = Camera{{-1.5f, 0, 1.2f}, {0.2f, 0, 0}, {0, 0, 1}, 40.0f};
  return scene;
}

// What the light gives along `ray` (hitting the plane): colour x light x pi
// x BRDF x cos (the scene files' convention: a Lambertian Kd gives Kd cos).
Vec3 lit_by_point_light(const Scene& scene, const Ray& ray) {
  const Vec3 point = ray.origin + ray.direction * (-ray.origin.z / ray.direction.z);
  const Material& m = scene.materials[0];
  const detail::GgxLobe lobe(detail::ggx_alpha(m.ggx_roughness), {0, 0, 1}, -normalize(ray.direction));
  const float pi = 3.14159265358979323846f;
  return m.ggx_color * scene.lights[0].color * (pi * lobe.brdf_cos(normalize(scene.lights[0].position - point)));
}

TEST(GgxWhitted, APointLightLightsAGgxPlaneAsThePathTracerDoesAndTheLobeCastsNoRays) {
  const Scene scene = plane_under_point_light();
  const int side = 8;
  RenderOptions whitted;
  whitted.width = whitted.height = side;
  const Rendered w = render(scene, whitted);
  const PinholeCamera camera(*scene.camera, side, side);
  double brightest = 0;
  for (int y = 0; y < side; ++y) {
    for (int x = 0; x < side; ++x) {
      const Vec3 want = lit_by_point_light(scene, camera.primary_ray(x, y));
      const Vec3 got = w.image.pixels[std::size_t(y) * side + x];
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1e-4f * std::max(1.0f, want[c])) << x << "," << y;
      brightest = std::max(brightest, double(want.x));
    }
  }
  EXPECT_GT(brightest, 0.5);  // the highlight is in view
  EXPECT_EQ(w.stats.rays[static_cast<int>(RayKind::Reflection)], 0u);
  // The path tracer: the same light averaged over each pixel (a 32 x 32
  // midpoint rule), within 3 standard errors.
  const std::uint32_t spp = 64;
  const Rendered p = render(scene, path_options(side, spp, 0));
  expect_means(p.image, spp, [&](int x, int y) {
    Vec3 sum;
    for (int i = 0; i < 32; ++i) {
      for (int j = 0; j < 32; ++j) {
        sum += lit_by_point_light(scene, camera.ray_through(float(x) + (i + 0.5f) / 32, float(y) + (j + 0.5f) / 32));
      }
    }
    return sum / (32.0f * 32.0f);
  }, 1e-5f);
}

TEST(GgxHeader, TheHeaderDescribesTheLobeOnlyForASceneThatHasOne) {
  using nodetrace::testing::program;
  using nodetrace::testing::run_command;
  nodetrace::testing::TempDir dir;
  const std::string plane = "v\nfrom 0 -3 2\nat 0 0 0\nup 0 0 1\nangle 40\nhither 0.1\nresolution 8 6\nl 1 -1 3\n"
                            "f 0.8 0.7 0.6 1 0 0 0 1\n";
  const std::string quad = "p 4\n-2 -2 0\n2 -2 0\n2 2 0\n-2 2 0\n";
  nodetrace::testing::write_file(dir / "ggx.aff", plane + "fg 0.5 0.5 0.5 0.3\n" + quad);
  nodetrace::testing::write_file(dir / "matte.aff", plane + quad);
  for (const std::string integrator : {"whitted", "path"}) {
    for (const std::string scene : {"ggx", "matte"}) {
      const auto trace = dir / (scene + "-" + integrator + ".din.zst");
      const auto result = run_command(program("tracer").string() + " render " + (dir / (scene + ".aff")).string() +
                                      " -q --width 8 --height 6 --integrator " + integrator + " -o " + trace.string());
      ASSERT_EQ(result.exit_code, 0) << result.err;
      const nlohmann::json header = formats::TraceReader::open(trace.string())->header().json;
      const nlohmann::json& render_header = header.at("render");
      EXPECT_EQ(render_header.contains("ggx"), scene == "ggx") << scene << " " << integrator;
      if (scene == "ggx") {
        const std::string text = render_header.at("ggx");
        EXPECT_NE(text.find("Cycles' Glossy BSDF with distribution GGX"), std::string::npos) << text;
        EXPECT_NE(text.find(integrator == "path" ? "visible normal" : "point lights only"), std::string::npos) << text;
      }
    }
  }
}

}  // namespace
}  // namespace nodetrace::tracer
