// The error of a sampled simulation (cachesim/SAMPLING.md): the ratio
// estimator over sampled units (windows of the trace, or groups of cache
// sets), its standard error and a 95% interval, for one configuration's miss
// ratio and for the split gain (single minus split miss ratio).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

namespace nodetrace::cachesim {

// What one sampled unit contributed to one configuration.
struct SampleUnitCounts {
  std::uint64_t fetches = 0;
  std::uint64_t misses = 0;
};

struct Estimate {
  double value = 0;  // the estimate (a miss ratio, or a gain), as a fraction
  // Unknown (nullopt) when fewer than two units were sampled and the sample
  // is not the whole population: one unit says nothing of the spread.
  std::optional<double> standard_error;
  std::optional<double> low95;
  std::optional<double> high95;
};

// How the units were chosen, which decides the variance formula.
enum class SampleDesign : std::uint8_t {
  // A simple random sample of units (set groups): sum e_i^2 / (n - 1).
  Random,
  // One unit per stratum of consecutive units, in trace order (windows):
  // successive differences, sum (e_i - e_{i-1})^2 / (2 (n - 1)), which
  // follows a trend along the trace instead of counting it as spread.
  Stratified,
};

// Student's t quantile t(0.975, degrees) from a table; between tabulated
// degrees of freedom the next lower entry (a little wider interval); 1.96
// beyond 120. degrees >= 1.
double student_t975(std::uint64_t degrees);

// The miss ratio R = sum misses / sum fetches of the sampled units, with
// population_units units in all (population_units >= units.size()).
Estimate ratio_estimate(const std::vector<SampleUnitCounts>& units, std::uint64_t population_units,
                        SampleDesign design = SampleDesign::Random);

// The gain G = R(single) - R(split) over the same sampled units (one entry
// per unit in both vectors, in the same order).
Estimate gain_estimate(const std::vector<SampleUnitCounts>& single, const std::vector<SampleUnitCounts>& split,
                       std::uint64_t population_units, SampleDesign design = SampleDesign::Random);

}  // namespace nodetrace::cachesim
