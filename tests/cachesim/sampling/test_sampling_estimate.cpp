// The sampling estimator on synthetic units whose answers are computed by
// hand in the comments.
#include <gtest/gtest.h>

#include "nodetrace/cachesim/sampling/sampling_estimate.hpp"

namespace nodetrace::cachesim {
namespace {

// (fetches, misses) of three sampled windows out of 8.
const std::vector<SampleUnitCounts> kSingle{{100, 10}, {100, 20}, {200, 30}};
const std::vector<SampleUnitCounts> kSplit{{100, 5}, {100, 10}, {200, 25}};

TEST(SamplingEstimate, RatioEstimateOfThreeWindowsOutOfEightMatchesTheHandComputation) {
  // R = 60 / 400 = 0.15; residuals m - R f = -5, 5, 0; fbar = 400 / 3;
  // var = (1 - 3/8) / (3 fbar^2) * (25 + 25 + 0) / 2 = 0.00029296875.
  const Estimate estimate = ratio_estimate(kSingle, 8);
  EXPECT_DOUBLE_EQ(estimate.value, 0.15);
  ASSERT_TRUE(estimate.standard_error);
  EXPECT_NEAR(*estimate.standard_error * *estimate.standard_error, 0.00029296875, 1e-15);
  // t(0.975, 2) = 4.303.
  const double half = 4.303 * *estimate.standard_error;
  EXPECT_NEAR(*estimate.low95, 0.15 - half, 1e-12);
  EXPECT_NEAR(*estimate.high95, 0.15 + half, 1e-12);
  EXPECT_NEAR(*estimate.low95, 0.076349, 1e-6);
}

TEST(SamplingEstimate, GainIsSingleMinusSplitWithThePairedResidualsVariance) {
  // R(split) = 40 / 400 = 0.1, residuals -5, 0, 5; G = 0.05; differences of
  // the residuals 0, 5, -5: the same variance as the single ratio above.
  const Estimate gain = gain_estimate(kSingle, kSplit, 8);
  EXPECT_NEAR(gain.value, 0.05, 1e-15);
  ASSERT_TRUE(gain.standard_error);
  EXPECT_NEAR(*gain.standard_error * *gain.standard_error, 0.00029296875, 1e-15);
  EXPECT_NEAR(*gain.high95 - *gain.low95, 2 * 4.303 * *gain.standard_error, 1e-12);
}

TEST(SamplingEstimate, StratifiedDesignUsesSuccessiveDifferences) {
  // Residuals -5, 5, 0 in order: differences 10, -5; S^2 = 125 / (2 * 2);
  // var = (1 - 3/8) / (3 fbar^2) * 31.25 = 0.0003662109375.
  const Estimate estimate = ratio_estimate(kSingle, 8, SampleDesign::Stratified);
  EXPECT_DOUBLE_EQ(estimate.value, 0.15);
  EXPECT_NEAR(*estimate.standard_error * *estimate.standard_error, 0.0003662109375, 1e-15);
  // The gain's residual differences 0, 5, -5: steps 5, -10, the same S^2.
  const Estimate gain = gain_estimate(kSingle, kSplit, 8, SampleDesign::Stratified);
  EXPECT_NEAR(*gain.standard_error * *gain.standard_error, 0.0003662109375, 1e-15);
  // A steady trend (residuals -10, 0, 10) is no spread between neighbours
  // beyond the trend's steps: S^2 = (100 + 100) / 4 = 50, against 100 at random.
  const std::vector<SampleUnitCounts> trend{{100, 0}, {100, 10}, {100, 20}};
  const double stratified = *ratio_estimate(trend, 30, SampleDesign::Stratified).standard_error;
  const double random = *ratio_estimate(trend, 30, SampleDesign::Random).standard_error;
  EXPECT_NEAR(stratified * stratified * 2, random * random, 1e-15);
}

TEST(SamplingEstimate, FullCoverageGivesTheTotalsRatioWithZeroError) {
  const Estimate estimate = ratio_estimate(kSingle, 3);
  EXPECT_EQ(estimate.value, 60.0 / 400.0);
  EXPECT_EQ(*estimate.standard_error, 0.0);
  EXPECT_EQ(*estimate.low95, estimate.value);
  EXPECT_EQ(*estimate.high95, estimate.value);
  const Estimate gain = gain_estimate(kSingle, kSplit, 3);
  EXPECT_EQ(*gain.standard_error, 0.0);
  EXPECT_EQ(*gain.low95, gain.value);
  // One unit that is the whole population: exact too.
  const Estimate one = ratio_estimate({{50, 5}}, 1);
  EXPECT_EQ(one.value, 0.1);
  EXPECT_EQ(*one.standard_error, 0.0);
}

TEST(SamplingEstimate, OneUnitOfSeveralHasNoErrorEstimate) {
  const Estimate estimate = ratio_estimate({{50, 5}}, 4);
  EXPECT_EQ(estimate.value, 0.1);
  EXPECT_FALSE(estimate.standard_error);
  EXPECT_FALSE(estimate.low95);
  EXPECT_FALSE(estimate.high95);
}

// Units with no fetch at all (a sample of copy-backs, of an empty trace):
// the ratio has no value, so neither a standard error nor an interval, even
// where the sample is the whole population (issue 52, item 3).
TEST(SamplingEstimate, ASampleWithoutFetchesHasNoErrorAndNoInterval) {
  for (const std::uint64_t population : {2u, 4u}) {
    const Estimate estimate = ratio_estimate({{0, 0}, {0, 0}}, population);
    EXPECT_FALSE(estimate.standard_error) << population;
    EXPECT_FALSE(estimate.low95) << population;
    EXPECT_FALSE(estimate.high95) << population;
    const Estimate gain = gain_estimate({{10, 1}, {20, 2}}, {{0, 0}, {0, 0}}, population);
    EXPECT_FALSE(gain.standard_error) << population;
    EXPECT_FALSE(gain.low95) << population;
  }
}

TEST(SamplingEstimate, UnitsThatAllHaveTheSameRatioHaveZeroError) {
  const Estimate estimate = ratio_estimate({{100, 10}, {300, 30}, {50, 5}}, 30);
  EXPECT_DOUBLE_EQ(estimate.value, 0.1);
  EXPECT_NEAR(*estimate.standard_error, 0.0, 1e-15);
}

TEST(SamplingEstimate, StudentTableAtItsEdges) {
  EXPECT_EQ(student_t975(1), 12.706);
  EXPECT_EQ(student_t975(30), 2.042);
  EXPECT_EQ(student_t975(45), 2.021);  // the next lower entry, 40
  EXPECT_EQ(student_t975(1000), 1.960);
  EXPECT_THROW(student_t975(0), std::invalid_argument);
}

TEST(SamplingEstimate, MoreSampledThanPopulationIsRejected) {
  EXPECT_THROW(ratio_estimate(kSingle, 2), std::invalid_argument);
  EXPECT_THROW(gain_estimate(kSingle, {{1, 1}}, 8), std::invalid_argument);
}

}  // namespace
}  // namespace nodetrace::cachesim
