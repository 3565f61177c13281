// run_sampled_sweep: the block-number set filter selects whole sets in every
// cache of the sweep, and window selection is one window per stratum.
#include <gtest/gtest.h>

#include <map>
#include <set>

#include "nodetrace/cachesim/sampling.hpp"
#include "sampling_trace.hpp"
#include "test_support.hpp"

namespace nodetrace::cachesim {
namespace {

std::vector<NodeCacheConfig> configs() {
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

}  // namespace
}  // namespace nodetrace::cachesim
