// tracetool: inspect, print, verify and convert traces (formats/FORMAT.md).
// Exit codes: 0 success, 1 bad data, 2 bad usage.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <new>
#include <string>
#include <vector>

#include "nodetrace/cli/archive_option.hpp"
#include "nodetrace/cli/number_range.hpp"
#include "nodetrace/cli/command_line.hpp"
#include "nodetrace/cli/csv_text.hpp"
#include "nodetrace/cli/format_option.hpp"
#include "nodetrace/cli/exit_status.hpp"
#include "nodetrace/cli/subcommand_dispatch.hpp"
#include "nodetrace/base/error.hpp"
#include "nodetrace/cli/option_limits.hpp"
#include "nodetrace/cli/progress_line.hpp"
#include "nodetrace/cli/zstd_level_option.hpp"
#include "nodetrace/formats/read/observed_totals.hpp"
#include "nodetrace/formats/read/trace_reader.hpp"
#include "nodetrace/formats/record/record_summary.hpp"
#include "nodetrace/base/standard_output.hpp"
#include "nodetrace/formats/record/tag_filter.hpp"
#include "nodetrace/formats/write/conversion_losses.hpp"
#include "nodetrace/formats/write/trace_output.hpp"
#include "nodetrace/formats/write/trace_writer.hpp"

namespace base = nodetrace::base;
namespace cli = nodetrace::cli;
namespace formats = nodetrace::formats;
using formats::Record;

namespace {

formats::ReaderOptions reader_options(bool tags_are_levels, std::optional<formats::RecordForm> form,
                                      unsigned threads = 0) {
  formats::ReaderOptions options;
  options.tags_are_levels = tags_are_levels;
  options.form = form;
  options.threads = threads;
  return options;
}

std::optional<formats::RecordForm> form_option(const std::string& name) {
  if (name.empty()) return std::nullopt;
  return formats::parse_form_name(name);
}

// docs/ARCHITECTURE.md: a trace without animation-frame markers is one
// animation frame (info and verify count alike).
std::uint64_t animation_frame_count(std::uint64_t markers) { return std::max<std::uint64_t>(markers, 1); }

void print_warnings(const formats::ConversionLosses& losses) {
  for (const std::string& warning : losses.warnings()) fmt::print(stderr, "tracetool: warning: {}\n", warning);
}

// A conversion keeps only the fields it read: say how many records lost
// others (docs/ARCHITECTURE.md: simulation ignores them, a conversion says so).
void warn_of_dropped_fields(const formats::TraceReader& reader) {
  const std::uint64_t dropped = reader.records_with_ignored_fields();
  if (dropped == 0) return;
  fmt::print(stderr,
             "tracetool: warning: {}: {} record{} had fields after the {} (e.g. a level tag) that were dropped; "
             "pass --tags-are-levels to keep a tag field of node levels\n",
             reader.source_name(), dropped, dropped == 1 ? "" : "s",
             reader.form() == formats::RecordForm::ExtendedDin ? "size" : "address");
}

// One animation frame's treelet map as info shows it.
nlohmann::json treelet_map_info(const formats::AnimationFrameMarker& marker) {
  return {{"frame", marker.frame},
          {"treelets", marker.treelets->treelets.size()},
          {"bytes", formats::treelet_map_frame_bytes(*marker.treelets)}};
}

// The treelet maps of a seekable container, read without its data frames.
nlohmann::json treelet_maps_of(const std::string& path, formats::ReaderOptions options) {
  options.keep_data_frame = [](const formats::DataFrameIndexEntry&) { return false; };
  auto reader = formats::TraceReader::open(path, options);
  nlohmann::json maps = nlohmann::json::array();
  formats::RecordBatch batch;
  while (reader->next(batch)) {
    if (batch.marker && batch.marker->treelets) maps.push_back(treelet_map_info(*batch.marker));
  }
  return maps;
}

int run_info(const std::string& path, const std::string& format, bool tags_are_levels, const std::string& form) {
  auto reader = formats::TraceReader::open(path, reader_options(tags_are_levels, form_option(form)));
  const bool maps = reader->header().carries_treelet_maps();
  nlohmann::json info = nlohmann::json::object();
  info["file"] = reader->source_name();
  info["kind"] = std::string(reader->input_kind());
  info["records_form"] = std::string(formats::form_name(reader->form()));
  info["tags"] = reader->tags_are_levels() ? "node-level" : "none";
  if (reader->units() > 1) info["units"] = reader->units();
  if (reader->header().present()) {
    const nlohmann::json& header = reader->header().json;
    info["header"] = header;
    // The tracer's acceleration structure: named by the header's "accel";
    // a kd-tree trace has none (its header predates BVHs) but a "kdtree".
    if (header.contains("accel") && header["accel"].is_object() && header["accel"].contains("name")) {
      info["accel"] = header["accel"]["name"];
    } else if (header.contains("kdtree")) {
      info["accel"] = "kdtree";
    }
  }
  const auto& trailer = reader->trailer();
  if (trailer && trailer->totals.contains("records") && trailer->totals.contains("record_bytes")) {
    // A seekable container: everything is in the trailer.
    info["records"] = trailer->totals["records"];
    info["records_per_tag"] = trailer->totals.value("records_per_tag", nlohmann::json::object());
    info["records_per_type"] = trailer->totals.value("records_per_type", nlohmann::json::object());
    info["animation_frames"] = animation_frame_count(trailer->totals.value("animation_frames", std::uint64_t{0}));
    info["data_frames"] = trailer->index.size();
    info["decompressed_bytes"] = trailer->totals["record_bytes"];
    info["totals"] = trailer->totals;
    if (maps) info["treelet_maps"] = treelet_maps_of(path, reader_options(tags_are_levels, form_option(form)));
  } else {
    formats::ObservedTotals seen;
    formats::RecordBatch batch;
    nlohmann::json treelet_maps = nlohmann::json::array();
    while (reader->next(batch)) {
      seen.add(batch);
      if (batch.marker && batch.marker->treelets) treelet_maps.push_back(treelet_map_info(*batch.marker));
    }
    if (maps) info["treelet_maps"] = treelet_maps;
    info["records"] = seen.summary().records();
    info["records_per_tag"] = seen.summary().records_per_tag();
    info["records_per_type"] = seen.summary().records_per_type();
    info["animation_frames"] = animation_frame_count(seen.animation_frame_markers());
    info["data_frames"] = reader->trailer() ? reader->trailer()->index.size() : 0;
    info["decompressed_bytes"] = reader->record_bytes();
    if (reader->trailer()) info["totals"] = reader->trailer()->totals;
  }
  std::error_code error;
  const auto file_size = path == "-" ? 0 : std::filesystem::file_size(path, error);
  if (path != "-" && !error) info["file_bytes"] = file_size;
  const auto records = info["records"].get<std::uint64_t>();
  if (info.contains("file_bytes") && records > 0) {
    info["bytes_per_record"] = static_cast<double>(file_size) / static_cast<double>(records);
  }
  if (info.contains("treelet_maps")) {
    std::uint64_t map_bytes = 0;
    for (const auto& map : info["treelet_maps"]) map_bytes += map["bytes"].get<std::uint64_t>();
    info["treelet_map_bytes"] = map_bytes;
  }
  if (format == "json") {
    fmt::print("{}\n", info.dump(2));
    return 0;
  }
  if (format == "csv") {
    fmt::print("{}", cli::field_value_csv(info));
    return 0;
  }
  const auto row = [](std::string_view key, const std::string& value) { fmt::print("{:<20} {}\n", key, value); };
  row("file", info["file"].get<std::string>());
  row("kind", info["kind"].get<std::string>());
  row("records form", info["records_form"].get<std::string>());
  row("tags", info["tags"].get<std::string>());
  if (info.contains("accel")) row("accel", info["accel"].is_string() ? info["accel"].get<std::string>() : info["accel"].dump());
  if (info.contains("units")) row("units", info["units"].dump());
  if (info.contains("header")) {
    for (const auto& [key, value] : info["header"].items()) row("header." + key, value.dump());
  }
  row("records", std::to_string(records));
  row("animation frames", info["animation_frames"].dump());
  row("data frames", info["data_frames"].dump());
  if (info.contains("file_bytes")) row("file bytes", info["file_bytes"].dump());
  row("decompressed bytes", info["decompressed_bytes"].dump());
  if (info.contains("bytes_per_record")) row("bytes per record", fmt::format("{:.3f}", info["bytes_per_record"].get<double>()));
  if (info.contains("treelet_maps")) {
    row("treelet map bytes", info["treelet_map_bytes"].dump());
    fmt::print("treelet maps\n");
    for (const auto& map : info["treelet_maps"]) {
      fmt::print("  frame {:<12} {} treelets, {} bytes\n", map["frame"].dump(), map["treelets"].dump(),
                 map["bytes"].dump());
    }
  }
  fmt::print("records per type\n");
  for (const auto& [key, value] : info["records_per_type"].items()) fmt::print("  {:<18} {}\n", key, value.dump());
  fmt::print("records per tag\n");
  for (const auto& [key, value] : formats::ordered_tag_counts(info["records_per_tag"])) fmt::print("  {:<18} {}\n", key, value);
  if (info.contains("totals")) {
    for (const auto& [key, value] : info["totals"].items()) {
      if (key == "records" || key == "records_per_tag" || key == "records_per_type" || key == "animation_frames" ||
          key == "data_frames" || key == "record_bytes")
        continue;
      row("totals." + key, value.dump());
    }
  }
  return 0;
}

int run_cat(const std::string& path, const std::string& tags, const std::string& records_form,
            std::optional<unsigned> unit, bool tags_are_levels, const std::string& form) {
  auto reader = formats::TraceReader::open(path, reader_options(tags_are_levels, form_option(form)));
  if (unit && *unit >= reader->units()) {
    throw base::UsageError(
        reader->units() > 1
            ? fmt::format("{}: --unit {}: the trace has traversal units 0 to {}", reader->source_name(), *unit,
                          reader->units() - 1)
            : fmt::format("{}: --unit {}: the trace's records carry no unit (its header says no \"units\" above 1)",
                          reader->source_name(), *unit));
  }
  std::optional<formats::TagFilter> filter;
  if (!tags.empty()) {
    filter = formats::TagFilter::parse(tags);
    if (!reader->tags_are_levels()) {
      throw base::UsageError(fmt::format(
          "{}: --tags filters by node level, but this trace's tags are not marked as node levels "
          "(no \"tag\": \"node-level\" in a header); pass --tags-are-levels if its tag field holds levels",
          reader->source_name()));
    }
  }
  formats::WriterOptions options;
  options.form = formats::choose_output_form("-", form_option(records_form), reader->form());
  options.kind = formats::OutputKind::Plain;
  if (options.form == formats::RecordForm::Binary) base::refuse_binary_on_terminal("-", "binary records");
  formats::ConversionLosses losses(*reader, options.form, false);
  options.threads = 1;
  // All units keep their field (the text zstdcat shows); one unit's records
  // are a trace of one unit, without it.
  if (!unit && options.form != formats::RecordForm::Binary) options.units = reader->units();
  auto writer = formats::TraceWriter::create("-", nlohmann::json::object(), options);
  // Din has no size field (every record reads as 4 bytes); a container's
  // header knows its nodes' size, so node records written as extended din
  // (or binary) get that size rather than din's 4.
  std::optional<std::uint32_t> node_size;
  if (reader->form() == formats::RecordForm::Din && options.form != formats::RecordForm::Din &&
      reader->header().present() && reader->tags_are_levels() && reader->header().json.contains("layout")) {
    node_size = static_cast<std::uint32_t>(reader->header().layout().node_size);
  }
  formats::RecordBatch batch;
  std::vector<Record> kept;
  while (reader->next(batch)) {
    if (!filter && !node_size && !unit) {
      losses.count(batch.records);
      writer->write(batch.records);
      continue;
    }
    kept.clear();
    for (Record record : batch.records) {
      if (filter && !filter->keeps(record.tag)) continue;
      if (unit && formats::unit_index(record.unit) != *unit) continue;
      if (node_size && formats::is_level(record.tag)) record.size = *node_size;
      kept.push_back(record);
    }
    losses.count(kept);
    writer->write(kept);
  }
  writer->finish();
  warn_of_dropped_fields(*reader);
  print_warnings(losses);
  return 0;
}

int run_verify(const std::string& path, bool tags_are_levels, const std::string& form) {
  auto reader = formats::TraceReader::open(path, reader_options(tags_are_levels, form_option(form)));
  formats::RecordBatch batch;
  formats::ObservedTotals seen;
  std::uint64_t treelet_maps = 0;  // each checked by the reader (FORMAT.md 2.2.2)
  while (reader->next(batch)) {
    seen.add(batch);
    treelet_maps += batch.marker && batch.marker->treelets;
  }
  seen.check_trailer(*reader);
  const std::uint64_t records = seen.summary().records();
  const std::uint64_t animation_frames = animation_frame_count(seen.animation_frame_markers());
  if (reader->input_kind() == "container") {
    const std::uint64_t data_frames = reader->trailer() ? reader->trailer()->index.size() : 0;
    fmt::print("OK: {} records, {} animation frame{}, {} data frame{}{}\n", records, animation_frames,
               animation_frames == 1 ? "" : "s", data_frames, data_frames == 1 ? "" : "s",
               reader->header().carries_treelet_maps()
                   ? fmt::format(", {} treelet map{}", treelet_maps, treelet_maps == 1 ? "" : "s")
                   : "");
  } else {
    const std::string form_words = reader->form() == formats::RecordForm::Binary ? "Dinero binary"
                                                                                 : std::string(formats::form_name(reader->form())) + " text";
    fmt::print("OK: {} records, {} animation frame{} (a plain {}{} trace: every record parses; it has no checksums "
               "of ours)\n",
               records, animation_frames, animation_frames == 1 ? "" : "s",
               reader->input_kind() == "zstd" ? "zstd-compressed " : "", form_words);
  }
  return 0;
}

struct ConvertOptions {
  std::string records;
  std::string form;
  int zstd_level = 3;
  unsigned threads = 0;
  std::uint64_t frame_records = 1u << 20;
  bool tags_are_levels = false;
  bool address16 = false;
  bool archive = false;
};

int run_convert(const std::string& in, const std::string& out, const ConvertOptions& convert) {
  cli::check_thread_count(convert.threads, "--threads");
  auto reader =
      formats::TraceReader::open(in, reader_options(convert.tags_are_levels, form_option(convert.form), convert.threads));
  formats::WriterOptions options;
  const formats::TraceOutput output = formats::decide_trace_output(
      out, formats::OutputKind::Auto,
      formats::choose_output_form(out, form_option(convert.records), reader->form()));
  options.form = output.form;
  base::refuse_binary_on_terminal(out, output.container ? "a trace" : "binary records");
  options.zstd_level = convert.zstd_level;
  options.threads = convert.threads;
  options.records_per_data_frame = convert.frame_records;
  options.tags_are_levels = reader->tags_are_levels();
  options.units = reader->units();
  options.address_digits = convert.address16 ? 16 : 8;
  // A container keeps the treelet maps; plain output drops them (losses say so).
  options.treelet_maps = output.container && reader->header().carries_treelet_maps();
  if (convert.archive) formats::use_archive_setting(options);
  // The producer's part of the header travels along; the writer sets the rest.
  nlohmann::json header = reader->header().json;
  for (const char* key : {"container", "records", "tag", "trailer"}) header.erase(key);
  auto writer = formats::TraceWriter::create(out, header, options);
  formats::ConversionLosses losses(*reader, options.form, output.container);
  cli::ProgressLine progress_line;
  const std::optional<std::uint64_t> total =
      reader->trailer() && reader->trailer()->totals.contains("records")
          ? std::optional<std::uint64_t>(reader->trailer()->totals["records"].get<std::uint64_t>())
          : std::nullopt;
  std::uint64_t records = 0;
  formats::RecordBatch batch;
  while (reader->next(batch)) {
    if (batch.marker) writer->begin_animation_frame(*batch.marker);
    if (batch.window) writer->begin_window(*batch.window);
    losses.count(batch);
    writer->write(batch.records);
    records += batch.records.size();
    if (progress_line.shown()) progress_line.update_count("converting " + reader->source_name(), records, total, "records");
  }
  if (reader->trailer()) {
    nlohmann::json totals = reader->trailer()->totals;
    for (const char* key : {"records", "records_per_tag", "records_per_type", "animation_frames", "sample_windows",
                            "data_frames", "record_bytes"})
      totals.erase(key);
    if (options.form == reader->form()) writer->add_totals(totals);
  }
  writer->finish();
  progress_line.clear();
  warn_of_dropped_fields(*reader);
  print_warnings(losses);
  return 0;
}

constexpr const char* kUsage =
    "tracetool: inspect, print, verify and convert nodetrace / Dinero IV traces\n"
    "\n"
    "Usage:\n"
    "  tracetool info FILE [options]     metadata and index summary of a trace\n"
    "  tracetool cat FILE [options]      print records, optionally filtered by tag\n"
    "  tracetool verify FILE [options]   check every checksum, the index, frame order and the record hash\n"
    "  tracetool convert IN OUT [options]\n"
    "                                    convert any readable trace to a container (OUT *.zst or -) or\n"
    "                                    plain records\n"
    "  tracetool --version               the version, as trace headers record it\n"
    "\n"
    "`tracetool SUBCOMMAND --help` describes each.\n";

const std::vector<std::string> kForms = {"din", "xdin", "binary"};

// The record form of plain input: --informat, as in cachesim and Dinero IV.
void add_informat_option(CLI::App& app, std::string& form) {
  app.add_option("--informat", form,
                 "Record form of plain input: din, xdin or binary (default: detected; binary from a .bin or "
                 ".bin.zst name)")
      ->check(CLI::IsMember(kForms));
}

// The record form of the output: --records, as in tracer render (--to is the
// old name, kept as an alias).
void add_records_option(CLI::App& app, std::string& form, const char* unnamed) {
  app.add_option("--records,--to", form,
                 fmt::format("Output record form: din, xdin or binary (default: {}); --to is an alias", unnamed))
      ->check(CLI::IsMember(kForms));
}

// The options every subcommand reads a trace with.
struct InputOptions {
  std::string form;
  bool tags_are_levels = false;

  void add_to(CLI::App& app) {
    app.add_flag("--tags-are-levels", tags_are_levels, "Read a plain trace's tag field as node levels");
    add_informat_option(app, form);
  }
};

struct InfoCommand {
  std::string path, format = "table";
  InputOptions input;
  void add_options(CLI::App& app) {
    app.add_option("FILE", path, "Trace file, or - for standard input")->required();
    cli::add_format_option(app, format, "json: one object, csv: one table field,value");
    input.add_to(app);
  }
  int run() const {
    return cli::exit_status_of("tracetool info", [&] { return run_info(path, format, input.tags_are_levels, input.form); });
  }
};

struct CatCommand {
  std::string path, tags, records_form;
  std::optional<unsigned> unit;
  InputOptions input;
  void add_options(CLI::App& app) {
    app.add_option("FILE", path, "Trace file, or - for standard input")->required();
    app.add_option("--tags", tags, "Keep these tags: levels, ranges and p / t, e.g. 0-3,9-,p");
    app.add_option("--unit", unit,
                   "Keep the records of this traversal unit (0-based; a trace whose header says \"units\"), "
                   "written without the unit field");
    add_records_option(app, records_form, "the input's");
    input.add_to(app);
  }
  int run() const {
    return cli::exit_status_of("tracetool cat", [&] { return run_cat(path, tags, records_form, unit, input.tags_are_levels, input.form); });
  }
};

struct VerifyCommand {
  std::string path;
  InputOptions input;
  void add_options(CLI::App& app) {
    app.add_option("FILE", path, "Trace file, or - for standard input")->required();
    input.add_to(app);
  }
  int run() const {
    return cli::exit_status_of("tracetool verify", [&] { return run_verify(path, input.tags_are_levels, input.form); });
  }
};

struct ConvertCommand {
  std::string in, out;
  ConvertOptions options;
  void add_options(CLI::App& app) {
    app.add_option("IN", in, "Input trace, or - for standard input")->required();
    app.add_option("OUT", out, "Output: *.zst or - for a container, any other name for plain records")->required();
    auto* level = cli::add_zstd_level_option(app, options.zstd_level);
    add_records_option(app, options.records, "what OUT's name says (.din, .xdin, .bin, each with or without .zst), "
                       "else the input's");
    app.add_flag("--tags-are-levels", options.tags_are_levels, "The input's tag field holds node levels");
    app.add_option("--threads", options.threads, "Compression and decoding threads (0: one per core; at most 16 per core)");
    // At most 2^24 records per data frame: each compressing thread buffers a
    // data frame's text, up to a few hundred MB at that size.
    auto* frame_records =
        app.add_option("--frame-records", options.frame_records, "Records per data frame (1 to 16777216)")
            ->check(cli::NumberRange(std::uint64_t{1}, std::uint64_t{1} << 24));
    cli::add_archive_flag(app, options.archive, level, frame_records);
    app.add_flag("--address16", options.address16, "Write 16 hex address digits instead of 8");
    add_informat_option(app, options.form);
  }
  int run() const {
    return cli::exit_status_of("tracetool convert", [&] { return run_convert(in, out, options); });
  }
};

int run(int argc, char** argv) {
  return cli::dispatch_subcommand(
      "tracetool", kUsage, argc, argv,
      {{"info", [](int c, char** v) { return cli::run_command<InfoCommand>("tracetool info", "Metadata and index summary of a trace", c, v); }},
       {"cat", [](int c, char** v) { return cli::run_command<CatCommand>("tracetool cat", "Print records, optionally filtered by tag", c, v); }},
       {"verify", [](int c, char** v) { return cli::run_command<VerifyCommand>("tracetool verify", "Check every checksum, the index, frame order and the record hash", c, v); }},
       {"convert", [](int c, char** v) { return cli::run_command<ConvertCommand>("tracetool convert", "Convert any readable trace to a container (OUT *.zst or -) or plain records", c, v); }}});
}

}  // namespace

int main(int argc, char** argv) { return base::finish_standard_output("tracetool", run(argc, argv)); }
