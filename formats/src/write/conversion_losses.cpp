#include "nodetrace/formats/write/conversion_losses.hpp"

#include <fmt/format.h>

namespace nodetrace::formats {

namespace {

std::string records_text(std::uint64_t count) { return fmt::format("{} record{}", count, count == 1 ? "" : "s"); }

}  // namespace

ConversionLosses::ConversionLosses(const TraceReader& input, RecordForm output_form, bool container_output)
    : source_(input.source_name()), input_form_(input.form()), output_form_(output_form) {
  header_lost_ = !container_output && input.header().present();
  if (header_lost_) {
    row_sampled_ = input.header().sampling().has_value();
    had_layout_ = input.header().json.contains("layout");
    units_ = input.units();
  }
}

void ConversionLosses::count(const std::vector<Record>& records) {
  if (output_form_ == RecordForm::Din && input_form_ != RecordForm::Din) {
    for (const Record& record : records) sizes_lost_ += record.size != 4;
  }
  if (output_form_ == RecordForm::Binary) {
    for (const Record& record : records) {
      tags_lost_ += record.tag != kTagNone;
      units_lost_ += unit_index(record.unit) != 0;
    }
  }
}

void ConversionLosses::count(const RecordBatch& batch) {
  if (header_lost_) {
    markers_lost_ += batch.marker.has_value();
    windows_lost_ += batch.window.has_value();
    treelet_maps_lost_ += batch.marker && batch.marker->treelets;
  }
  count(batch.records);
}

std::vector<std::string> ConversionLosses::warnings() const {
  std::vector<std::string> out;
  if (sizes_lost_ > 0) {
    out.push_back(fmt::format("{}: {} had sizes other than 4 bytes, which din records cannot carry: Dinero IV and "
                              "cachesim read every din record as 4 bytes (write xdin, --records xdin, to keep them)",
                              source_, records_text(sizes_lost_)));
  }
  if (tags_lost_ > 0) {
    out.push_back(fmt::format("{}: {} lost their tags (node levels, p, t): Dinero binary records carry none, so "
                              "the split scheme cannot route them (write din or xdin to keep them)",
                              source_, records_text(tags_lost_)));
  }
  if (units_lost_ > 0) {
    out.push_back(fmt::format("{}: {} lost their traversal unit: Dinero binary records carry none",
                              source_, records_text(units_lost_)));
  }
  if (header_lost_) {
    std::vector<std::string> lost;
    if (row_sampled_) lost.push_back("its row sampling (cachesim would report the records as a full run)");
    if (had_layout_) lost.push_back("its layout (K = auto needs it)");
    // Binary output says so per record above; text keeps the field, unread.
    if (units_ > 1 && output_form_ != RecordForm::Binary) {
      lost.push_back(fmt::format("its {} traversal units (each line keeps its unit field, but a trace without a "
                                 "header is read as one unit: cachesim --units private needs them)",
                                 units_));
    }
    if (markers_lost_ > 0) {
      lost.push_back(fmt::format("{} animation-frame marker{} (per-frame K and --per-frame need them)", markers_lost_,
                                 markers_lost_ == 1 ? "" : "s"));
    }
    if (treelet_maps_lost_ > 0) {
      lost.push_back(fmt::format("{} treelet map{} (cachesim --prefetch treelet needs them)", treelet_maps_lost_,
                                 treelet_maps_lost_ == 1 ? "" : "s"));
    }
    if (windows_lost_ > 0) {
      lost.push_back(fmt::format("{} sample-window marker{}", windows_lost_, windows_lost_ == 1 ? "" : "s"));
    }
    std::string list;
    for (std::size_t i = 0; i < lost.size(); ++i) {
      list += (i == 0 ? "" : i + 1 == lost.size() ? " and " : ", ") + lost[i];
    }
    if (!lost.empty()) {
      out.push_back(fmt::format("{}: plain records keep no header: lost {} (write a container, a *.zst name, to "
                                "keep them)",
                                source_, list));
    }
  }
  return out;
}

}  // namespace nodetrace::formats
