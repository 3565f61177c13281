// Row-band sampling (issue 8, tracer side) and frame ranges: the rate and
// range parsers, the band choice, and `tracer render --sample-rows` end to
// end: 1/1 is the full render, a sampled trace holds exactly the full
// trace's records of its bands, each band begins a window, the bytes do not
// depend on the thread count, the seed picks the bands, and bad rates are
// usage errors.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <map>
#include <set>
#include <string>
#include <vector>

#include "nodetrace/base/error.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"
#include "nodetrace/base/sample_rate.hpp"
#include "nodetrace/tracer/render/animation_frame_range.hpp"
#include "nodetrace/tracer/accel/layout.hpp"
#include "nodetrace/tracer/render/render.hpp"
#include "nodetrace/tracer/render/row_sampling.hpp"
#include "test_render_scenes.hpp"
#include "test_support.hpp"

namespace nodetrace::tracer {
namespace {

using nodetrace::testing::program;
using nodetrace::testing::read_file;
using nodetrace::testing::run_command;
using nodetrace::testing::TempDir;

const std::string kScene = "mountain:6";
const std::string kSize = " --width 40 --height 30 ";

std::string render() { return program("tracer").string() + " render " + kScene + kSize + "-q "; }

TEST(SampleRateTest, AcceptsOneOverKOnly) {
  EXPECT_EQ(base::parse_sample_rate("1/1", "--sample-rows"), 1u);
  EXPECT_EQ(base::parse_sample_rate("1/16", "--sample-rows"), 16u);
  for (const char* bad : {"1/0", "3/2", "abc", "0/4", "1/", "/4", "1/4x", "1/-4", "2/4", ""}) {
    try {
      base::parse_sample_rate(bad, "--sample-rows");
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const base::UsageError& e) {
      EXPECT_NE(std::string(e.what()).find("--sample-rows"), std::string::npos) << e.what();
    }
  }
}

TEST(FrameRangeTest, StepTakesEveryStepthFrameUpToTheEnd) {
  EXPECT_EQ(parse_frame_range("0-9").frames(), (std::vector<std::uint64_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}));
  EXPECT_EQ(parse_frame_range("0-9:3").frames(), (std::vector<std::uint64_t>{0, 3, 6, 9}));
  EXPECT_EQ(parse_frame_range("2-10:4").frames(), (std::vector<std::uint64_t>{2, 6, 10}));
  EXPECT_EQ(parse_frame_range("5-7:100").frames(), (std::vector<std::uint64_t>{5}));
  EXPECT_EQ(parse_frame_range("4-4").count(), 1u);
  for (const char* bad : {"3", "3-", "-3", "0-9:0", "0-9:", "5-2", "a-b", "0-9:2:3", "0-9x"}) {
    EXPECT_THROW(parse_frame_range(bad), base::UsageError) << bad;
  }
  EXPECT_NO_THROW(check_frame_range({0, 9, 3}, 10, "s"));
  EXPECT_THROW(check_frame_range({0, 10, 5}, 10, "s"), base::UsageError);
}

TEST(BandChoiceTest, OneBandPerStratumEachWithinItAndFullCoverageAtOne) {
  const auto all = choose_bands({1, 4, 7}, 0, 10, 30);
  ASSERT_EQ(all.size(), 8u);  // ceil(30 / 4)
  for (std::size_t b = 0; b < all.size(); ++b) {
    EXPECT_EQ(all[b].band, b);
    EXPECT_EQ(all[b].first_pixel, b * 40);
  }
  EXPECT_EQ(all.back().end_pixel, 300u);  // the last band is 2 rows

  const RowSampling sampling{4, 2, 11};
  const auto chosen = choose_bands(sampling, 3, 10, 600);  // 300 bands, 75 strata
  EXPECT_EQ(chosen.size(), 75u);
  for (std::size_t s = 0; s < chosen.size(); ++s) {
    EXPECT_EQ(chosen[s].band / 4, s);  // one band in each stratum of 4
    EXPECT_EQ(chosen[s].end_pixel - chosen[s].first_pixel, 20u);
  }
  EXPECT_EQ(choose_bands(sampling, 3, 10, 600)[10].band, chosen[10].band);  // seeded, not random
}

TEST(BandChoiceTest, SeedAndFrameChangeTheBands) {
  const auto bands = [](std::uint64_t seed, std::uint64_t frame) {
    std::vector<std::uint64_t> numbers;
    for (const auto& b : choose_bands({8, 1, seed}, frame, 4, 800)) numbers.push_back(b.band);
    return numbers;
  };
  EXPECT_EQ(bands(1, 0), bands(1, 0));
  EXPECT_NE(bands(1, 0), bands(2, 0));
  EXPECT_NE(bands(1, 0), bands(1, 1));
}

TEST(RenderRunsTest, RunsGetTheFullRendersRecordsAndStartJustBeforeThem) {
  const Scene scene = test_scenes::cornell_box();
  const KdTree tree = KdTree::build(scene.triangles);
  const Layout layout = make_layout(tree, LayoutKind::Dfl);
  RenderOptions options;
  options.width = 32;
  options.height = 24;
  // The full render, one pixel a chunk: where each pixel's records begin.
  options.threads = 1;
  options.pixels_per_chunk = 1;
  std::vector<formats::Record> full;
  std::vector<std::size_t> pixel_start{0};
  const auto collect = [](std::vector<formats::Record>& into) {
    return [&into](std::span<const formats::Record> r) { into.insert(into.end(), r.begin(), r.end()); };
  };
  Renderer(scene, tree, layout, options).render(collect(full), nullptr, [&](double) { pixel_start.push_back(full.size()); });
  ASSERT_EQ(pixel_start.size(), 32u * 24u + 1);

  const std::vector<Renderer::PixelRun> runs{{5, 17}, {40, 41}, {41, 41}, {100, 300}, {700, 768}};
  for (const unsigned threads : {1u, 2u, 3u}) {
    options.threads = threads;
    options.pixels_per_chunk = 7;
    options.records_per_flush = 3;  // hand records on in the middle of pixels too
    std::vector<formats::Record> sampled;
    std::vector<std::size_t> started;
    const RenderStats stats = Renderer(scene, tree, layout, options)
                                  .render_runs(runs, [&](std::size_t run) {
                                    EXPECT_EQ(run, started.size());
                                    started.push_back(sampled.size());
                                  }, collect(sampled), nullptr);
    std::vector<formats::Record> expected;
    std::vector<std::size_t> expected_starts;
    for (const auto& run : runs) {
      expected_starts.push_back(expected.size());
      expected.insert(expected.end(), full.begin() + pixel_start[run.begin], full.begin() + pixel_start[run.end]);
    }
    EXPECT_TRUE(sampled == expected) << threads << " threads";
    EXPECT_EQ(started, expected_starts) << threads << " threads";
    EXPECT_EQ(stats.records, expected.size());
    EXPECT_EQ(stats.rays[0], 12u + 1 + 200 + 68);  // one primary ray a pixel rendered
  }
}

TEST(RenderRunsTest, AFailingSinkStopsTheRenderWithItsErrorForAnyThreadCount) {
  const Scene scene = test_scenes::cornell_box();
  const KdTree tree = KdTree::build(scene.triangles);
  const Layout layout = make_layout(tree, LayoutKind::Dfl);
  RenderOptions options;
  options.width = 64;
  options.height = 48;
  options.pixels_per_chunk = 5;
  for (const std::size_t flush : {std::size_t{2}, std::size_t{1} << 20}) {  // from workers, or the emitting thread
    for (const unsigned threads : {1u, 2u, 4u}) {
      options.threads = threads;
      options.records_per_flush = flush;
      int calls = 0;
      const Renderer renderer(scene, tree, layout, options);
      EXPECT_THROW(renderer.render([&](std::span<const formats::Record>) {
                     if (++calls == 3) throw std::runtime_error("disk full");
                   }, nullptr),
                   std::runtime_error)
          << threads << " threads";
      EXPECT_EQ(calls, 3) << threads << " threads";  // nothing reaches the sink after its error
    }
  }
}

// Records of a trace in order, and for each window its band and records.
struct Windows {
  std::vector<formats::Record> records;
  std::vector<std::uint64_t> bands;
  std::vector<nlohmann::json> extras;
  std::vector<std::vector<formats::Record>> window_records;
  nlohmann::json header;
  std::optional<formats::SamplingInfo> sampling;  // as the formats library reads the header
};

Windows read_windows(const std::filesystem::path& path) {
  Windows w;
  auto reader = formats::TraceReader::open(path.string());
  w.header = reader->header().json;
  w.sampling = reader->header().sampling();
  formats::RecordBatch batch;
  while (reader->next(batch)) {
    if (batch.window) {
      w.bands.push_back(batch.window->window);
      w.extras.push_back(batch.window->extra);
      w.window_records.emplace_back();
    }
    for (const auto& r : batch.records) {
      w.records.push_back(r);
      if (!w.window_records.empty()) w.window_records.back().push_back(r);
    }
  }
  return w;
}

TEST(SampleRowsCliTest, OneInOneIsTheFullRenderByteForByte) {
  TempDir dir;
  ASSERT_EQ(run_command(render() + "-o " + (dir / "full.din").string()).exit_code, 0);
  const auto r = run_command(render() + "--sample-rows 1/1 --band-height 3 -o " + (dir / "all.din").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string full = read_file(dir / "full.din");
  ASSERT_GT(full.size(), 1000u);
  EXPECT_TRUE(full == read_file(dir / "all.din"));  // plain text: no header, no window marker

  ASSERT_EQ(run_command(render() + "-o " + (dir / "full.din.zst").string()).exit_code, 0);
  ASSERT_EQ(run_command(render() + "--sample-rows 1/1 --band-height 3 -o " + (dir / "all.din.zst").string()).exit_code, 0);
  const Windows all = read_windows(dir / "all.din.zst");
  EXPECT_TRUE(all.records == read_windows(dir / "full.din.zst").records);
  EXPECT_EQ(all.bands, (std::vector<std::uint64_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}));
  EXPECT_EQ(all.header["sampling"]["method"], "rows");
  EXPECT_EQ(all.header["sampling"]["every"], 1);
  EXPECT_EQ(all.header["sampling"]["band_height"], 3);
  EXPECT_EQ(all.header["sampling"]["bands"], 10);
  ASSERT_TRUE(all.sampling);
  EXPECT_EQ(all.sampling->method, "rows");
  EXPECT_EQ(all.sampling->band_height, 3u);
  EXPECT_EQ(all.sampling->extra["band_pixels"], 120);
  EXPECT_FALSE(read_windows(dir / "full.din.zst").sampling);  // a full render is not sampled
}

TEST(SampleRowsCliTest, SampledRecordsAreTheFullTracesRecordsOfTheChosenRows) {
  TempDir dir;
  // 1/1 in bands of one row: the full trace cut at every row.
  ASSERT_EQ(run_command(render() + "--sample-rows 1/1 --band-height 1 -o " + (dir / "rows.din.zst").string()).exit_code, 0);
  const Windows rows = read_windows(dir / "rows.din.zst");
  ASSERT_EQ(rows.window_records.size(), 30u);
  const auto r = run_command(render() + "--sample-rows 1/4 --band-height 2 --sample-seed 5 -o " +
                             (dir / "s.din.zst").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Windows sampled = read_windows(dir / "s.din.zst");
  // 15 bands: strata of 4, 4, 4 and 3 (the last may give none).
  ASSERT_EQ(sampled.bands.size(), choose_bands({4, 2, 5}, 0, 40, 30).size());
  ASSERT_GE(sampled.bands.size(), 3u);
  EXPECT_EQ(sampled.header["sampling"]["every"], 4);
  EXPECT_EQ(sampled.header["sampling"]["seed"], 5);
  std::size_t total = 0;
  for (std::size_t w = 0; w < sampled.bands.size(); ++w) {
    const std::uint64_t band = sampled.bands[w];
    EXPECT_EQ(band / 4, w);
    EXPECT_EQ(sampled.extras[w]["rows"], (nlohmann::json{2 * band, 2 * band + 2}));
    std::vector<formats::Record> expected = rows.window_records[2 * band];
    const auto& second = rows.window_records[2 * band + 1];
    expected.insert(expected.end(), second.begin(), second.end());
    EXPECT_TRUE(sampled.window_records[w] == expected) << "band " << band;
    total += expected.size();
  }
  EXPECT_EQ(sampled.records.size(), total);  // nothing outside the windows
}

TEST(SampleRowsCliTest, SameSeedSameBytesForOneAndTwoThreadsAndOtherSeedsOtherBands) {
  TempDir dir;
  const std::string sampled = render() + "--sample-rows 1/3 --band-height 2 ";
  ASSERT_EQ(run_command(sampled + "--sample-seed 7 --threads 1 -o " + (dir / "a1.din.zst").string()).exit_code, 0);
  ASSERT_EQ(run_command(sampled + "--sample-seed 7 --threads 2 -o " + (dir / "a2.din.zst").string()).exit_code, 0);
  const std::string one = read_file(dir / "a1.din.zst");
  ASSERT_GT(one.size(), 1000u);
  EXPECT_TRUE(one == read_file(dir / "a2.din.zst"));

  std::set<std::vector<std::uint64_t>> band_sets;
  for (int seed = 0; seed < 4; ++seed) {
    const auto path = dir / ("s" + std::to_string(seed) + ".din.zst");
    ASSERT_EQ(run_command(sampled + "--sample-seed " + std::to_string(seed) + " -o " + path.string()).exit_code, 0);
    band_sets.insert(read_windows(path).bands);
  }
  EXPECT_EQ(band_sets.size(), 4u);  // 15 bands in strata of 3: four seeds, four different choices
}

TEST(SampleRowsCliTest, BandsOfTiledAndMortonOrdersAreRunsOfTheirSequence) {
  TempDir dir;
  for (const std::string order : {"tiled", "morton"}) {
    const auto full = dir / (order + "-full.din.zst"), all = dir / (order + "-all.din.zst");
    ASSERT_EQ(run_command(render() + "--pixel-order " + order + " -o " + full.string()).exit_code, 0);
    ASSERT_EQ(run_command(render() + "--pixel-order " + order + " --sample-rows 1/1 --band-height 8 -o " +
                          all.string()).exit_code, 0);
    const Windows w = read_windows(all);
    EXPECT_TRUE(w.records == read_windows(full).records) << order;
    ASSERT_EQ(w.extras.size(), 4u) << order;
    EXPECT_EQ(w.extras[1]["pixels"], (nlohmann::json{320, 640})) << order;
    // Tiles of 8 rows: a band of 8 rows is whole rows; a Morton run is not.
    EXPECT_EQ(w.extras[1].contains("rows"), order == "tiled") << order;
  }
}

TEST(SampleRowsCliTest, BadRatesAreUsageErrorsNamingTheOption) {
  TempDir dir;
  const std::string out = " -o " + (dir / "x.din.zst").string();
  for (const std::string rate : {"1/0", "3/2", "abc", "0/4"}) {
    const auto r = run_command(render() + "--sample-rows " + rate + out);
    EXPECT_EQ(r.exit_code, 2) << rate;
    EXPECT_NE(r.err.find("--sample-rows"), std::string::npos) << r.err;
  }
  const auto r = run_command(render() + "--band-height 0 --sample-rows 1/2" + out);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--band-height"), std::string::npos) << r.err;
  EXPECT_EQ(run_command(render() + "--sample-seed 3" + out).exit_code, 2);  // needs --sample-rows
  EXPECT_FALSE(std::filesystem::exists(dir / "x.din.zst"));
}

TEST(FramesCliTest, StepRendersEveryStepthFrame) {
  NODETRACE_SHARED_OR_SKIP(shared);
  const auto robot = shared / "scenes/bart/robots/Robot.aff";
  TempDir dir;
  const auto path = dir / "r.din.zst";
  const auto result = run_command(program("tracer").string() + " render " + robot.string() +
                                  " --width 8 --height 6 --frames 2-7:2 -q -o " + path.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  auto reader = formats::TraceReader::open(path.string());
  EXPECT_EQ(reader->header().json["render"]["frames"], 3);
  EXPECT_EQ(reader->header().json["render"]["frame_step"], 2);
  formats::RecordBatch batch;
  std::vector<std::uint64_t> frames;
  while (reader->next(batch)) {
    if (batch.marker) frames.push_back(batch.marker->frame);
  }
  EXPECT_EQ(frames, (std::vector<std::uint64_t>{2, 4, 6}));
  const auto bad = run_command(program("tracer").string() + " render " + robot.string() + " --frames 0-9:0 -q -o " +
                               (dir / "x.din.zst").string());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--frames"), std::string::npos) << bad.err;
}

TEST(FramesCliTest, RenderAndInfoRejectAMissingFrameAlike) {
  TempDir dir;
  const auto info = run_command(program("tracer").string() + " info " + kScene + " --frame 1");
  const auto rendered = run_command(render() + "--frame 1 -o " + (dir / "x.din.zst").string());
  EXPECT_EQ(info.exit_code, 2);
  EXPECT_EQ(rendered.exit_code, 2);
  const std::string message = "frame 1 is out of range: mountain has 1 frame(s), numbered from 0";
  EXPECT_NE(info.err.find(message), std::string::npos) << info.err;
  EXPECT_NE(rendered.err.find(message), std::string::npos) << rendered.err;
}

}  // namespace
}  // namespace nodetrace::tracer
