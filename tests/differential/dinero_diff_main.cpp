// dinero_diff: the differential test at any scale (scripts/dinero-diff.sh).
//   dinero_diff --dinero PATH --cachesim PATH [--cases N] [--seed S] [--keep DIR]
// Compares N valid cases (seeds S, S+1, ...; cases Dinero IV rejects are
// counted apart and must be rejected by cachesim dinero too), keeps every
// differing case in DIR/seed-NNN/, and prints the counts. Exit 1 when any
// case differs.
#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>

#include "dinero_cases.hpp"
#include "test_support.hpp"

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  std::uint64_t cases = 1000, seed = 1;
  fs::path dinero, cachesim, keep = "dinero-diff";
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string option = argv[i];
    const std::string value = argv[i + 1];
    if (option == "--cases") {
      cases = std::stoull(value);
    } else if (option == "--seed") {
      seed = std::stoull(value);
    } else if (option == "--dinero") {
      dinero = value;
    } else if (option == "--cachesim") {
      cachesim = value;
    } else if (option == "--keep") {
      keep = value;
    } else {
      std::fprintf(stderr, "dinero_diff: unknown option %s\n", option.c_str());
      return 2;
    }
  }
  if (dinero.empty() || cachesim.empty() || argc % 2 == 0) {
    std::fprintf(stderr, "usage: dinero_diff --dinero PATH --cachesim PATH [--cases N] [--seed S] [--keep DIR]\n");
    return 2;
  }
  nodetrace::testing::TempDir work;
  const auto start = std::chrono::steady_clock::now();
  std::uint64_t valid = 0, identical = 0, rejected = 0, rejected_alike = 0, hung = 0;
  std::uint64_t s = seed;
  for (; valid < cases; ++s) {
    const auto c = nodetrace::testing::make_dinero_case(s);
    const auto result = nodetrace::testing::compare_dinero_case(c, dinero, cachesim, work.path());
    if (result.dinero_broke) {
      ++hung;
      continue;
    }
    (result.valid ? valid : rejected) += 1;
    (result.valid ? identical : rejected_alike) += result.same ? 1 : 0;
    if (!result.same) {
      const auto folder = keep / fmt::format("seed-{}", s);
      nodetrace::testing::keep_dinero_case(c, result, folder);
      std::fprintf(stderr, "differs: seed %llu (kept in %s)\n", static_cast<unsigned long long>(s),
                   folder.c_str());
    }
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("seeds %llu-%llu: %llu valid configurations compared, %llu identical, %llu differ; "
              "%llu rejected by Dinero IV (%llu also by cachesim dinero); %llu on which Dinero IV crashed "
              "or did not finish in 5 s (not compared); %.1f s\n",
              static_cast<unsigned long long>(seed), static_cast<unsigned long long>(s - 1),
              static_cast<unsigned long long>(valid), static_cast<unsigned long long>(identical),
              static_cast<unsigned long long>(valid - identical), static_cast<unsigned long long>(rejected),
              static_cast<unsigned long long>(rejected_alike), static_cast<unsigned long long>(hung), seconds);
  return identical == valid && rejected_alike == rejected ? 0 : 1;
}
