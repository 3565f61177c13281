// Hostile scenes, traces and options, one table row each: the command, the
// exit code it must give and the words its error message must start with.
// Every command runs in a fresh directory holding the fixture files below,
// under a hang guard (`timeout`), and with a memory limit where the row says
// so. A new case is one line.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "test_support.hpp"

namespace nodetrace::testing {
namespace {

// Small input files every case can use by name.
std::vector<std::pair<std::string, std::string>> fixture_files() {
  const std::string triangle = "v -1 -1 0\nv 1 -1 0\nv 0 1 0\n";
  std::vector<std::pair<std::string, std::string>> files = {
      {"ok.obj", triangle + "f 1 2 3\n"},
      {"far.obj", triangle + "f 1 2 100000000\n"},
      {"far_normal.obj", triangle + "vn 0 0 1\nf 1//1 2//1 3//90000000\n"},
      {"far_negative.obj", triangle + "f 1 2 -100000000\n"},
      {"one_past.obj", triangle + "f 1 2 4\n"},
      {"negative_past.obj", triangle + "f -1 -2 -9\n"},
      {"zero_index.obj", triangle + "f 0 1 2\n"},
      {"far_texture.obj", triangle + "vt 0 0\nf 1/1 2/1 3/7\n"},
      {"two_corners.obj", triangle + "f 1 2\n"},
      {"huge.obj", "v 1e39 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"},
      {"garbage.obj", "this is not an OBJ file\nnor is this\n"},
      {"huge.aff", "p 3\n1e39 0 0\n0 1 0\n0 0 1\n"},
      {"polygon_count.aff", "p 100000000\n0 0 0\n1 0 0\n0 1 0\n"},
      {"mesh_count.aff", "m vertices 100000000\n0 0 0\n1 0 0\n0 1 0\ntriangles 1\n0 1 2\n"},
      {"resolution.aff", "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 0 0\n"
                         "p 3\n0 0 0\n1 0 0\n0 1 0\n"},
      {"view_degenerate.aff", "v\nfrom 1 2 3\nat 1 2 3\nup 0 1 0\nangle 45\nhither 1\nresolution 4 3\n"
                              "p 3\n0 0 0\n1 0 0\n0 1 0\n"},
      {"view_up.aff", "v\nfrom 0 0 5\nat 0 0 0\nup 0 0 1\nangle 45\nhither 1\nresolution 4 3\n"
                      "p 3\n0 0 0\n1 0 0\n0 1 0\n"},
      {"view_angle.aff", "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 0\nhither 1\nresolution 4 3\n"
                         "p 3\n0 0 0\n1 0 0\n0 1 0\n"},
      {"empty.aff", "b 0 0 0\n"},
      {"animated.aff", "a 0 1 10\nk move {\ntransl 2\n0 0 0 0 0 0 0\n1 1 0 0 0 0 0\n}\n"
                       "x move {\np 3\n0 0 0\n1 0 0\n0 1 0\n}\n"},
      {"tag_cr.din", "0 00001000 07\r\n"},
      {"big_size.xdin", "r 104 10000\n"},
  };
  // A chain of files each including the next twice: 2^40 inclusions.
  for (int i = 0; i < 40; ++i) {
    const std::string next = fmt::format("chain{}.aff", i + 1);
    files.push_back({fmt::format("chain{}.aff", i), "i 1 " + next + "\ni 1 " + next + "\n"});
  }
  files.push_back({"chain40.aff", "p 3\n0 0 0\n1 0 0\n0 1 0\n"});
  std::string records;  // a 15K-record plain din trace
  for (int i = 0; i < 15000; ++i) records += fmt::format("0 {:08x} {:02d}\n", 8 * (i % 997), i % 12);
  files.push_back({"t.din", records});
  return files;
}

// `message` and `out` match from the start of standard error / output; a
// `*` in them skips any text (a byte offset, a path) up to what follows.
struct HostileCase {
  const char* name;
  // $B: build/bin; $LIMIT: a 4 GiB address-space limit, a guard. A row
  // that sets its own limit (`ulimit -v`) to make something run out is
  // skipped under AddressSanitizer.
  const char* command;
  int exit_code;
  const char* message;   // standard error starts with this
  const char* out = "";  // standard output starts with this
};

// clang-format off
const HostileCase kCases[] = {
  // OBJ face indices: every form bounds-checked, naming the line.
  {"ObjFarIndex", "$B/tracer info far.obj", 1, "tracer info: far.obj:4: vertex index 100000000 is out of range"},
  {"ObjFarIndexRender", "$B/tracer render far.obj --width 4 --height 3", 1, "tracer render: far.obj:4: vertex index 100000000"},
  {"ObjFarNormalIndex", "$B/tracer info far_normal.obj", 1, "tracer info: far_normal.obj:5: normal index 90000000 is out of range"},
  {"ObjFarNegativeIndex", "$B/tracer info far_negative.obj", 1, "tracer info: far_negative.obj:4: vertex index -100000000 is out of range"},
  {"ObjOnePastTheEnd", "$B/tracer info one_past.obj", 1, "tracer info: one_past.obj:4: vertex index 4 is out of range (3 vertices)"},
  {"ObjNegativePastTheStart", "$B/tracer info negative_past.obj", 1, "tracer info: negative_past.obj:4: vertex index -9 is out of range"},
  {"ObjZeroIndex", "$B/tracer info zero_index.obj", 1, "tracer info: zero_index.obj:4: vertex index 0 is out of range"},
  {"ObjFarTextureIndex", "$B/tracer info far_texture.obj", 1, "tracer info: far_texture.obj:5: texture coordinate index 7 is out of range"},
  {"ObjTwoCornerFace", "$B/tracer info two_corners.obj", 1, "tracer info: two_corners.obj:4: expected a face of at least 3 vertices"},
  {"ObjFloatOverflow", "$B/tracer info huge.obj", 1, "tracer info: huge.obj:1: expected a finite number of at most 3.40282e+38 in magnitude in 'v' line, got '1e39'"},
  {"ObjNoTriangles", "$B/tracer info garbage.obj", 1, "tracer info: garbage.obj: no triangles"},
  // AFF values, counts and includes.
  {"AffFloatOverflow", "$B/tracer info huge.aff", 1, "tracer info: huge.aff:2: expected polygon vertex coordinate (a number of at most 3.40282e+38 in magnitude), got '1e39'"},
  {"AffPolygonCount", "$LIMIT $B/tracer info polygon_count.aff", 1, "tracer info: polygon_count.aff:1: polygon vertex count 100000000 needs at least"},
  {"AffMeshVertexCount", "$LIMIT $B/tracer info mesh_count.aff", 1, "tracer info: mesh_count.aff:1: mesh vertex count 100000000 needs at least"},
  {"AffIncludeExplosion", "$LIMIT $B/tracer info chain0.aff", 1, "tracer info: chain"},
  {"AffResolutionZero", "$B/tracer info resolution.aff", 1, "tracer info: resolution.aff:7: expected a resolution of at least 1x1"},
  {"AffEyeAtLookAt", "$B/tracer info view_degenerate.aff", 1, "tracer info: view_degenerate.aff:1: view 'from' and 'at' are the same point"},
  {"AffUpAlongView", "$B/tracer info view_up.aff", 1, "tracer info: view_up.aff:1: view 'up' is parallel to the view direction"},
  {"AffViewAngle", "$B/tracer info view_angle.aff", 1, "tracer info: view_angle.aff:5: expected a view angle"},
  {"AffNoTriangles", "$B/tracer info empty.aff", 1, "tracer info: empty.aff: no triangles"},
  // Scene time and camera options.
  {"TimeNan", "$B/tracer info animated.aff --time nan", 2, "tracer info: --time nan: expected a finite number"},
  {"TimeNanRender", "$B/tracer render animated.aff --time nan --width 4 --height 3", 2, "tracer render: --time nan: expected a finite number"},
  {"TimeInf", "$B/tracer info animated.aff --time inf", 2, "tracer info: --time inf: expected a finite number"},
  {"EyeNan", "$B/tracer render ok.obj --eye nan 0 0 --look-at 0 0 0", 2, "tracer render: --eye"},
  {"EyeInf", "$B/tracer render ok.obj --eye inf 0 0 --look-at 0 0 0", 2, "tracer render: --eye"},
  {"EyeHuge", "$B/tracer render ok.obj --eye 1e39 0 0 --look-at 0 0 0", 2, "tracer render: --eye"},
  {"EyeLarge", "$B/tracer render ok.obj --eye 1e30 0 0 --look-at 0 0 0", 2, "tracer render: --eye 1e+30 0 0: expected coordinates of at most 1e+15"},
  {"LookAtNan", "$B/tracer render ok.obj --eye 0 0 5 --look-at nan 0 0", 2, "tracer render: --look-at"},
  {"UpNan", "$B/tracer render ok.obj --eye 0 0 5 --look-at 0 0 0 --up 0 nan 0", 2, "tracer render: --up"},
  {"FovNan", "$B/tracer render ok.obj --fov nan", 2, "tracer render: --fov"},
  {"EyeEqualsLookAt", "$B/tracer render ok.obj --eye 1 2 3 --look-at 1 2 3", 2, "tracer render: --eye and --look-at are the same point"},
  {"UpAlongView", "$B/tracer render ok.obj --eye 0 0 5 --look-at 0 0 0 --up 0 0 1", 2, "tracer render: --up is parallel to the view direction"},
  {"UpZero", "$B/tracer render ok.obj --eye 0 0 5 --look-at 0 0 0 --up 0 0 0", 2, "tracer render: --up is parallel to the view direction"},
  // Image, tree and address options.
  {"WidthZero", "$B/tracer render ok.obj --width 0", 2, "tracer render: --width: 0 is outside 1 to 65535"},
  {"NodeSizeZero", "$B/tracer render ok.obj --node-size 0", 2, "tracer render: --node-size: 0 is outside 1 to 65535"},
  {"InfoNodeSizeZero", "$B/tracer info ok.obj --node-size 0", 2, "tracer info: --node-size: 0 is outside 1 to 65535"},
  {"TileSizeZero", "$B/tracer render ok.obj --tile-size 0", 2, "tracer render: --tile-size: 0 is outside 1 to 65535"},
  {"ImageSideTooLarge", "$B/tracer render ok.obj --width 65536 --height 65536", 2, "tracer render: --width: 65536 is outside 1 to 65535"},
  {"ImageTooLarge", "$B/tracer render ok.obj --width 65535 --height 65535", 2, "tracer render: --width 65535 --height 65535: at most 67108864 pixels"},
  {"NodeBaseWraps", "$B/tracer render sphereflake:1 --width 4 --height 3 --node-base 0xfffffffffffffff0 -o t.din.zst", 2, "tracer render: --node-base 0xfffffffffffffff0"},
  {"ListBaseWraps", "$B/tracer render ok.obj --width 4 --height 3 --streams nodes,lists --list-base 0xffffffffffffffff -o t.din.zst --default-lights none", 2, "tracer render: --list-base 0xffffffffffffffff"},
  {"SceneSizeZero", "$B/tracer info sphereflake:0", 1, "tracer info: scene 'sphereflake:0': size 0 is out of range"},
  {"SceneSizeLarge", "$B/tracer info sphereflake:9", 1, "tracer info: scene 'sphereflake:9': size 9 is out of range"},
  {"SplitLevelHuge", "$B/tracer render ok.obj --width 4 --height 3 --split-level 4294967295", 2, "tracer render: --split-level: 4294967295 is outside 0 to 100"},
  {"TraversalCostNan", "$B/tracer render ok.obj --width 4 --height 3 --traversal-cost nan", 2, "tracer render: --traversal-cost nan: expected a finite number"},
  {"EmptyBonusNan", "$B/tracer info ok.obj --empty-bonus nan", 2, "tracer info: --empty-bonus: 'nan' is not a number: expected 0 to 1"},
  {"OutOfMemory", "ulimit -v 1000000; $B/tracer render ok.obj --width 8192 --height 8192 --image o.png --default-lights none", 1, "tracer render: out of memory"},
  {"FrameRecordsZero", "$B/tracetool convert t.din out.din.zst --tags-are-levels --frame-records 0", 2, "tracetool convert: --frame-records: 0 is outside 1 to 16777216"},
  {"FrameRecordsHuge", "$B/tracetool convert t.din out.din.zst --tags-are-levels --frame-records 100000000000", 2, "tracetool convert: --frame-records: 100000000000 is outside 1 to 16777216"},
  // Usage messages name the program and subcommand first (issue 22, items 4, 7, 8, 10, 16).
  // One behaviour for a missing or unknown subcommand in every program (item 6).
  {"TracetoolBogus", "$B/tracetool bogus", 2, "tracetool: unknown subcommand 'bogus'"},
  {"TracerBogus", "$B/tracer bogus", 2, "tracer: unknown subcommand 'bogus'"},
  {"CachesimBogus", "$B/cachesim bogus", 2, "cachesim: unknown subcommand 'bogus'"},
  {"DineroWrapBogus", "$B/dinero-wrap bogus", 2, "dinero-wrap: unknown subcommand 'bogus'"},
  {"TracetoolBare", "$B/tracetool", 2, "tracetool: inspect, print, verify and convert"},
  {"TracerBare", "$B/tracer", 2, "tracer: render scenes"},
  {"CachesimBare", "$B/cachesim", 2, "cachesim: simulate node caches"},
  {"CachesimStdinTwice", "cat t.din | $B/cachesim run - - --tags-are-levels", 2, "cachesim run: traces: standard input (-) is named more than once"},
  {"CachesimEmptyZst", ": > empty.din.zst; $B/cachesim run empty.din.zst", 1, "cachesim run: empty.din.zst: 0 bytes: not a zstd stream"},
  {"VerifyEmptyZst", ": > empty.din.zst; $B/tracetool verify empty.din.zst", 1, "tracetool verify: empty.din.zst: 0 bytes: not a zstd stream"},
  // An input without records is an error, file or pipe (issue 52, item 2).
  {"VerifyEmptyPipe", "$B/tracer render nosuchscene -o - 2>/dev/null | $B/tracetool verify -", 1, "tracetool verify: <stdin>: no records: an input without records is not a trace (did the command before the pipe fail?)"},
  {"CachesimEmptyPipeSplit", "$B/tracer render nosuchscene -o - 2>/dev/null | $B/cachesim run - --scheme single,split", 1, "cachesim run: <stdin>: no records: an input without records is not a trace (did the command before the pipe fail?)"},
  {"CachesimEmptyFile", ": > empty.din; $B/cachesim run empty.din", 1, "cachesim run: empty.din: no records: an input without records is not a trace"},
  {"WrapEmptyPipe", ": | $B/dinero-wrap run - --dinero \"$B/cachesim dinero\"", 1, "dinero-wrap run: <stdin>: no records: an input without records is not a trace (did the command before the pipe fail?)"},
  {"InfoEmptyFile", ": > empty.din; $B/tracetool info empty.din", 1, "tracetool info: empty.din: no records: an input without records is not a trace"},
  {"CachesimFormatXml", "$B/cachesim run t.din --format xml", 2, "cachesim run: --format: xml not in {table,csv,json}"},
  {"CachesimNoTraces", "$B/cachesim run", 2, "cachesim run: traces is required"},
  {"CachesimPolicyLfu", "$B/cachesim run t.din --policy lfu", 2, "cachesim run: --policy: 'lfu' is not one of lru, fifo, random, plru, srrip, brrip, drrip, opt"},
  {"CachesimSchemeBad", "$B/cachesim run t.din --scheme both", 2, "cachesim run: --scheme: 'both' is not one of single, split"},
  {"TracetoolInfoFormatXml", "$B/tracetool info t.din --format xml", 2, "tracetool info: --format: xml not in {table,csv,json}"},
  // Threads.
  {"TracerThreads", "$B/tracer render ok.obj --width 4 --height 3 --threads 100000", 2, "tracer render: --threads 100000: at most"},
  {"ConvertThreads", "$B/tracetool convert t.din out.din.zst --tags-are-levels --threads 100000", 2, "tracetool convert: --threads 100000: at most"},
  {"CachesimThreads", "$B/cachesim run t.din --threads 100000", 2, "cachesim run: --threads 100000: at most"},
  {"WrapThreads", "$B/dinero-wrap run t.din --threads 100000 --dinero '$B/cachesim dinero'", 2, "dinero-wrap run: --threads 100000: at most"},
  {"WrapJobs", "$B/dinero-wrap run t.din --jobs 100000 --dinero '$B/cachesim dinero'", 2, "dinero-wrap run: --jobs 100000: at most"},
  // Threads that cannot start (their stacks do not fit the address space).
  {"TracerThreadsFail", "ulimit -v 250000; $B/tracer render ok.obj --width 256 --height 256 --threads 64 -q --default-lights none", 1, "tracer render: cannot start 64 threads"},
  {"ConvertThreadsFail", "ulimit -v 250000; $B/tracetool convert t.din out.din.zst --tags-are-levels --threads 64", 1, "tracetool convert: cannot start 64 threads"},
  {"CachesimThreadsFail", "ulimit -v 250000; $B/cachesim run t.din --threads 64", 1, "cachesim run: cannot start 64 threads"},
  // What one path of cachesim run would get wrong is refused, naming the record (issue 47's harness: d, g, h).
  {"CachesimLastOneByteBlock", "printf 'r ffffffffffffffff 1\\n' > last.xdin; $B/cachesim run last.xdin --block 1", 1, "cachesim run: last.xdin: record 1: address 0xffffffffffffffff of 1 bytes reaches address 0xffffffffffffffff"},
  {"CachesimSampleSetsSpanning", "printf 'r 8 10\\nr 10 8\\n' > g.xdin; $B/cachesim run g.xdin --size 256 --block 8 --assoc 4 --sample-sets 1/1", 1, "cachesim run: g.xdin: record 1: --sample-sets: the reference at 0x8 of 16 bytes spans blocks of 8 bytes"},
  {"CachesimPrefetchAbove2To32", "printf 'r 0 8\\nr 100000000 8\\n' > h.xdin; $B/cachesim run h.xdin --size 1k --fetch always", 1, "cachesim run: h.xdin: record 2: address 0x100000000 reaches 2^32: a --fetch other than demand is simulated by Dinero IV's engine"},
  // Caches whose state cannot fit are refused before they are allocated (issue 52, item 7).
  {"CachesimStateTooLarge", "ulimit -v 800000; $B/cachesim run t.din --size 256m --assoc 32,full", 2, "cachesim run: the caches asked for keep about 3072 MiB of state, allocated before the first record, more than the "},
  {"CachesimSizePerCache", "$B/cachesim run t.din --size 512m", 2, "cachesim run: --size 512m: at most 256m (the largest cache: its state is allocated up front)"},
  // Cache sizes: a stated limit instead of an allocation of the size asked.
  {"CacheSizeHuge", "$LIMIT $B/cachesim run t.din --size 1024g", 2, "cachesim run: --size 1024g: at most 256m"},
  {"CacheSize16g", "$LIMIT $B/cachesim run t.din --size 16g", 2, "cachesim run: --size 16g: at most 256m"},
  {"HighSizeHuge", "$LIMIT $B/cachesim run t.din --scheme split --split-level 3 --high-size 16g", 2, "cachesim run: --high-size 16g: at most 256m"},
  {"CacheBlocks", "$LIMIT $B/cachesim run t.din --size 256m --block 1", 2, "cachesim run: --size 256m with --block 1: 268435456 blocks, at most 33554432"},
  {"WrapCacheSize", "$LIMIT $B/dinero-wrap run t.din --size 16g --dinero '$B/cachesim dinero'", 2, "dinero-wrap run: --size 16g: at most 256m"},
  // Trace data.
  {"XdinSize16Bits", "$B/cachesim run big_size.xdin", 1, "cachesim run: big_size.xdin: record 1: size 0x10000"},
  {"XdinSize16BitsInfo", "$B/tracetool verify big_size.xdin", 1, "tracetool verify: big_size.xdin: record 1: size 0x10000"},
  {"TagWithCarriageReturn", "$B/tracetool verify tag_cr.din --tags-are-levels", 1, "tracetool verify: tag_cr.din: record 1: tag '07\\r'"},
  {"MarkerErrorNamesTheKey", "$B/tracer render sphereflake:1 --width 8 --height 6 -q -o m.din.zst && "
      "sed 's/\"leaves\":\\([0-9]\\)\\([0-9]*\\)\\([0-9]\\)/\"leaves\":\"\\2\"/' m.din.zst > bad.din.zst && "
      "$B/tracetool verify bad.din.zst", 1, "tracetool verify: bad.din.zst: at byte *: animation frame marker: \"leaves\" is \""},
  {"PlainZstdDamageNamesItsFrame", "zstd -q t.din -o t.zst && dd if=/dev/zero of=t.zst bs=1 seek=1000 count=16 conv=notrunc 2>/dev/null && "
      "$B/tracetool verify t.zst", 1, "tracetool verify: t.zst: damaged zstd data in the zstd frame that starts at byte 0"},
  {"PlainZstdDamageInALaterFrame", "head -c 100000 t.din | zstd -q > t.zst && tail -c +100001 t.din | zstd -q > tail.zst && "
      "wc -c < t.zst > first_size && dd if=/dev/zero of=tail.zst bs=1 seek=200 count=16 conv=notrunc 2>/dev/null && "
      "cat tail.zst >> t.zst && $B/tracetool verify t.zst 2>&1 >/dev/null | grep -q \"frame that starts at byte $(cat first_size) \" && "
      "$B/tracetool verify t.zst", 1, "tracetool verify: t.zst: damaged zstd data in the zstd frame that starts at byte "},
  {"VerifyCountsAnimationFrames", "$B/tracer render animated.aff --frames 0-2 --width 4 --height 3 -q -o a.din.zst && "
      "$B/tracetool verify a.din.zst", 0, "", "OK: * records, 3 animation frames, "},
  {"VerifyNamesBinaryInput", "$B/tracetool convert t.din t.bin --to binary --tags-are-levels && "
      "$B/tracetool verify t.bin --informat binary", 0, "", "OK: 15000 records, 1 animation frame (a plain Dinero binary trace"},
  // Option names and scripts.
  // --informat everywhere (Dinero IV's own -informat) for the input's form, --records for the output's;
  // tracetool's --form, an input alias easily read as the output's, is gone (one name each).
  {"TracetoolInformat", "$B/tracetool info t.din --informat xdin", 1, "tracetool info: t.din: record 1: unknown access type '0'"},
  {"TracetoolFormIsGone", "$B/tracetool info t.din --form xdin", 2, "tracetool info: The following arguments were not expected: xdin --form"},
  {"CachesimInformat", "$B/cachesim run t.din --informat xdin", 1, "cachesim run: t.din: record 1: unknown access type '0'"},
  {"TestScriptHelp", "$SRC/scripts/test.sh --help", 0, ""},
};
// clang-format on

void PrintTo(const HostileCase& c, std::ostream* out) { *out << c.command; }

// Whether `text` starts with `pattern`, where `*` matches any run of text.
bool matches_from_start(const std::string& text, const std::string& pattern) {
  std::size_t at = 0, from = 0;
  bool anchored = true;
  while (true) {
    const std::size_t star = pattern.find('*', from);
    const std::string part = pattern.substr(from, star == std::string::npos ? std::string::npos : star - from);
    const std::size_t found = anchored ? (text.compare(at, part.size(), part) == 0 ? at : std::string::npos)
                                       : text.find(part, at);
    if (found == std::string::npos) return false;
    at = found + part.size();
    if (star == std::string::npos) return true;
    from = star + 1;
    anchored = false;
  }
}

class HostileInput : public ::testing::TestWithParam<HostileCase> {};

std::string expand(std::string command, const std::string& name, const std::string& value) {
  for (std::size_t at = command.find(name); at != std::string::npos; at = command.find(name, at + value.size())) {
    command.replace(at, name.size(), value);
  }
  return command;
}

TEST_P(HostileInput, ExitsWithItsCodeAndMessage) {
  const HostileCase& c = GetParam();
  TempDir dir;
  for (const auto& [name, bytes] : fixture_files()) write_file(dir / name, bytes);
#if defined(__SANITIZE_ADDRESS__)
  // AddressSanitizer reserves terabytes of address space: no limit applies.
  if (std::string(c.command).find("ulimit -v") != std::string::npos) GTEST_SKIP() << "needs an address-space limit";
  const std::string limit;
#else
  const std::string limit = "ulimit -v 4194304;";
#endif
  std::string command = expand(c.command, "$LIMIT", limit);
  command = expand(command, "$B", program("").string());
  command = expand(command, "$SRC", NODETRACE_SOURCE_DIR);
  write_file(dir / "case.sh", command + "\n");
  // The hang guard: a case that runs this long has hung (exit 124).
  const auto result = run_command("cd '" + dir.path().string() + "' && timeout 300 sh ./case.sh");
  EXPECT_EQ(result.exit_code, c.exit_code) << c.command << "\nstderr: " << result.err;
  EXPECT_TRUE(matches_from_start(result.err, c.message)) << c.command << "\nstderr: " << result.err
                                                          << "\nexpected: " << c.message;
  EXPECT_TRUE(matches_from_start(result.out, c.out)) << c.command << "\nstdout: " << result.out
                                                      << "\nexpected: " << c.out;
}

INSTANTIATE_TEST_SUITE_P(Table, HostileInput, ::testing::ValuesIn(kCases),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace nodetrace::testing
