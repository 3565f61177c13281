// Environment maps (issue 49 item 2), the parts below the renderer: the
// equirectangular orientation is Blender's (the six axis directions land in
// the pixels Blender's Environment Texture picks), the PFM reader takes both
// byte orders and stores the file's first row at the bottom, the map refuses
// values that are not finite and non-negative, naming the pixel, and its
// distribution's density is a density that sample() and look_up() agree on.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "nodetrace/base/error.hpp"
#include "nodetrace/tracer/render/environment_map.hpp"
#include "nodetrace/tracer/render/equirectangular.hpp"
#include "nodetrace/tracer/render/image.hpp"
#include "pfm_bytes.hpp"
#include "test_support.hpp"

namespace nodetrace::tracer {
namespace {

using nodetrace::testing::TempDir;
using test_files::pfm_bytes;
using nodetrace::testing::write_file;

constexpr double kPi = 3.14159265358979323846;

// Blender's lookup as Cycles writes it (kernel/camera/projection.h,
// direction_to_equirectangular with range (-2 pi, pi, -pi, pi)), in a form
// other than ours, and its "Closest" pixel: floor(u W), floor(v H) from the
// bottom.
struct BlenderPixel {
  int column, row_from_bottom;
};
BlenderPixel blender_closest(const Vec3& d, int width, int height) {
  const double length = std::sqrt(double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z);
  const double u = (std::atan2(double(d.y), double(d.x)) - kPi) / (-2 * kPi);
  const double v = (std::acos(double(d.z) / length) - kPi) / (-kPi);
  return {static_cast<int>(std::floor(u * width)) % width, static_cast<int>(std::floor(v * height))};
}

TEST(Equirectangular, TheSixAxisDirectionsLandInBlendersPixels) {
  // 8 x 5: the equator is the middle of row 2, no axis on a pixel edge but -X (u = 0).
  constexpr std::uint32_t kWidth = 8, kHeight = 5;
  struct Case {
    Vec3 direction;
    double u, v;
    std::uint32_t column, row_from_top;
  };
  const Case cases[] = {
      {{1, 0, 0}, 0.5, 0.5, 4, 2},    // +X: the middle column
      {{0, 1, 0}, 0.25, 0.5, 2, 2},   // +Y: a quarter from the left
      {{-1, 0, 0}, 0.0, 0.5, 0, 2},   // -X: the seam, left edge
      {{0, -1, 0}, 0.75, 0.5, 6, 2},  // -Y: three quarters
      {{0, 0, 1}, 0.5, 1.0, 4, 0},    // +Z: the top row
      {{0, 0, -1}, 0.5, 0.0, 4, 4},   // -Z: the bottom row
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(::testing::Message() << c.direction.x << " " << c.direction.y << " " << c.direction.z);
    const EquirectangularUv uv = equirectangular_uv(c.direction * 3.0f);  // any length
    EXPECT_NEAR(uv.u, c.u, 1e-12);
    EXPECT_NEAR(uv.v, c.v, 1e-12);
    const MapPixel p = equirectangular_pixel(c.direction, kWidth, kHeight);
    EXPECT_EQ(p.column, c.column);
    EXPECT_EQ(p.row, c.row_from_top);
    // The inverse gives the direction back.
    const Vec3 back = equirectangular_direction(c.u, c.v);
    EXPECT_NEAR(back.x, c.direction.x, 1e-6);
    EXPECT_NEAR(back.y, c.direction.y, 1e-6);
    EXPECT_NEAR(back.z, c.direction.z, 1e-6);
    // Blender's pixel, but at the poles: v = 1 is one past Blender's top row
    // there (its repeat extension wraps a direction exactly +Z to the bottom
    // row); we keep the pole's own row.
    const BlenderPixel blender = blender_closest(c.direction, kWidth, kHeight);
    if (c.direction.z <= 0) {
      EXPECT_EQ(int(p.column), blender.column);
      EXPECT_EQ(int(kHeight - 1 - p.row), blender.row_from_bottom);
    }
  }
}

TEST(Equirectangular, EveryPixelCentreMapsBackToItsPixelAsBlenderPicksIt) {
  constexpr std::uint32_t kWidth = 12, kHeight = 7;
  for (std::uint32_t row = 0; row < kHeight; ++row) {
    for (std::uint32_t column = 0; column < kWidth; ++column) {
      const double u = (column + 0.5) / kWidth, v = (kHeight - 1 - row + 0.5) / kHeight;
      const Vec3 d = equirectangular_direction(u, v);
      const MapPixel p = equirectangular_pixel(d, kWidth, kHeight);
      EXPECT_EQ(p.column, column);
      EXPECT_EQ(p.row, row);
      const BlenderPixel blender = blender_closest(d, kWidth, kHeight);
      EXPECT_EQ(blender.column, int(column));
      EXPECT_EQ(blender.row_from_bottom, int(kHeight - 1 - row));
    }
  }
}

Vec3 index_colour(int x, int y) { return {float(x), float(y), float(x + 100 * y)}; }

TEST(EnvironmentMapFile, BothByteOrdersReadTheSamePixelsTheFilesFirstRowAtTheBottom) {
  TempDir dir;
  write_file(dir / "le.pfm", pfm_bytes(5, 3, index_colour, true));
  write_file(dir / "be.pfm", pfm_bytes(5, 3, index_colour, false));
  const Image le = read_pfm((dir / "le.pfm").string(), 100), be = read_pfm((dir / "be.pfm").string(), 100);
  ASSERT_EQ(le.width, 5);
  ASSERT_EQ(le.height, 3);
  for (int y = 0; y < 3; ++y) {
    for (int x = 0; x < 5; ++x) EXPECT_EQ(le.pixels[std::size_t(y) * 5 + x], index_colour(x, y));
  }
  EXPECT_TRUE(le.pixels == be.pixels);
  // The file's first stored row is the picture's bottom one.
  const std::string bytes = pfm_bytes(5, 3, index_colour);
  float first;
  std::memcpy(&first, bytes.data() + bytes.find("-1.0\n") + 5 + 4, 4);  // pixel (0, bottom)'s green
  EXPECT_EQ(first, 2.0f);
  // And the map looks up pixels in that order: +Z is the top row, -Z the bottom.
  const EnvironmentMap le_map("le.pfm", le), be_map("be.pfm", be);
  EXPECT_EQ(le_map.look_up({0, 0, 1}).radiance, index_colour(2, 0));
  EXPECT_EQ(le_map.look_up({0, 0, -1}).radiance, index_colour(2, 2));
  EXPECT_EQ(le_map.look_up({0, 1, 0.01f}).radiance, index_colour(1, 1));  // u = 0.25: column 1 of 5
  EXPECT_EQ(le_map.checksum(), be_map.checksum());
  EXPECT_EQ(le_map.checksum().rfind("fnv1a64:", 0), 0u);
}

TEST(EnvironmentMapFile, MalformedFilesAreFormatErrorsNamingTheFile) {
  TempDir dir;
  const std::string good = pfm_bytes(4, 2, index_colour);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"truncated", good.substr(0, good.size() - 5)},
      {"longer", good + "x"},
      {"not a PFM", "P6\n4 2\n255\n" + std::string(24, '\0')},
      {"greyscale", "Pf\n1 1\n-1.0\n" + std::string(4, '\0')},
      {"zero width", "PF\n0 2\n-1.0\n"},
      {"zero height", "PF\n2 0\n-1.0\n"},
      {"no scale", "PF\n1 1\n"},
      {"zero scale", "PF\n1 1\n0\n" + std::string(12, '\0')},
      {"empty", ""},
  };
  for (const auto& [what, bytes] : cases) {
    const auto file = dir / "m.pfm";
    write_file(file, bytes);
    try {
      read_pfm(file.string(), 1000);
      ADD_FAILURE() << what << ": read";
    } catch (const base::FormatError& error) {
      EXPECT_NE(std::string(error.what()).find(file.string()), std::string::npos) << what << ": " << error.what();
    }
  }
  write_file(dir / "big.pfm", pfm_bytes(4, 2, index_colour));
  EXPECT_THROW(read_pfm((dir / "big.pfm").string(), 7), base::FormatError);  // 8 pixels, at most 7
  EXPECT_THROW(read_pfm((dir / "missing.pfm").string(), 1000), base::IoError);
}

TEST(EnvironmentMapValues, NanInfiniteOrNegativeRadianceIsRefusedNamingThePixel) {
  for (const float bad : {std::nanf(""), INFINITY, -INFINITY, -0.5f}) {
    Image picture;
    picture.width = 3;
    picture.height = 2;
    picture.pixels.assign(6, Vec3{0.5f, 0.5f, 0.5f});
    picture.pixels[1 * 3 + 2].y = bad;
    try {
      const EnvironmentMap map("sky.pfm", picture);
      ADD_FAILURE() << bad << ": accepted";
    } catch (const base::FormatError& error) {
      const std::string what = error.what();
      EXPECT_NE(what.find("sky.pfm"), std::string::npos) << what;
      EXPECT_NE(what.find("column 2, row 1"), std::string::npos) << what;
      EXPECT_NE(what.find("green"), std::string::npos) << what;
    }
  }
  Image empty;
  EXPECT_THROW(EnvironmentMap("empty.pfm", empty), base::FormatError);
}

// A map of `width` x `height` with one bright pixel on a dim sky.
Image peaky_picture(int width, int height, int bright_x, int bright_y) {
  Image picture;
  picture.width = width;
  picture.height = height;
  picture.pixels.assign(std::size_t(width) * height, Vec3{0.01f, 0.02f, 0.03f});
  picture.pixels[std::size_t(bright_y) * width + bright_x] = {50, 40, 30};
  return picture;
}

// The solid angle of pixel (x, y from the top) of a width x height map.
double pixel_solid_angle(int width, int height, int y) {
  return 2 * kPi / width * (std::cos(kPi * y / height) - std::cos(kPi * (y + 1) / height));
}

TEST(EnvironmentMapDistribution, DensityIntegratesToOneAndSamplesAgreeWithLookUps) {
  for (const EnvironmentSampling sampling : {EnvironmentSampling::Importance, EnvironmentSampling::Uniform}) {
    const EnvironmentMap map("peaky", peaky_picture(16, 8, 5, 2), sampling);
    ASSERT_TRUE(map.lights());
    double integral = 0;
    for (int y = 0; y < 8; ++y) {
      for (int x = 0; x < 16; ++x) {
        const Vec3 centre = equirectangular_direction((x + 0.5) / 16, (8 - 1 - y + 0.5) / 8);
        integral += map.look_up(centre).pdf * pixel_solid_angle(16, 8, y);
      }
    }
    EXPECT_NEAR(integral, 1.0, 1e-5);
    int bright = 0;
    for (int i = 0; i < 4096; ++i) {
      const float u = (float(i % 64) + 0.5f) / 64, v = (float(i / 64) + 0.5f) / 64;
      const EnvironmentMap::Sample s = map.sample(u, v);
      EXPECT_NEAR(length(s.direction), 1.0f, 1e-6f);
      const EnvironmentMap::LookUp seen = map.look_up(s.direction);
      EXPECT_EQ(seen.radiance, s.radiance) << u << " " << v;
      EXPECT_FLOAT_EQ(seen.pdf, s.pdf);
      bright += s.radiance.x == 50;
      if (sampling == EnvironmentSampling::Uniform) {
        EXPECT_FLOAT_EQ(s.pdf, float(1 / (4 * kPi)));
      }
    }
    // The bright pixel holds nearly all the luminance x solid angle; it is
    // 1 of 128 pixels of the sphere.
    if (sampling == EnvironmentSampling::Importance) {
      EXPECT_GT(bright, 4096 * 95 / 100);
    } else {
      EXPECT_LT(bright, 4096 * 3 / 100);
    }
  }
}

TEST(EnvironmentMapDistribution, ABlackMapLightsNothing) {
  Image picture;
  picture.width = 4;
  picture.height = 2;
  picture.pixels.assign(8, Vec3{});
  const EnvironmentMap map("black", picture);
  EXPECT_FALSE(map.lights());
  EXPECT_EQ(map.look_up({1, 0, 0}).pdf, 0.0f);
}

}  // namespace
}  // namespace nodetrace::tracer
