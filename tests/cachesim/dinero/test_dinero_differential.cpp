// The differential test against the real Dinero IV (d4-7): a fixed range of
// seeded random cases (tests/differential/dinero_cases.hpp: traces in din,
// extended din and binary; one to five levels of caches with every option),
// Dinero IV's whole output compared byte for byte with `cachesim dinero`'s.
// scripts/dinero-diff.sh runs as many more as asked.
#include <gtest/gtest.h>

#include <cstdio>

#include "dinero_cases.hpp"
#include "test_support.hpp"

namespace nodetrace::testing {
namespace {

// The sanitizer build runs cachesim several times slower: fewer cases there.
#if defined(__SANITIZE_ADDRESS__)
constexpr std::uint64_t kValidCases = 150;
#else
constexpr std::uint64_t kValidCases = 1000;
#endif

TEST(DineroDifferential, RandomValidConfigurationsPrintExactlyWhatDineroIVPrints) {
  NODETRACE_DINERO_OR_SKIP(dinero);
  TempDir work;
  std::uint64_t valid = 0, identical = 0, broke = 0;
  // Seeds from 1 until kValidCases valid ones: a fixed range for a fixed generator.
  for (std::uint64_t seed = 1; valid < kValidCases; ++seed) {
    const DineroCase c = make_dinero_case(seed);
    const DineroComparison result = compare_dinero_case(c, dinero, program("cachesim"), work.path());
    if (result.dinero_broke) {  // Dinero IV's own crash or endless loop: nothing to compare, but counted
      ++broke;
      continue;
    }
    if (!result.valid) {
      EXPECT_TRUE(result.same) << "seed " << seed << ": Dinero IV rejects " << joined_arguments(c.args)
                               << " (" << result.dinero_err << ") but cachesim dinero does not";
      continue;
    }
    ++valid;
    if (result.same) {
      ++identical;
      continue;
    }
    ADD_FAILURE() << "seed " << seed << ": " << joined_arguments(c.args)
                  << "\ncachesim dinero exit " << result.cachesim_status << ": " << result.cachesim_err
                  << "(scripts/dinero-diff.sh --cases 1 --seed " << seed << " keeps the case)";
  }
  EXPECT_EQ(identical, valid);
  // A few seeds draw what d4-7 crashes on (sub-blocks of many-set caches);
  // many more would mean the cases or the runs went wrong, not Dinero IV.
  EXPECT_LE(broke, valid / 20) << broke << " cases on which Dinero IV crashed or did not finish";
  std::printf("%llu valid configurations compared, %llu identical; %llu on which Dinero IV crashed or did not "
              "finish (not compared)\n",
              static_cast<unsigned long long>(valid), static_cast<unsigned long long>(identical),
              static_cast<unsigned long long>(broke));
  RecordProperty("valid_configurations", static_cast<int>(valid));
  RecordProperty("dinero_crashes", static_cast<int>(broke));
}

}  // namespace
}  // namespace nodetrace::testing
