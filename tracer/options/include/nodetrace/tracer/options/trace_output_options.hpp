// The options of `tracer render` that say which records a render writes and
// how: -o, --records, --streams, --zstd-level and --archive, and their
// translation into the trace job. Shared by the front end and the Python
// module's render(), so both take the same names and values.
#pragma once

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <optional>
#include <string>
#include <string_view>

#include "nodetrace/base/error.hpp"
#include "nodetrace/cli/archive_option.hpp"
#include "nodetrace/cli/zstd_level_option.hpp"
#include "nodetrace/formats/write/trace_output.hpp"
#include "nodetrace/tracer/options/render_options.hpp"
#include "nodetrace/tracer/render/trace_job.hpp"

namespace nodetrace::tracer::tools {

struct TraceOutputOptions {
  std::string output, records_name, streams = "nodes";
  // The container's default level 3: on the default scene level 1 writes the
  // trace only about 10% faster for 6% more bytes, and at 3 a trace is no
  // larger than `zstd -3` makes of its text.
  int zstd_level = 3;
  bool archive = false;
  CLI::Option* output_option = nullptr;
};

inline void add_trace_output_option(CLI::App& app, TraceOutputOptions& o) {
  o.output_option = app.add_option("-o,--output", o.output,
                                   "trace file (.din.zst, .xdin.zst, .din, .xdin, .bin) or - for standard output; "
                                   "without it nothing is written (render only)");
  app.add_option("--records", o.records_name, "record form: din, xdin or binary (default: from the file name)")
      ->check(CLI::IsMember({"din", "xdin", "binary"}));
}

inline void add_trace_record_options(CLI::App& app, TraceOutputOptions& o) {
  app.add_option("--streams", o.streams,
                 "records to write, comma-separated: nodes, lists (leaf primitive lists, tag p), "
                 "triangles (tag t)")
      ->capture_default_str();
  cli::add_archive_flag(app, o.archive, cli::add_zstd_level_option(app, o.zstd_level));
}

// A BVH node is larger than din's 4 bytes: unless --records says
// otherwise its fetches are written as extended din, with the node's size,
// so Dinero IV counts the bytes each fetch reads. A name that asks for din
// is refused rather than given xdin records.
inline void choose_bvh_record_form(TraceJobOptions& options, const std::string& output, bool form_named) {
  if (options.accel == AccelKind::KdTree || form_named || options.render.addresses.node_size <= 4) return;
  if (options.form != formats::RecordForm::Din) return;
  const auto ends_with = [&](std::string_view suffix) {
    return output.size() >= suffix.size() && output.compare(output.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  if (ends_with(".din") || ends_with(".din.zst")) {
    throw base::UsageError(fmt::format("--accel {}: {}-byte nodes are written as extended din (din reads every "
                                       "fetch as 4 bytes): name the trace .xdin.zst, or give --records din",
                                       accel_name(options.accel), options.render.addresses.node_size));
  }
  options.form = formats::RecordForm::ExtendedDin;
}

// The record form, streams and compression into the job (its output names
// are set by make_job_options).
inline void apply_trace_output(const TraceOutputOptions& o, TraceJobOptions& options) {
  options.zstd_level = o.zstd_level;
  options.archive = o.archive;
  std::optional<formats::RecordForm> named_form;
  if (!o.records_name.empty()) named_form = formats::parse_form_name(o.records_name);
  options.form = formats::choose_output_form(o.output, named_form, formats::RecordForm::Din);
  choose_bvh_record_form(options, o.output, named_form.has_value());
  options.render.streams = parse_streams(o.streams);
}

}  // namespace nodetrace::tracer::tools
