// `tracer render --integrator path` end to end: its options and their usage
// errors, the header's integrator settings and ray kinds, the trailer's
// count of dropped samples (hostile materials), the float images, a black
// scene's note, and the same bytes for any thread count.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <string>

#include "nodetrace/formats/read/trace_reader.hpp"
#include "test_support.hpp"

namespace nodetrace::tracer {
namespace {

using nodetrace::testing::program;
using nodetrace::testing::read_file;
using nodetrace::testing::run_command;
using nodetrace::testing::TempDir;
using nodetrace::testing::write_file;

std::string tracer_render(const std::string& scene) {
  return program("tracer").string() + " render " + scene + " --width 32 --height 24 -q ";
}

// A diffuse floor and a diffuse block over it: no mirror, no glass.
std::string matte_scene(bool light, const std::string& background) {
  std::string text = "v\nfrom 0 -3 2\nat 0 0 0\nup 0 0 1\nangle 40\nhither 0.1\nresolution 32 24\n";
  text += "b " + background + "\nam 0 0 0\n";
  if (light) text += "l 1 -1 3\n";
  text += "f 0.8 0.7 0.6 1 0 0 0 1\np 4\n-2 -2 0\n2 -2 0\n2 2 0\n-2 2 0\n";
  text += "p 3\n-0.5 0 0.2\n0.5 0 0.2\n0 0.5 1\n";
  return text;
}

nlohmann::json header_of(const std::filesystem::path& trace) {
  return formats::TraceReader::open(trace.string())->header().json;
}

TEST(PathTracerCli, OptionsThatCannotWorkAreUsageErrorsNamingTheOption) {
  const std::string render = tracer_render("mountain:6");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--integrator path --spp 0", "--spp"},
      {"--integrator path --max-bounces -1", "--max-bounces"},
      {"--integrator path --max-bounces 65", "--max-bounces"},
      {"--integrator bidirectional", "--integrator"},
      {"--spp 4", "--spp"},
      {"--max-bounces 2", "--max-bounces"},
      {"--integrator whitted --variance-pfm v.pfm", "--variance-pfm"},
      {"--integrator path --rays primary", "--rays"},
      {"--integrator path --max-depth 4", "--max-depth"},
      {"--path-seed 3", "--path-seed needs --integrator path"},
      {"--integrator path --path-seed -1", "--path-seed"},
      {"--integrator path --path-seed x", "--path-seed"},
  };
  for (const auto& [options, named] : cases) {
    const auto result = run_command(render + options);
    EXPECT_EQ(result.exit_code, 2) << options;
    EXPECT_NE(result.err.find(named), std::string::npos) << options << ": " << result.err;
  }
}

TEST(PathTracerCli, HeaderStatesTheIntegratorAndTheKindsTheSceneCanCast) {
  TempDir dir;
  write_file(dir / "matte.aff", matte_scene(true, "0.2 0.3 0.4"));
  const auto trace = dir / "p.din.zst";
  ASSERT_EQ(run_command(tracer_render((dir / "matte.aff").string()) + "--integrator path --spp 2 --max-bounces 3 -o " +
                        trace.string())
                .exit_code,
            0);
  const nlohmann::json header = header_of(trace);
  const nlohmann::json& path = header.at("render").at("path");
  EXPECT_EQ(path.at("integrator"), "path");
  EXPECT_EQ(path.at("spp"), 2);
  EXPECT_EQ(path.at("max_bounces"), 3);
  EXPECT_EQ(header.at("render").at("max_depth"), 4);
  EXPECT_EQ(header.at("rays").at("cast"), nlohmann::json({"primary", "shadow", "diffuse"}));
  EXPECT_EQ(header.at("rays").at("left_out").at("refraction"), "no material transmits");
  EXPECT_TRUE(header.at("rays").at("left_out").contains("glossy"));
  auto reader = formats::TraceReader::open(trace.string());
  const nlohmann::json& totals = reader->trailer()->totals;
  EXPECT_EQ(totals.at("nonfinite_samples"), 0);
  EXPECT_EQ(totals.at("rays").at("primary"), 32 * 24 * 2);
  EXPECT_GT(totals.at("rays").at("diffuse").get<int>(), 0);
}

// --path-seed: another set of numbers, stated in the header; 0 is a render
// without it, header and records alike.
TEST(PathTracerCli, APathSeedChangesTheNumbersAndTheHeaderSaysSoAndZeroChangesNothing) {
  TempDir dir;
  write_file(dir / "matte.aff", matte_scene(true, "0.2 0.3 0.4"));
  const std::string render = tracer_render((dir / "matte.aff").string()) + "--integrator path --spp 2 ";
  const auto none = dir / "none.din.zst", zero = dir / "zero.din.zst", seven = dir / "seven.din.zst";
  ASSERT_EQ(run_command(render + "-o " + none.string()).exit_code, 0);
  ASSERT_EQ(run_command(render + "--path-seed 0 -o " + zero.string()).exit_code, 0);
  ASSERT_EQ(run_command(render + "--path-seed 7 -o " + seven.string()).exit_code, 0);
  EXPECT_EQ(read_file(zero), read_file(none));
  EXPECT_NE(read_file(seven), read_file(none));
  const nlohmann::json path = header_of(seven).at("render").at("path");
  EXPECT_EQ(path.at("seed"), "--path-seed 7: XORed into the keys above");
  EXPECT_NE(path.at("random").get<std::string>().find("key (0x6e747266, frame >> 32)"), std::string::npos)
      << path.at("random");
  EXPECT_FALSE(header_of(none).at("render").at("path").contains("seed"));
}

TEST(PathTracerCli, WhittedTracesKeepTheirHeaderKeysAndTotals) {
  TempDir dir;
  const auto trace = dir / "w.din.zst";
  ASSERT_EQ(run_command(tracer_render("mountain:6") + "-o " + trace.string()).exit_code, 0);
  const nlohmann::json header = header_of(trace);
  EXPECT_FALSE(header.at("render").contains("path"));
  EXPECT_EQ(header.at("rays").at("cast"), nlohmann::json({"primary", "shadow", "reflection", "refraction"}));
  auto reader = formats::TraceReader::open(trace.string());
  const nlohmann::json& totals = reader->trailer()->totals;
  EXPECT_FALSE(totals.contains("nonfinite_samples"));
  EXPECT_FALSE(totals.at("rays").contains("diffuse"));
}

TEST(PathTracerCli, SameBytesForAnyThreadCountAndFloatImagesOfEveryPixel) {
  TempDir dir;
  const std::string common = tracer_render("mountain:6") + "--integrator path --spp 3 --pfm " +
                             (dir / "mean.pfm").string() + " --variance-pfm " + (dir / "variance.pfm").string() + " ";
  ASSERT_EQ(run_command(common + "--threads 1 -o " + (dir / "a.din.zst").string()).exit_code, 0);
  const std::string mean = read_file(dir / "mean.pfm");
  ASSERT_EQ(run_command(common + "--threads 2 -o " + (dir / "b.din.zst").string()).exit_code, 0);
  EXPECT_TRUE(read_file(dir / "a.din.zst") == read_file(dir / "b.din.zst"));
  EXPECT_TRUE(read_file(dir / "mean.pfm") == mean);
  const std::string pfm_header = "PF\n32 24\n-1.0\n";
  EXPECT_EQ(mean.substr(0, pfm_header.size()), pfm_header);
  EXPECT_EQ(mean.size(), pfm_header.size() + 32u * 24u * 12u);
  const std::string variance = read_file(dir / "variance.pfm");
  EXPECT_EQ(variance.size(), mean.size());
  EXPECT_FALSE(variance.substr(pfm_header.size()) == std::string(32u * 24u * 12u, '\0'));  // 3 samples vary somewhere
}

TEST(PathTracerCli, NoLightAndABlackBackgroundGivesABlackImageAValidTraceAndANote) {
  TempDir dir;
  write_file(dir / "dark.aff", matte_scene(false, "0 0 0"));
  const auto trace = dir / "dark.din.zst";
  const auto result = run_command(program("tracer").string() + " render " + (dir / "dark.aff").string() +
                                  " --width 32 --height 24 --integrator path --pfm " + (dir / "dark.pfm").string() +
                                  " -o " + trace.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.err.find("note: the scene has no light, no ambient light and a black background"),
            std::string::npos)
      << result.err;
  const std::string pfm = read_file(dir / "dark.pfm");
  const std::string pfm_header = "PF\n32 24\n-1.0\n";
  ASSERT_EQ(pfm.size(), pfm_header.size() + 32u * 24u * 12u);
  EXPECT_TRUE(pfm.substr(pfm_header.size()) == std::string(32u * 24u * 12u, '\0'));  // every pixel black
  EXPECT_EQ(run_command(program("tracetool").string() + " verify " + trace.string()).exit_code, 0);
  EXPECT_TRUE(header_of(trace).at("render").contains("notes"));
}

// An AFF file without `am` and lights over a black background: its ambient
// 0.1 is the AFF default, stated in the header; with --default-lights none
// the scene is dark and the dark-scene rule holds (issue 49 item 3).
TEST(PathTracerCli, DefaultAmbientIsInTheHeaderAndNoneMakesADarkSceneBlack) {
  TempDir dir;
  std::string text = matte_scene(false, "0 0 0");
  text.erase(text.find("am 0 0 0\n"), 9);
  write_file(dir / "no_am.aff", text);
  const std::string render = program("tracer").string() + " render " + (dir / "no_am.aff").string() +
                             " --width 32 --height 24 --integrator path --pfm " + (dir / "img.pfm").string() +
                             " -o " + (dir / "t.din.zst").string();
  const auto lit = run_command(render);
  ASSERT_EQ(lit.exit_code, 0) << lit.err;
  EXPECT_NE(header_of(dir / "t.din.zst").at("scene").value("default_light", "").find("ambient light 0.1"),
            std::string::npos);
  const std::string pfm_header = "PF\n32 24\n-1.0\n";
  const std::string black(32u * 24u * 12u, '\0');
  EXPECT_FALSE(read_file(dir / "img.pfm").substr(pfm_header.size()) == black);
  const auto dark = run_command(render + " --default-lights none");
  ASSERT_EQ(dark.exit_code, 0) << dark.err;
  EXPECT_NE(dark.err.find("note: the scene has no light, no ambient light and a black background"), std::string::npos)
      << dark.err;
  EXPECT_FALSE(header_of(dir / "t.din.zst").at("scene").contains("default_light"));
  EXPECT_TRUE(read_file(dir / "img.pfm").substr(pfm_header.size()) == black);
}

TEST(PathTracerCli, HostileMaterialsRenderAndTheTrailerCountsTheDroppedSamples) {
  TempDir dir;
  // Colour 1e38 x Kd 3 overflows, shininess 1e30, glass of index 0.
  std::string text = matte_scene(true, "0.2 0.3 0.4");
  text.replace(text.find("f 0.8 0.7 0.6 1 0 0 0 1"), 23, "f 1e38 1e38 1e38 3 0.5 1e30 0.5 0");
  write_file(dir / "hostile.aff", text);
  const auto trace = dir / "h.din.zst";
  const auto result = run_command(program("tracer").string() + " render " + (dir / "hostile.aff").string() +
                                  " --width 32 --height 24 --integrator path --spp 2 -o " + trace.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.err.find("samples dropped (NaN or infinite throughput or radiance): "), std::string::npos)
      << result.err;
  auto reader = formats::TraceReader::open(trace.string());
  EXPECT_GT(reader->trailer()->totals.at("nonfinite_samples").get<int>(), 0);
  EXPECT_EQ(run_command(program("tracetool").string() + " verify " + trace.string()).exit_code, 0);
}

// Issue 47: --spp abc said "Value abc not in range 1 to 65536".
TEST(PathTracerCli, ASppThatIsNotANumberSaysSo) {
  const auto result = run_command(tracer_render("mountain:6") + "--integrator path --spp abc");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("tracer render: --spp: 'abc' is not a whole number: expected 1 to 65536"),
            std::string::npos)
      << result.err;
}

// Issue 47: tracer info took --integrator path --max-depth 1 and ignored
// it. One rule for both commands, in the same words.
TEST(PathTracerCli, InfoAndRenderRefuseTheOtherIntegratorsDepthAlike) {
  for (const auto& [options, says] : std::vector<std::pair<std::string, std::string>>{
           {"--integrator path --max-depth 1",
            "--max-depth is the Whitted tracer's ray depth: --integrator path takes --max-bounces"},
           {"--max-bounces 2", "--max-bounces needs --integrator path (Whitted: --max-depth)"}}) {
    const auto info = run_command(program("tracer").string() + " info mountain:6 " + options);
    const auto render = run_command(tracer_render("mountain:6") + options);
    EXPECT_EQ(info.exit_code, 2) << options;
    EXPECT_EQ(render.exit_code, 2) << options;
    EXPECT_NE(info.err.find("tracer info: " + says), std::string::npos) << options << ": " << info.err;
    EXPECT_NE(render.err.find("tracer render: " + says), std::string::npos) << options << ": " << render.err;
  }
}

TEST(PathTracerCli, InfoShowsThePathTracersKinds) {
  const auto result = run_command(program("tracer").string() +
                                  " info mountain:6 --integrator path --max-bounces 0 --format json");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const nlohmann::json info = nlohmann::json::parse(result.out);
  EXPECT_EQ(info.at("rays").at("primary"), "cast");
  EXPECT_EQ(info.at("rays").at("diffuse"), "left out: max_bounces is 0");
  EXPECT_EQ(info.at("rays_max_bounces"), 0);
}

}  // namespace
}  // namespace nodetrace::tracer
