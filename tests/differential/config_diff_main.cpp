// config_diff: the differential test of `cachesim run` over every path
// (scripts/config-diff.sh).
//   config_diff --cachesim PATH [--dinero PATH] [--tracer PATH] [--cases N] [--seed S] [--renders R]
//               [--keep DIR] [--jobs J] [--avoid LETTERS] [--python DIR] [--python-every N]
// --python: also run every Nth case's list (seed divisible by N; default 10)
// through the nodetrace Python module built in DIR, whose rows must equal
// cachesim run's.
// --renders: R render checks first (check_render_case; tracer beside cachesim unless --tracer).
// --avoid: the open defects (config_cases.hpp) whose triggers to leave out, e.g. abcd.
// Without --dinero, Dinero IV is found as the tests find it ($DINEROIV, PATH,
// build/dinero). Checks N cases (seeds S, S+1, ...; config_cases.hpp says how), keeps every
// differing case in DIR/seed-NNN/, and prints the counts. Exit 1 when any
// case differs.
#include <fmt/format.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <map>
#include <mutex>
#include <string>
#include <thread>

#include "config_cases.hpp"
#include "test_support.hpp"

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  using namespace nodetrace::testing;
  std::uint64_t cases = 1000, seed = 1, renders = 0;
  unsigned jobs = 2;
  Programs programs;
  ConfigCaseOptions options;
  fs::path keep = "config-diff";
  for (int i = 1; i < argc; ++i) {
    const std::string option = argv[i];
    if (i + 1 >= argc) {
      std::fprintf(stderr, "config_diff: %s needs a value\n", option.c_str());
      return 2;
    }
    const std::string value = argv[++i];
    if (option == "--cases") {
      cases = std::stoull(value);
    } else if (option == "--seed") {
      seed = std::stoull(value);
    } else if (option == "--jobs") {
      jobs = std::max(1u, static_cast<unsigned>(std::stoul(value)));
    } else if (option == "--cachesim") {
      programs.cachesim = value;
    } else if (option == "--dinero") {
      programs.dinero = fs::path(value);
    } else if (option == "--renders") {
      renders = std::stoull(value);
    } else if (option == "--tracer") {
      programs.tracer = fs::path(value);
    } else if (option == "--avoid") {
      options.avoid = value;
    } else if (option == "--python") {
      programs.python_module = fs::path(value);
    } else if (option == "--python-every") {
      programs.python_every = std::max<std::uint64_t>(1, std::stoull(value));
    } else if (option == "--keep") {
      keep = value;
    } else {
      std::fprintf(stderr, "config_diff: unknown option %s\n", option.c_str());
      return 2;
    }
  }
  if (programs.cachesim.empty()) {
    std::fprintf(stderr,
                 "usage: config_diff --cachesim PATH [--dinero PATH] [--tracer PATH] [--cases N] [--seed S] [--renders R] "
                 "[--keep DIR] [--jobs J] "
                 "[--avoid LETTERS] [--python DIR] [--python-every N]\n");
    return 2;
  }
  if (!programs.dinero) programs.dinero = real_dinero();
  if (!programs.dinero) {
    if (shared_data_required()) {
      std::fprintf(stderr, "config_diff: Dinero IV not found (scripts/build-dinero.sh builds it from ../shared)\n");
      return 1;
    }
    std::fprintf(stderr, "config_diff: Dinero IV not found: the comparisons with it are skipped\n");
  }
  if (!programs.tracer) programs.tracer = programs.cachesim.parent_path() / "tracer";
  const auto start = std::chrono::steady_clock::now();
  std::atomic<std::uint64_t> next{0}, render_rows{0}, sampled_sets{0}, sampled_windows{0}, curve_points{0}, python_rows{0}, rows{0}, dinero_rows{0}, properties{0}, configs{0};
  std::mutex mutex;
  std::map<std::uint64_t, std::vector<std::string>> differing;  // seed -> known-defect triggers
  std::uint64_t differing_renders = 0;
  auto worker = [&] {
    TempDir work;
    for (std::uint64_t n = next++; n < renders + cases; n = next++) {
      ConfigCaseResult result;
      if (n < renders) {  // the render checks first
        const std::uint64_t s = seed + n;
        try {
          result = check_render_case(s, programs, work.path());
        } catch (const std::exception& error) {
          result.differences.push_back(fmt::format("the harness failed: {}", error.what()));
        }
        properties += result.properties;
        render_rows += result.rows;
        if (result.differences.empty()) continue;
        const auto folder = keep / fmt::format("render-{}", s);
        keep_runs(result, folder, fmt::format("render check, seed {}\n", s));
        const std::lock_guard lock(mutex);
        ++differing_renders;
        std::fprintf(stderr, "differs: render seed %llu (kept in %s): %s\n", static_cast<unsigned long long>(s),
                     folder.c_str(), result.differences[0].c_str());
        continue;
      }
      const std::uint64_t s = seed + n - renders;
      const ConfigCase c = make_config_case(s, options);
      try {
        result = check_config_case(c, programs, work.path());
      } catch (const std::exception& error) {
        result.differences.push_back(fmt::format("the harness failed: {}", error.what()));
      }
      rows += result.rows;
      dinero_rows += result.dinero_rows;
      properties += result.properties;
      sampled_sets += result.sampled_sets;
      sampled_windows += result.sampled_windows;
      curve_points += result.curve_points;
      python_rows += result.python_rows;
      configs += c.configs.size();
      if (result.differences.empty()) continue;
      const auto folder = keep / fmt::format("seed-{}", s);
      keep_config_case(c, result, folder);
      const std::lock_guard lock(mutex);
      differing[s] = c.known_defect_triggers;
      std::fprintf(stderr, "differs: seed %llu (kept in %s): %s%s\n", static_cast<unsigned long long>(s),
                   folder.c_str(), result.differences[0].c_str(),
                   result.differences.size() > 1 ? fmt::format(" (and {} more)", result.differences.size() - 1).c_str()
                                                 : "");
    }
  };
  std::vector<std::thread> threads;
  for (unsigned j = 0; j < jobs; ++j) threads.emplace_back(worker);
  for (auto& thread : threads) thread.join();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::uint64_t with_triggers = 0;
  for (const auto& [s, triggers] : differing) with_triggers += triggers.empty() ? 0 : 1;
  std::printf("seeds %llu-%llu: %llu cases, %llu configurations; %llu rows checked against the reference and alone, "
              "%llu also against Dinero IV; %llu rows also from nodetrace.simulate(); %llu curve points; %llu render checks (%llu rows); %llu property checks (sampling at 1/1: %llu rows by "
              "windows, %llu by sets); %llu cases differ (%llu of them "
              "hold a trigger of a defect not yet fixed), %llu render checks differ; %.1f s\n",
              static_cast<unsigned long long>(seed), static_cast<unsigned long long>(seed + cases - 1),
              static_cast<unsigned long long>(cases), static_cast<unsigned long long>(configs.load()),
              static_cast<unsigned long long>(rows.load()), static_cast<unsigned long long>(dinero_rows.load()),
              static_cast<unsigned long long>(python_rows.load()),
              static_cast<unsigned long long>(curve_points.load()), static_cast<unsigned long long>(renders),
              static_cast<unsigned long long>(render_rows.load()), static_cast<unsigned long long>(properties.load()),
              static_cast<unsigned long long>(sampled_windows.load()),
              static_cast<unsigned long long>(sampled_sets.load()),
              static_cast<unsigned long long>(differing.size()), static_cast<unsigned long long>(with_triggers),
              static_cast<unsigned long long>(differing_renders), seconds);
  return differing.empty() && differing_renders == 0 ? 0 : 1;
}
