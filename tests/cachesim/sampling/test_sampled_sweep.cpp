// run_sampled_sweep: the block-number set filter selects whole sets in every
// cache of the sweep, and window selection is one window per stratum.
#include <gtest/gtest.h>

#include <map>
#include <set>

#include "nodetrace/cachesim/sampling/sampled_sweep.hpp"
#include "nodetrace/base/error.hpp"
#include "sampling_trace.hpp"
#include "test_support.hpp"

namespace nodetrace::cachesim {
namespace {

std::vector<Configuration> configs() {
  SweepOptions options;
  options.sizes = {256, 1024, 4096};  // 32 to 512 sets of 8 bytes
  options.assocs = {1, 2};
  options.schemes = {Scheme::Single, Scheme::Split};
  options.high_policies = {HighPolicy::Retain, HighPolicy::Cache};
  return expand_configurations(options);
}

SampledResult sampled(const std::filesystem::path& trace, const SamplingOptions& options) {
  auto reader = formats::TraceReader::open(trace.string());
  return run_sampled_sweep(*reader, configs(), "t", options);
}

TEST(SampledSweep, SetResiduesPartitionEveryCachesSetsExactly) {
  // (address / block) mod K == r picks the sets s with s mod K == r in every
  // cache of at least K (power-of-two) sets, whatever its set count, and
  // sets never interact: the K residues' misses add up to the full run's.
  testing::TempDir dir;
  write_walks(dir / "walks.din.zst");
  constexpr std::uint64_t kEvery = 4;
  const SampledResult full = sampled(dir / "walks.din.zst", {});
  std::map<std::uint64_t, SampledResult> by_residue;
  for (std::uint64_t seed = 0; by_residue.size() < kEvery && seed < 200; ++seed) {
    SamplingOptions options;
    options.set_every = kEvery;
    options.seed = seed;
    SampledResult result = sampled(dir / "walks.din.zst", options);
    // Seeds that chose the same residue simulate the same references; the
    // residues are told apart by how many they hold.
    by_residue.emplace(result.rows[0].row.refs, std::move(result));
  }
  ASSERT_EQ(by_residue.size(), kEvery);
  for (std::size_t c = 0; c < full.rows.size(); ++c) {
    std::uint64_t refs = 0;
    std::uint64_t misses = 0;
    std::uint64_t low_misses = 0;
    for (const auto& [key, result] : by_residue) {
      refs += result.rows[c].row.refs;
      misses += result.rows[c].row.misses;
      low_misses += result.rows[c].row.low_misses;
    }
    EXPECT_EQ(refs, full.rows[c].row.refs) << c;
    EXPECT_EQ(misses, full.rows[c].row.misses) << c;
    EXPECT_EQ(low_misses, full.rows[c].row.low_misses) << c;
  }
}

TEST(SampledSweep, OneWindowPerStratumChosenBySeed) {
  for (const std::uint64_t seed : {0u, 1u, 99u}) {
    std::set<std::uint64_t> offsets;
    for (std::uint64_t stratum = 0; stratum < 64; ++stratum) {
      const std::uint64_t chosen = chosen_in_stratum(seed, stratum, 8);
      EXPECT_LT(chosen, 8u);
      EXPECT_EQ(chosen, chosen_in_stratum(seed, stratum, 8));
      offsets.insert(chosen);
    }
    EXPECT_GT(offsets.size(), 4u) << "offsets vary between strata";
  }
  testing::TempDir dir;
  write_walks(dir / "walks.din.zst");
  SamplingOptions options;
  options.window_every = 8;
  options.window_records = 1000;  // 40960 records: 41 windows, the last one short
  const SampledResult result = sampled(dir / "walks.din.zst", options);
  EXPECT_EQ(result.windows, 41u);
  // Strata 0..4 are whole; stratum 5 holds window 40 alone, chosen only at offset 0.
  const std::uint64_t expected = 5 + (chosen_in_stratum(0, 5, 8) == 0 ? 1 : 0);
  EXPECT_EQ(result.windows_simulated, expected);
}

TEST(SampledSweep, SkippedDataFramesAreNotDecompressedAndChangeNoNumber) {
  testing::TempDir dir;
  write_walks(dir / "walks.din.zst");
  SamplingOptions options;
  options.window_every = 4;
  options.window_records = kRecordsPerDataFrame;  // one window, one data frame
  options.seed = 5;
  formats::ReaderOptions skipping;
  skipping.keep_data_frame = data_frame_filter(options);
  auto reader = formats::TraceReader::open((dir / "walks.din.zst").string(), skipping);
  const SampledResult skipped = run_sampled_sweep(*reader, configs(), "t", options);
  // 40 data frames, 10 strata of 4: one frame of each stratum read.
  EXPECT_EQ(reader->data_frames_decompressed(), 10u);
  EXPECT_EQ(reader->data_frames_skipped(), 30u);
  EXPECT_EQ(skipped.windows, 40u);
  EXPECT_EQ(skipped.windows_simulated, 10u);
  const SampledResult read_all = sampled(dir / "walks.din.zst", options);
  ASSERT_EQ(skipped.rows.size(), read_all.rows.size());
  for (std::size_t c = 0; c < skipped.rows.size(); ++c) {
    EXPECT_EQ(skipped.rows[c].row.refs, read_all.rows[c].row.refs);
    EXPECT_EQ(skipped.rows[c].row.misses, read_all.rows[c].row.misses);
    EXPECT_EQ(skipped.rows[c].sampled_fraction, 0.25);
    EXPECT_EQ(skipped.rows[c].estimate.standard_error, read_all.rows[c].estimate.standard_error);
  }
  // Windows of 1.5 data frames: a frame is read when any chosen record is in it.
  options.window_records = kRecordsPerDataFrame * 3 / 2;
  skipping.keep_data_frame = data_frame_filter(options);
  auto partial = formats::TraceReader::open((dir / "walks.din.zst").string(), skipping);
  const SampledResult partly = run_sampled_sweep(*partial, configs(), "t", options);
  const SampledResult partly_all = sampled(dir / "walks.din.zst", options);
  EXPECT_GT(partial->data_frames_skipped(), 0u);
  for (std::size_t c = 0; c < partly.rows.size(); ++c) {
    EXPECT_EQ(partly.rows[c].row.misses, partly_all.rows[c].row.misses);
  }
}

TEST(SampledSweep, DataFrameFilterKeepsEveryFrameWithAChosenRecord) {
  SamplingOptions options;
  options.window_every = 4;
  options.window_records = 100;
  for (std::uint64_t first = 0; first < 2000; first += 37) {
    bool any = false;
    for (std::uint64_t record = first; record < first + 150; ++record) {
      any = any || window_chosen(options, record / 100);
    }
    EXPECT_EQ(records_chosen(options, first, 150), any) << first;
  }
  EXPECT_FALSE(records_chosen(options, 0, 0));
  EXPECT_TRUE(records_chosen(options, 0, 100000));  // many strata
  options.window_every = 0;  // sets only: every frame
  EXPECT_TRUE(data_frame_filter(options)(formats::DataFrameIndexEntry{0, 10, 5000, 1024, 0, 0}));
}

TEST(SampledSweep, RowSampledTraceIsEstimatedFromItsMarkedWindows) {
  testing::TempDir dir;
  // 16 bands, one in 4: 4 windows per frame, 2 frames.
  write_row_sampled(dir / "rows.din.zst", 4, 16, 2);
  const SampledResult result = sampled(dir / "rows.din.zst", {});
  EXPECT_EQ(result.windows, 32u);
  EXPECT_EQ(result.windows_simulated, 8u);
  for (const SampledRow& row : result.rows) {
    EXPECT_EQ(row.row.refs, 8u * 600u);  // every record of the trace
    EXPECT_EQ(row.sampled_fraction, 0.25);
    EXPECT_EQ(row.estimate.value,
              static_cast<double>(row.row.misses) / static_cast<double>(row.row.fetches));
    ASSERT_TRUE(row.estimate.standard_error);
    EXPECT_GT(*row.estimate.standard_error, 0.0);
  }
  EXPECT_EQ(result.gains.size(), 12u);  // one per split configuration: 3 sizes x 2 assocs x 2 high policies
  // Every band present (1/1): exact, zero error.
  write_row_sampled(dir / "all.din.zst", 1, 16, 1);
  const SampledResult all = sampled(dir / "all.din.zst", {});
  EXPECT_EQ(all.windows, 16u);
  EXPECT_EQ(all.windows_simulated, 16u);
  for (const SampledRow& row : all.rows) {
    EXPECT_EQ(row.sampled_fraction, 1.0);
    EXPECT_EQ(*row.estimate.standard_error, 0.0);
  }
}

TEST(SampledSweep, RowSampledTraceRefusesWindowSampling) {
  testing::TempDir dir;
  write_row_sampled(dir / "rows.din.zst", 4, 16, 1);
  SamplingOptions options;
  options.window_every = 2;
  EXPECT_THROW(sampled(dir / "rows.din.zst", options), base::UsageError);
}

}  // namespace
}  // namespace nodetrace::cachesim
