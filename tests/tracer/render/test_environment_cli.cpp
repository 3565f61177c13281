// `tracer render --environment FILE.pfm` end to end: bad maps are bad data
// (exit 1, the file and the pixel named, no trace left behind), the option
// without --integrator path is a usage error, the header states the map as
// the user named it, and the bytes do not depend on the map's byte order or
// the thread count.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "nodetrace/formats/read/trace_reader.hpp"
#include "pfm_bytes.hpp"
#include "test_support.hpp"

namespace nodetrace::tracer {
namespace {

using nodetrace::testing::program;
using nodetrace::testing::read_file;
using nodetrace::testing::run_command;
using nodetrace::testing::shell_quoted;
using nodetrace::testing::TempDir;
using nodetrace::testing::write_file;
using test_files::pfm_bytes;

// In `dir`, so the map's name is as typed: a render of a matte AFF scene.
std::string render_in(const TempDir& dir, const std::string& options) {
  return "cd " + shell_quoted(dir.path()) + " && " + program("tracer").string() +
         " render scene.aff --width 16 --height 12 -q " + options;
}

void write_scene(const TempDir& dir) {
  write_file(dir / "scene.aff",
             "v\nfrom 0 -3 2\nat 0 0 0\nup 0 0 1\nangle 40\nhither 0.1\nresolution 16 12\nb 0 0 0\nam 0 0 0\n"
             "f 0.8 0.7 0.6 1 0 0 0 1\np 4\n-2 -2 0\n2 -2 0\n2 2 0\n-2 2 0\np 3\n-0.5 0 0.2\n0.5 0 0.2\n0 0.5 1\n");
}

Vec3 sky(int x, int y) { return {0.1f * float(x), 0.2f * float(y), 0.5f}; }

TEST(EnvironmentCli, BadMapsAreBadDataNamingTheFileAndPixelWithNoTraceLeft) {
  TempDir dir;
  write_scene(dir);
  const std::string good = pfm_bytes(8, 4, sky);
  const auto with_value = [&](float value) {
    return pfm_bytes(8, 4, [&](int x, int y) { return x == 3 && y == 2 ? Vec3{0.5f, value, 0.5f} : sky(x, y); });
  };
  struct Case {
    std::string what, bytes, named;
  };
  const std::vector<Case> cases = {
      {"truncated", good.substr(0, good.size() - 7), "truncated"},
      {"not a PFM", "P3\n1 1\n255\n0 0 0\n", "not a PFM"},
      {"greyscale", "Pf\n1 1\n-1.0\n" + std::string(4, '\0'), "greyscale"},
      {"zero width", "PF\n0 4\n-1.0\n", "0x4"},
      {"zero height", "PF\n8 0\n-1.0\n", "8x0"},
      {"NaN", with_value(std::nanf("")), "column 3, row 2"},
      {"infinite", with_value(INFINITY), "column 3, row 2"},
      {"negative", with_value(-1.0f), "column 3, row 2"},
  };
  for (const Case& c : cases) {
    write_file(dir / "map.pfm", c.bytes);
    const auto result = run_command(render_in(dir, "--integrator path --environment map.pfm -o t.din.zst"));
    EXPECT_EQ(result.exit_code, 1) << c.what << ": " << result.err;
    EXPECT_NE(result.err.find("map.pfm"), std::string::npos) << c.what << ": " << result.err;
    EXPECT_NE(result.err.find(c.named), std::string::npos) << c.what << ": " << result.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "t.din.zst")) << c.what;
    EXPECT_TRUE(nodetrace::testing::temporaries(dir.path()).empty()) << c.what;
  }
  const auto missing = run_command(render_in(dir, "--integrator path --environment none.pfm -o t.din.zst"));
  EXPECT_EQ(missing.exit_code, 1) << missing.err;
  EXPECT_NE(missing.err.find("none.pfm"), std::string::npos) << missing.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "t.din.zst"));
}

TEST(EnvironmentCli, WithoutThePathTracerItIsAUsageError) {
  TempDir dir;
  write_scene(dir);
  write_file(dir / "map.pfm", pfm_bytes(8, 4, sky));
  const auto result = run_command(render_in(dir, "--environment map.pfm -o t.din.zst"));
  EXPECT_EQ(result.exit_code, 2) << result.err;
  EXPECT_NE(result.err.find("--environment"), std::string::npos) << result.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "t.din.zst"));
}

nlohmann::json header_of(const std::filesystem::path& trace) {
  return formats::TraceReader::open(trace.string())->header().json;
}

TEST(EnvironmentCli, HeaderStatesTheMapAsNamedAndTheBytesIgnoreByteOrderAndThreads) {
  TempDir little, big;
  for (const TempDir* dir : {&little, &big}) {
    write_scene(*dir);
    write_file(*dir / "sky.pfm", pfm_bytes(8, 4, sky, dir == &little));
  }
  const std::string options = "--integrator path --spp 3 --environment sky.pfm --pfm mean.pfm ";
  ASSERT_EQ(run_command(render_in(little, options + "-o t.din.zst --threads 1")).exit_code, 0);
  ASSERT_EQ(run_command(render_in(big, options + "-o t.din.zst --threads 2")).exit_code, 0);
  EXPECT_EQ(read_file(little / "t.din.zst"), read_file(big / "t.din.zst"));
  EXPECT_EQ(read_file(little / "mean.pfm"), read_file(big / "mean.pfm"));
  const nlohmann::json header = header_of(little / "t.din.zst");
  const nlohmann::json& map = header.at("render").at("path").at("environment");
  EXPECT_EQ(map.at("file"), "sky.pfm");
  EXPECT_EQ(map.at("width"), 8);
  EXPECT_EQ(map.at("height"), 4);
  EXPECT_EQ(map.at("checksum").get<std::string>().rfind("fnv1a64:", 0), 0u);
  EXPECT_NE(map.at("mapping").get<std::string>().find("atan2(y, x)"), std::string::npos);
  // The map lights a scene without lights: shadow rays are cast, and no
  // note says the image is black.
  EXPECT_EQ(header.at("rays").at("cast"), nlohmann::json({"primary", "shadow", "diffuse"}));
  EXPECT_FALSE(header.at("render").contains("notes"));
  // Another map, another checksum.
  write_file(little / "sky.pfm", pfm_bytes(8, 4, [](int x, int y) { return sky(x, y) * 2.0f; }));
  ASSERT_EQ(run_command(render_in(little, options + "-o u.din.zst")).exit_code, 0);
  EXPECT_NE(header_of(little / "u.din.zst").at("render").at("path").at("environment").at("checksum"),
            map.at("checksum"));
  // Without --environment the header has no such key.
  ASSERT_EQ(run_command(render_in(little, "--integrator path -o v.din.zst")).exit_code, 0);
  const nlohmann::json dark = header_of(little / "v.din.zst");
  EXPECT_FALSE(dark.at("render").at("path").contains("environment"));
  EXPECT_TRUE(dark.at("render").contains("notes"));
  // A black map in place of a bright background lights nothing: the note says so.
  std::string bright = read_file(little / "scene.aff");
  bright.replace(bright.find("b 0 0 0"), 7, "b 1 1 1");
  write_file(little / "bright.aff", bright);
  write_file(little / "black.pfm", pfm_bytes(2, 1, [](int, int) { return Vec3{}; }));
  const auto black = run_command("cd " + shell_quoted(little.path()) + " && " + program("tracer").string() +
                                 " render bright.aff --width 8 --height 6 --integrator path --environment black.pfm");
  ASSERT_EQ(black.exit_code, 0) << black.err;
  EXPECT_NE(black.err.find("a black environment map"), std::string::npos) << black.err;
}

TEST(EnvironmentCli, InfoShowsTheRayKindsTheMapMakesTheRenderCast) {
  TempDir dir;
  write_scene(dir);
  write_file(dir / "sky.pfm", pfm_bytes(8, 4, sky));
  const std::string info = "cd " + shell_quoted(dir.path()) + " && " + program("tracer").string() +
                           " info scene.aff --format json --integrator path";
  const auto dark = run_command(info);
  ASSERT_EQ(dark.exit_code, 0) << dark.err;
  EXPECT_EQ(nlohmann::json::parse(dark.out).at("rays").at("shadow"), "left out: scene has no light");
  const auto lit = run_command(info + " --environment sky.pfm");
  ASSERT_EQ(lit.exit_code, 0) << lit.err;
  EXPECT_EQ(nlohmann::json::parse(lit.out).at("rays").at("shadow"), "cast");
  EXPECT_EQ(nlohmann::json::parse(lit.out).at("rays_environment"), "sky.pfm");
  write_file(dir / "bad.pfm", "PF\n0 4\n-1.0\n");
  EXPECT_EQ(run_command(info + " --environment bad.pfm").exit_code, 1);
  const std::string whitted = "cd " + shell_quoted(dir.path()) + " && " + program("tracer").string() +
                              " info scene.aff --environment sky.pfm";
  EXPECT_EQ(run_command(whitted).exit_code, 2);
}

}  // namespace
}  // namespace nodetrace::tracer
