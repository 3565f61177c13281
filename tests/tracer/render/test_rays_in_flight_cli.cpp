// `tracer render --rays-in-flight N --units U` end to end: one ray of one
// unit is today's trace byte for byte, several are the same bytes for any
// thread count, and the header says how many units and rays in flight.
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

const std::string kScene = "mountain:6";  // a small built-in scene with mirror and glass

std::string common() {
  return program("tracer").string() + " render " + kScene + " --width 48 --height 36 -q --high-size 1k ";
}

TEST(RaysInFlightCli, OneRayOfOneUnitIsTodaysTraceByteForByte) {
  TempDir dir;
  ASSERT_EQ(run_command(common() + "-o " + (dir / "today.din.zst").string()).exit_code, 0);
  ASSERT_EQ(run_command(common() + "--rays-in-flight 1 --units 1 -o " + (dir / "one.din.zst").string()).exit_code, 0);
  const std::string today = read_file(dir / "today.din.zst");
  ASSERT_GT(today.size(), 1000u);
  EXPECT_TRUE(today == read_file(dir / "one.din.zst"));
}

TEST(RaysInFlightCli, SameBytesForAnyThreadCountAndTheHeaderSaysUnitsAndRays) {
  TempDir dir;
  const std::string options = "--rays-in-flight 16 --units 4 --pixel-order tiled ";
  ASSERT_EQ(run_command(common() + options + "--threads 1 -o " + (dir / "a.din.zst").string()).exit_code, 0);
  ASSERT_EQ(run_command(common() + options + "--threads 3 -o " + (dir / "b.din.zst").string()).exit_code, 0);
  EXPECT_TRUE(read_file(dir / "a.din.zst") == read_file(dir / "b.din.zst"));
  auto reader = formats::TraceReader::open((dir / "a.din.zst").string());
  EXPECT_EQ(reader->units(), 4u);
  const nlohmann::json& render = reader->header().json.at("render");
  EXPECT_EQ(render.at("rays_in_flight"), 16);
  EXPECT_EQ(render.at("units"), 4);
  EXPECT_EQ(render.at("unit_pixels"), 64);
  EXPECT_EQ(render.at("ready_order"), "depth-first");
  formats::RecordBatch batch;
  std::vector<std::uint64_t> per_unit(4);
  while (reader->next(batch)) {
    for (const auto& record : batch.records) ++per_unit.at(formats::unit_index(record.unit));
  }
  for (const auto count : per_unit) EXPECT_GT(count, 0u);
  // The text carries the unit after the level: `0 AAAAAAAA LL U`.
  const std::string text = run_command("zstd -dc " + (dir / "a.din.zst").string() + " | head -1").out;
  EXPECT_EQ(text.size(), 16u) << text;
}

TEST(RaysInFlightCli, OptionsThatCannotWorkAreUsageErrors) {
  TempDir dir;
  const std::string out = " -o " + (dir / "x.din.zst").string();
  EXPECT_EQ(run_command(common() + "--rays-in-flight 0" + out).exit_code, 2);
  EXPECT_EQ(run_command(common() + "--units 257" + out).exit_code, 2);
  EXPECT_EQ(run_command(common() + "--ready-order sideways" + out).exit_code, 2);
  const auto sampled = run_command(common() + "--units 2 --sample-rows 1/4" + out);
  EXPECT_EQ(sampled.exit_code, 2);
  EXPECT_NE(sampled.err.find("--sample-rows"), std::string::npos) << sampled.err;
  const auto binary = run_command(common() + "--units 2 -o " + (dir / "x.bin").string() + " --records binary");
  EXPECT_EQ(binary.exit_code, 2) << binary.err;
}

}  // namespace
}  // namespace nodetrace::tracer
