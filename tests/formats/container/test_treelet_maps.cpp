// Treelet maps (FORMAT.md 2.2.2): each animation frame's map round-trips
// with its marker in both encodings, through files, pipes, skipped data
// frames and seeks; the writer refuses maps that break the rules, the reader
// refuses damaged or impossible map frames naming the trace, the frame and
// the byte; tracetool shows, checks, keeps or drops them as it says.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "container/container.hpp"
#include "container/treelet_map_codec.hpp"
#include "formats_test_util.hpp"
#include "test_support.hpp"

namespace nodetrace::formats {
namespace {

using nodetrace::testing::program;
using nodetrace::testing::read_file;
using nodetrace::testing::run_command;
using nodetrace::testing::shell_quoted;
using nodetrace::testing::TempDir;
using nodetrace::testing::write_file;
using testing_util::read_all;
using testing_util::read_error;
using testing_util::sample_records;

constexpr std::uint64_t kNodeBase = 0x10000000;
constexpr std::uint64_t kNodeSize = 8;
constexpr std::uint64_t kNodes = 0x100000;  // sample_records' addresses lie in these nodes

nlohmann::json layout_header() {
  return {{"layout", {{"name", "treelet"}, {"node_size", kNodeSize}, {"node_base", kNodeBase}}}};
}

// `count` adjacent treelets from the node base, of 8 nodes but every
// seventh shorter: what the treelet layout makes, zstd's kind of input.
TreeletMap adjacent_map(std::size_t count) {
  TreeletMap map;
  std::uint64_t at = kNodeBase;
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint64_t bytes = (i % 7 == 6 ? 3 : 8) * kNodeSize;
    map.treelets.push_back({at, bytes});
    at += bytes;
  }
  return map;
}

// Two treelets with gaps before each, too small for zstd to pay.
TreeletMap gapped_map() { return TreeletMap{{{kNodeBase + 64, 24}, {kNodeBase + 800, 8}}}; }

AnimationFrameMarker marker_with(std::uint64_t frame, std::optional<TreeletMap> map) {
  AnimationFrameMarker marker;
  marker.frame = frame;
  marker.nodes = kNodes;
  marker.nodes_per_level = {1, kNodes - 1};
  marker.depth = 2;
  marker.treelets = std::move(map);
  return marker;
}

WriterOptions map_options(std::uint64_t records_per_data_frame = 1000) {
  WriterOptions options;
  options.form = RecordForm::Din;
  options.records_per_data_frame = records_per_data_frame;
  options.threads = 2;
  options.treelet_maps = true;
  return options;
}

// Three animation frames of 3000, 2500 and 0 records: a zstd-encoded map,
// a plain one and an empty one.
std::vector<std::pair<std::uint64_t, AnimationFrameMarker>> three_frames() {
  return {{0, marker_with(0, adjacent_map(5000))}, {3000, marker_with(1, gapped_map())},
          {5500, marker_with(2, TreeletMap{})}};
}

std::vector<std::optional<TreeletMap>> maps_read(const ReaderOptions& options, const std::string& path) {
  std::vector<std::optional<TreeletMap>> maps;
  for (const auto& [record, marker] : read_all(path, options).markers) maps.push_back(marker.treelets);
  return maps;
}

std::vector<std::optional<TreeletMap>> maps_written() {
  std::vector<std::optional<TreeletMap>> maps;
  for (const auto& [record, marker] : three_frames()) maps.push_back(marker.treelets);
  return maps;
}

// The payload of each map frame of a container without data frames (every
// frame is then a skippable one), and the same bytes with map `which`'s
// payload replaced. The index stays empty, so it fits whatever the length.
std::vector<std::pair<std::size_t, std::size_t>> map_payloads(const std::string& bytes) {
  std::vector<std::pair<std::size_t, std::size_t>> found;  // offset of the payload, its size
  for (std::size_t at = 0; at + 8 <= bytes.size();) {
    const std::uint32_t magic = detail::load_le32(bytes.data() + at);
    const std::uint32_t size = detail::load_le32(bytes.data() + at + 4);
    if (magic == detail::kTreeletMapMagic) found.emplace_back(at + 8, size);
    at += 8 + size;
  }
  return found;
}

std::string with_map_payload(std::string bytes, std::size_t which, const std::string& payload) {
  const auto [offset, size] = map_payloads(bytes).at(which);
  std::string size_bytes;
  detail::append_le32(size_bytes, static_cast<std::uint32_t>(payload.size()));
  bytes.replace(offset - 4, 4, size_bytes);
  bytes.replace(offset, size, payload);
  return bytes;
}

std::string varints(std::initializer_list<std::uint64_t> values) {
  std::string out;
  for (std::uint64_t value : values) {
    while (value >= 0x80) {
      out.push_back(static_cast<char>((value & 0x7F) | 0x80));
      value >>= 7;
    }
    out.push_back(static_cast<char>(value));
  }
  return out;
}

// A plain payload (encoding 0) of these varints.
std::string plain_payload(std::initializer_list<std::uint64_t> values) { return std::string(1, '\0') + varints(values); }

class TreeletMaps : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // A container of `markers` and no records, written with maps.
  std::string write_markers_only(const std::string& name) {
    testing_util::write_trace(path(name), {}, map_options(), layout_header(),
                              {{0, marker_with(0, gapped_map())}, {0, marker_with(1, adjacent_map(40))}});
    return read_file(path(name));
  }

  // The error reading `bytes` as a file, and as standard input.
  std::pair<std::string, std::string> errors_of(const std::string& bytes) {
    write_file(path("bad.din.zst"), bytes);
    std::string piped;
    const std::string thrown = testing_util::with_stdin_from(bytes, [&] { read_all("-"); });
    return {read_error(path("bad.din.zst")), thrown};
  }

  TempDir dir_;
};


TEST_F(TreeletMaps, EveryMapRoundTripsWithItsMarkerInBothEncodings) {
  const auto records = sample_records(5500);
  testing_util::write_trace(path("t.din.zst"), records, map_options(), layout_header(), three_frames());
  // The large map is held as zstd, the small one as plain varints.
  const std::string big = detail::encode_treelet_map(adjacent_map(5000));
  const std::string small = detail::encode_treelet_map(gapped_map());
  EXPECT_EQ(big[0], 1);
  EXPECT_LT(big.size(), 5000u / 4);
  EXPECT_EQ(small[0], 0);
  const auto read = read_all(path("t.din.zst"));
  auto as_din = records;  // din reads every record as 4 bytes
  for (Record& record : as_din) record.size = 4;
  EXPECT_EQ(read.records, as_din);
  ASSERT_EQ(read.markers.size(), 3u);
  EXPECT_EQ(read.markers[1].first, 3000u);
  EXPECT_EQ(maps_read({}, path("t.din.zst")), maps_written());
  // The header says the trace carries them.
  auto reader = TraceReader::open(path("t.din.zst"));
  EXPECT_TRUE(reader->header().carries_treelet_maps());
  EXPECT_EQ(reader->header().json["treelet_map"], true);
  // Standard input delivers them too.
  std::vector<std::optional<TreeletMap>> piped;
  EXPECT_EQ(testing_util::with_stdin_from(read_file(path("t.din.zst")),
                                          [&] {
                                            for (const auto& [r, m] : read_all("-").markers) piped.push_back(m.treelets);
                                          }),
            "");
  EXPECT_EQ(piped, maps_written());
}

TEST_F(TreeletMaps, ReadersThatSkipDataFramesStillDeliverEveryMap) {
  const auto records = sample_records(5500);
  testing_util::write_trace(path("t.din.zst"), records, map_options(), layout_header(), three_frames());
  for (const bool keep_first : {false, true}) {
    ReaderOptions options;
    // None kept, or only the first data frame of each animation frame.
    options.keep_data_frame = [&](const DataFrameIndexEntry& entry) {
      return keep_first && (entry.first_record == 0 || entry.first_record == 3000);
    };
    auto reader = TraceReader::open(path("t.din.zst"), options);
    std::vector<std::optional<TreeletMap>> maps;
    std::uint64_t delivered = 0;
    RecordBatch batch;
    while (reader->next(batch)) {
      if (batch.marker) maps.push_back(batch.marker->treelets);
      delivered += batch.records.size();
    }
    EXPECT_EQ(maps, maps_written()) << keep_first;
    EXPECT_EQ(delivered, keep_first ? 2000u : 0u);
    EXPECT_EQ(reader->data_frames_skipped(), keep_first ? 4u : 6u);
  }
  // A seek lands inside animation frame 0 (no marker there, as for any
  // seek); the markers after it carry their maps.
  auto reader = TraceReader::open(path("t.din.zst"));
  reader->seek_to_record(1500);
  std::vector<std::optional<TreeletMap>> after_seek;
  RecordBatch batch;
  while (reader->next(batch)) {
    if (batch.marker) after_seek.push_back(batch.marker->treelets);
  }
  const auto written = maps_written();
  EXPECT_EQ(after_seek, std::vector<std::optional<TreeletMap>>(written.begin() + 1, written.end()));
}

TEST_F(TreeletMaps, TracesWithoutMapsHaveNoMapFrameAndNoHeaderKey) {
  const auto records = sample_records(3000);
  WriterOptions options = map_options();
  options.treelet_maps = false;
  testing_util::write_trace(path("t.din.zst"), records, options, layout_header(), {{0, marker_with(0, std::nullopt)}});
  const std::string bytes = read_file(path("t.din.zst"));
  EXPECT_EQ(bytes.find("treelet_map"), std::string::npos);
  const auto read = read_all(path("t.din.zst"));
  ASSERT_EQ(read.markers.size(), 1u);
  EXPECT_FALSE(read.markers[0].second.treelets);
}

TEST_F(TreeletMaps, TheWriterRefusesABadMapNamingTheTraceAndTheFrame) {
  const struct {
    const char* name;
    TreeletMap map;
    const char* message;
  } cases[] = {
      {"unsorted", {{{kNodeBase + 64, 8}, {kNodeBase, 8}}}, "treelet 2 of 2 begins at 0x10000000, before treelet 1"},
      {"overlapping", {{{kNodeBase, 16}, {kNodeBase + 8, 8}}}, "treelet 2 of 2 begins at 0x10000008, inside treelet 1"},
      {"empty", {{{kNodeBase, 8}, {kNodeBase + 8, 0}}}, "treelet 2 of 2 (at 0x10000008) is empty"},
      {"below", {{{kNodeBase - 8, 8}}}, "treelet 1 of 1, 0xffffff8 + 8 bytes, lies outside the frame's node addresses "
                                         "[0x10000000, 0x10800000)"},
      {"above", {{{kNodeBase + kNodes * kNodeSize - 8, 16}}}, "treelet 1 of 1, 0x107ffff8 + 16 bytes, lies outside"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    auto writer = TraceWriter::create(path("w.din.zst"), layout_header(), map_options());
    try {
      writer->begin_animation_frame(marker_with(7, c.map));
      ADD_FAILURE() << "accepted";
    } catch (const base::FormatError& error) {
      const std::string expected = path("w.din.zst") + ": treelet map of animation frame 7: " + c.message;
      EXPECT_EQ(std::string(error.what()).rfind(expected, 0), 0u) << error.what();
    }
  }
  // A map the writer was not told of, and a missing one it was: usage.
  WriterOptions without = map_options();
  without.treelet_maps = false;
  EXPECT_THROW(TraceWriter::create(path("w.din.zst"), layout_header(), without)
                   ->begin_animation_frame(marker_with(0, gapped_map())),
               base::UsageError);
  EXPECT_THROW(TraceWriter::create(path("w.din.zst"), layout_header(), map_options())
                   ->begin_animation_frame(marker_with(0, std::nullopt)),
               base::UsageError);
}

TEST_F(TreeletMaps, AMapThatBreaksTheRulesIsRefusedNamingTheTraceTheFrameAndTheByte) {
  const std::string good = write_markers_only("good.din.zst");
  const auto payloads = map_payloads(good);
  ASSERT_EQ(payloads.size(), 2u);
  const std::uint64_t second = payloads[1].first;  // payload of animation frame 1's map
  const std::string where = fmt::format("treelet map of animation frame 1 at byte {}: ", second - 8);
  const std::uint64_t top = kNodeBase + kNodes * kNodeSize;
  const struct {
    const char* name;
    std::string payload;
    std::string message;
  } cases[] = {
      // Gaps are unsigned, so no payload is unsorted or overlapping: those
      // are the writer's to refuse (above).
      {"empty treelet", plain_payload({2, 8, 1 << 1 | 1, kNodeBase / 8 + 1, 0}),
       "treelet 2 of 2 (at 0x10000010) is empty"},
      {"below the nodes", plain_payload({1, 8, 2 << 1 | 1, kNodeBase / 8 - 1}),
       "treelet 1 of 1, 0xffffff8 + 16 bytes, lies outside the frame's node addresses [0x10000000, 0x10800000)"},
      {"above the nodes", plain_payload({1, 8, 2 << 1 | 1, top / 8 - 1}),
       "treelet 1 of 1, 0x107ffff8 + 16 bytes, lies outside"},
      {"past 2^64", plain_payload({1, 1, 2 << 1 | 1, ~std::uint64_t{0}}),
       fmt::format("byte {}: treelet 1 runs past address 2^64 - 1", second + 3)},
      {"cut varint", std::string(1, '\0') + varints({1, 8}) + "\x85", fmt::format("byte {}: the map ends inside a treelet's length", second + 3)},
      {"overlong varint", std::string(1, '\0') + std::string(11, '\x80'), fmt::format("byte {}: the treelet count is longer than 10 bytes", second + 1)},
      {"trailing bytes", plain_payload({1, 8, 2 << 1 | 1, kNodeBase / 8, 7}),
       fmt::format("byte {}: 1 bytes after the last of its 1 treelets", second + 8)},
      {"more treelets than nodes", plain_payload({kNodes + 1, 8}), fmt::format("byte {}: {} treelets, more than the frame's", second + 1, kNodes + 1)},
      {"unit 0", plain_payload({1, 0}), fmt::format("byte {}: the unit is 0 bytes", second + 2)},
      {"unknown encoding", std::string(1, '\x07') + varints({0, 1}), fmt::format("byte {}: encoding 7 is neither", second)},
      {"no encoding byte", std::string(), fmt::format("byte {}: the map is empty", second)},
      {"damaged zstd", std::string(1, '\x01') + std::string("\x28\xB5\x2F\xFD\x20\x05", 6) + "xxxxx",
       fmt::format("byte {}: the zstd frame", second + 1)},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const auto [file_error, piped_error] = errors_of(with_map_payload(good, 1, c.payload));
    EXPECT_EQ(file_error.rfind(path("bad.din.zst") + ": " + where + c.message, 0), 0u) << file_error;
    EXPECT_EQ(piped_error.rfind("<stdin>: " + where + c.message, 0), 0u) << piped_error;
  }
  // A compressed map whose content is damaged names the byte of that
  // content (zstd's own tool makes the frame, with its content size).
  write_file(path("body"), varints({1, 8, 2 << 1 | 1, kNodeBase / 8}) + "\x85");
  ASSERT_EQ(run_command("zstd -q -f -o " + shell_quoted(path("body.zst")) + " " + shell_quoted(path("body"))).exit_code, 0);
  const auto [file_error, piped_error] =
      errors_of(with_map_payload(good, 1, std::string(1, '\x01') + read_file(path("body.zst"))));
  EXPECT_EQ(file_error, path("bad.din.zst") + ": " + where +
                            "byte 7 of its decompressed content: 1 bytes after the last of its 1 treelets");
}

TEST_F(TreeletMaps, AMissingMisplacedOrCutMapFrameIsRefused) {
  const std::string good = write_markers_only("good.din.zst");
  const auto payloads = map_payloads(good);
  const std::uint64_t first_map = payloads[0].first - 8;
  // The map of frame 0 removed: frame 0's marker has none.
  std::string missing = good;
  missing.erase(first_map, 8 + payloads[0].second);
  const std::uint64_t header_end = 8 + detail::load_le32(good.data() + 4);  // frame 0's marker
  EXPECT_EQ(errors_of(missing).first,
            fmt::format("{}: animation frame 0 (marker at byte {}) has no treelet map at byte {}: the header says "
                        "every marker is followed by one",
                        path("bad.din.zst"), header_end, first_map));
  // Frame 0's map twice: the second follows no marker.
  std::string twice = good;
  const std::string frame = good.substr(first_map, 8 + payloads[0].second);
  twice.insert(first_map + frame.size(), frame);
  EXPECT_NE(errors_of(twice).first.find(fmt::format("treelet map at byte {} does not follow an animation frame marker",
                                                    first_map + frame.size())),
            std::string::npos)
      << errors_of(twice).first;
  // Cut inside the map frame (a pipe: a file's missing trailer is found first).
  const std::string piped = errors_of(good.substr(0, first_map + 10)).second;
  EXPECT_EQ(piped, fmt::format("<stdin>: truncated: treelet map at byte {} is cut short", first_map));
  // A header key that is not a boolean.
  std::string header_damaged = good;
  const auto key = header_damaged.find("\"treelet_map\":true");
  ASSERT_NE(key, std::string::npos);
  header_damaged.replace(key, 18, "\"treelet_map\":1   ");
  EXPECT_NE(errors_of(header_damaged).first.find("damaged header: \"treelet_map\" is 1, not true or false"),
            std::string::npos);
  // Without the header's key a 0x184D2A53 frame is someone else's, skipped
  // (FORMAT.md 2.5), and the markers carry no map.
  std::string unannounced = good;
  unannounced.replace(key, 18, "\"treelet_maX\":true");
  write_file(path("other.din.zst"), unannounced);
  ReaderOptions empty_ok;
  empty_ok.allow_empty = true;
  auto reader = TraceReader::open(path("other.din.zst"), empty_ok);
  std::size_t markers = 0;
  try {
    RecordBatch batch;
    while (reader->next(batch)) {
      if (batch.marker) {
        EXPECT_FALSE(batch.marker->treelets);
      }
      markers += batch.marker.has_value();
    }
    ADD_FAILURE() << "the changed header went unnoticed";
  } catch (const base::FormatError& error) {
    // Only the hash of the changed header's bytes is wrong.
    EXPECT_NE(std::string(error.what()).find("content hash mismatch"), std::string::npos) << error.what();
  }
  EXPECT_GE(markers, 1u);  // the last one, with no records, would go out after the final checks
}

TEST_F(TreeletMaps, TracetoolShowsChecksKeepsAndDropsThem) {
  const auto records = sample_records(5500);
  testing_util::write_trace(path("t.din.zst"), records, map_options(), layout_header(), three_frames());
  const std::string tracetool = shell_quoted(program("tracetool"));
  // info: per animation frame, the treelets and the map frame's bytes.
  const auto info = run_command(tracetool + " info --format json " + shell_quoted(path("t.din.zst")));
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const auto json = nlohmann::json::parse(info.out);
  const std::uint64_t big = 8 + detail::encode_treelet_map(adjacent_map(5000)).size();
  const std::uint64_t small = 8 + detail::encode_treelet_map(gapped_map()).size();
  const std::uint64_t empty = 8 + detail::encode_treelet_map(TreeletMap{}).size();
  EXPECT_EQ(json["treelet_maps"], nlohmann::json::parse(fmt::format(
                                      R"([{{"frame":0,"treelets":5000,"bytes":{}}},{{"frame":1,"treelets":2,"bytes":{}}},)"
                                      R"({{"frame":2,"treelets":0,"bytes":{}}}])",
                                      big, small, empty)));
  EXPECT_EQ(json["treelet_map_bytes"], big + small + empty);
  const auto table = run_command(tracetool + " info " + shell_quoted(path("t.din.zst")));
  EXPECT_NE(table.out.find(fmt::format("  frame 1            2 treelets, {} bytes\n", small)), std::string::npos)
      << table.out;
  // verify counts them (the reader checked each).
  const auto verify = run_command(tracetool + " verify " + shell_quoted(path("t.din.zst")));
  EXPECT_EQ(verify.exit_code, 0) << verify.err;
  EXPECT_EQ(verify.out, "OK: 5500 records, 3 animation frames, 6 data frames, 3 treelet maps\n");
  // Container to container keeps them; plain records drop them, saying so.
  const auto kept = run_command(tracetool + " convert --records xdin " + shell_quoted(path("t.din.zst")) + " " +
                                shell_quoted(path("t.xdin.zst")));
  ASSERT_EQ(kept.exit_code, 0) << kept.err;
  EXPECT_EQ(kept.err, "");
  EXPECT_EQ(maps_read({}, path("t.xdin.zst")), maps_written());
  for (const char* plain : {"t.din", "t.xdin", "t.bin"}) {
    const auto dropped =
        run_command(tracetool + " convert " + shell_quoted(path("t.din.zst")) + " " + shell_quoted(path(plain)));
    ASSERT_EQ(dropped.exit_code, 0) << dropped.err;
    EXPECT_NE(dropped.err.find("3 animation-frame markers (per-frame K and --per-frame need them) and 3 treelet maps "
                               "(cachesim --prefetch treelet needs them)"),
              std::string::npos)
        << plain << ": " << dropped.err;
  }
}

TEST_F(TreeletMaps, VerifyRefusesABadMapWithExitOne) {
  const std::string good = write_markers_only("good.din.zst");
  const auto payloads = map_payloads(good);
  write_file(path("bad.din.zst"), with_map_payload(good, 0, plain_payload({1, 8, 2 << 1 | 1, 0})));
  const auto result = run_command(shell_quoted(program("tracetool")) + " verify " + shell_quoted(path("bad.din.zst")));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_EQ(result.err.rfind(fmt::format("tracetool verify: {}: treelet map of animation frame 0 at byte {}: treelet 1 "
                                         "of 1, 0x0 + 16 bytes, lies outside the frame's node addresses",
                                         path("bad.din.zst"), payloads[0].first - 8),
                             0),
            0u)
      << result.err;
}

}  // namespace
}  // namespace nodetrace::formats
