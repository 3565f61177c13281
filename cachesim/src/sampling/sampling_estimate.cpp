// The ratio estimator of SAMPLING.md: residuals e_i = m_i - R f_i, the
// linearised variance (1 - n/N) / (n fbar^2) * S^2 with S^2 the residuals'
// spread (random or successive differences), and for the gain the same over
// the difference of the two standardised residuals.
#include "nodetrace/cachesim/sampling/sampling_estimate.hpp"

#include <array>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace nodetrace::cachesim {

double student_t975(std::uint64_t degrees) {
  static constexpr std::array<double, 30> kFirst30{
      12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
      2.201,  2.179, 2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086,
      2.080,  2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042};
  if (degrees == 0) throw std::invalid_argument("student_t975: no degrees of freedom");
  if (degrees <= 30) return kFirst30[degrees - 1];
  if (degrees < 40) return 2.042;
  if (degrees < 60) return 2.021;
  if (degrees < 120) return 2.000;
  if (degrees == 120) return 1.980;
  return 1.960;
}

namespace {

struct Totals {
  double fetches = 0;
  double misses = 0;
  double ratio() const { return fetches > 0 ? misses / fetches : 0.0; }
};

Totals totals(const std::vector<SampleUnitCounts>& units) {
  Totals sum;
  for (const SampleUnitCounts& unit : units) {
    sum.fetches += static_cast<double>(unit.fetches);
    sum.misses += static_cast<double>(unit.misses);
  }
  return sum;
}

// The spread S^2 of the residuals z_i under `design` (n >= 2).
double spread(const std::vector<double>& residuals, SampleDesign design) {
  const std::size_t n = residuals.size();
  double sum_squares = 0;
  if (design == SampleDesign::Stratified) {
    for (std::size_t i = 1; i < n; ++i) {
      const double step = residuals[i] - residuals[i - 1];
      sum_squares += step * step;
    }
    return sum_squares / (2.0 * static_cast<double>(n - 1));
  }
  for (const double z : residuals) sum_squares += z * z;
  return sum_squares / static_cast<double>(n - 1);
}

// The interval from per-unit linearised residuals z_i (already divided by
// the mean fetches per unit): var = (1 - f) / n * S^2.
Estimate with_error(double value, const std::vector<double>& residuals,
                    std::uint64_t population_units, SampleDesign design) {
  Estimate estimate;
  estimate.value = value;
  const std::uint64_t n = residuals.size();
  if (population_units < n) throw std::invalid_argument("sampled more units than there are");
  double variance = 0;
  if (n == population_units) {
    variance = 0;  // the whole population: no sampling error
  } else if (n < 2) {
    return estimate;
  } else {
    const double kept = static_cast<double>(n) / static_cast<double>(population_units);
    variance = (1.0 - kept) / static_cast<double>(n) * spread(residuals, design);
  }
  const double error = std::sqrt(variance);
  const double half = n >= 2 ? student_t975(n - 1) * error : 0.0;
  estimate.standard_error = error;
  estimate.low95 = value - half;
  estimate.high95 = value + half;
  return estimate;
}

// e_i / fbar for each unit: the ratio's linearised residuals.
std::vector<double> standardised_residuals(const std::vector<SampleUnitCounts>& units,
                                           const Totals& sum) {
  std::vector<double> residuals;
  residuals.reserve(units.size());
  const double mean_fetches = units.empty() ? 0 : sum.fetches / static_cast<double>(units.size());
  const double ratio = sum.ratio();
  for (const SampleUnitCounts& unit : units) {
    const double residual =
        static_cast<double>(unit.misses) - ratio * static_cast<double>(unit.fetches);
    residuals.push_back(mean_fetches > 0 ? residual / mean_fetches : 0.0);
  }
  return residuals;
}

}  // namespace

Estimate ratio_estimate(const std::vector<SampleUnitCounts>& units, std::uint64_t population_units,
                        SampleDesign design) {
  const Totals sum = totals(units);
  // No fetch sampled: the ratio has no value, so no error and no interval.
  if (sum.fetches == 0) return {};
  return with_error(sum.ratio(), standardised_residuals(units, sum), population_units, design);
}

Estimate gain_estimate(const std::vector<SampleUnitCounts>& single, const std::vector<SampleUnitCounts>& split,
                       std::uint64_t population_units, SampleDesign design) {
  if (single.size() != split.size()) throw std::invalid_argument("gain: unequal unit counts");
  const Totals single_sum = totals(single);
  const Totals split_sum = totals(split);
  if (single_sum.fetches == 0 || split_sum.fetches == 0) return {};
  std::vector<double> residuals = standardised_residuals(single, single_sum);
  const std::vector<double> split_residuals = standardised_residuals(split, split_sum);
  for (std::size_t i = 0; i < residuals.size(); ++i) residuals[i] -= split_residuals[i];
  return with_error(single_sum.ratio() - split_sum.ratio(), residuals, population_units, design);
}

}  // namespace nodetrace::cachesim
