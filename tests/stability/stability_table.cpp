// One row of the stability table (issue 9) per run: scripts/stability.sh
// runs each case in its own process, so the peak memory is that case's.
#include <sys/resource.h>

#include <charconv>
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>
#include <string>

#include "stability_cases.hpp"

namespace st = nodetrace::tracer::stability;

namespace {

using Maker = std::function<st::Case(std::size_t triangles, int pixels)>;

const std::map<std::string, Maker>& cases() {
  static const std::map<std::string, Maker> all = {
      {"scale-60", [](std::size_t, int p) { return st::scale_case(-60, p); }},
      {"scale-20", [](std::size_t, int p) { return st::scale_case(-20, p); }},
      {"scale0", [](std::size_t, int p) { return st::scale_case(0, p); }},
      {"scale20", [](std::size_t, int p) { return st::scale_case(20, p); }},
      {"scale60", [](std::size_t, int p) { return st::scale_case(60, p); }},
      {"tilted-plane", [](std::size_t, int p) { return st::tilted_plane_case(p); }},
      {"floor-camera-3e6", [](std::size_t, int p) { return st::big_floor_case(3e6f, p); }},
      {"floor-camera-20", [](std::size_t, int p) { return st::big_floor_case(20.0f, p); }},
      {"inside-closed-mesh", [](std::size_t, int p) { return st::inside_closed_mesh_case(4, p); }},
      {"fan-edges-vertices", [](std::size_t, int p) { return st::fan_case(p); }},
      {"grazing-1e-7", [](std::size_t, int p) { return st::grazing_case(p); }},
      {"coplanar", [](std::size_t n, int p) { return st::coplanar_case(n, p); }},
      {"slivers", [](std::size_t n, int p) { return st::sliver_case(n, p); }},
      {"range-1e-30-1e30", [](std::size_t n, int p) { return st::range_case(n, p); }},
      {"coincident", [](std::size_t n, int p) { return st::coincident_case(n, p); }},
      {"soup-3d", [](std::size_t n, int p) { return st::soup_case(n, p); }},
      {"mirrors-depth-64", [](std::size_t, int p) { return st::hall_of_mirrors_case(p); }},
  };
  return all;
}

int usage(std::FILE* out, int code) {
  std::fprintf(out,
               "Usage: stability_table --list | --header | CASE [TRIANGLES [PIXELS]]\n"
               "Runs one numerical-stability case and prints its row (CSV):\n"
               "case,triangles,build_s,build_cpu_s,peak_mb,rays,self_hits,escapes,watertight_misses,nans\n"
               "TRIANGLES sizes the coplanar, slivers, range, coincident and soup cases (default 100000);\n"
               "PIXELS is the image width (default 64).\n");
  return code;
}

bool parse(const char* text, std::size_t& value) {
  const char* end = text + std::strlen(text);
  const auto [at, error] = std::from_chars(text, end, value);
  return error == std::errc() && at == end && value > 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage(stderr, 2);
  const std::string first = argv[1];
  if (first == "--help" || first == "-h") return usage(stdout, 0);
  if (first == "--list") {
    for (const auto& [name, make] : cases()) std::printf("%s\n", name.c_str());
    return 0;
  }
  if (first == "--header") {
    std::printf("case,triangles,build_s,build_cpu_s,peak_mb,rays,self_hits,escapes,watertight_misses,nans\n");
    return 0;
  }
  const auto found = cases().find(first);
  if (found == cases().end()) {
    std::fprintf(stderr, "stability_table: unknown case '%s' (--list shows them)\n", first.c_str());
    return 2;
  }
  std::size_t triangles = 100000, pixels = 64;
  if ((argc > 2 && !parse(argv[2], triangles)) || (argc > 3 && !parse(argv[3], pixels)) || argc > 4) {
    return usage(stderr, 2);
  }
  const st::Case c = found->second(triangles, static_cast<int>(pixels));
  const st::Counts counts = st::run(c);
  rusage usage_now{};
  getrusage(RUSAGE_SELF, &usage_now);
  std::printf("%s,%llu,%.3f,%.3f,%.1f,%llu,%llu,%llu,%llu,%llu\n", first.c_str(),
              static_cast<unsigned long long>(counts.triangles), counts.build_seconds, counts.build_cpu_seconds,
              double(usage_now.ru_maxrss) / 1024.0, static_cast<unsigned long long>(counts.rays),
              static_cast<unsigned long long>(counts.self_hits), static_cast<unsigned long long>(counts.escapes),
              static_cast<unsigned long long>(counts.watertight_misses),
              static_cast<unsigned long long>(counts.nans));
  const bool clean = counts.self_hits == 0 && counts.escapes == 0 && counts.watertight_misses == 0 && counts.nans == 0;
  return clean ? 0 : 1;
}
