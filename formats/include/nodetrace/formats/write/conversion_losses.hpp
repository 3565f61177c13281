// What a conversion drops (tracetool convert and cat): a form without a field
// the input filled (din has no size, binary no tag or unit), and plain output,
// which keeps no header, animation-frame markers (nor their treelet maps) or
// sample windows. Nothing
// is dropped without a word (docs/ARCHITECTURE.md "Trace records").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "nodetrace/formats/read/trace_reader.hpp"
#include "nodetrace/formats/record/record.hpp"

namespace nodetrace::formats {

class ConversionLosses {
 public:
  // `input` is the trace converted; the output has records of `output_form`,
  // in a container (else plain records).
  ConversionLosses(const TraceReader& input, RecordForm output_form, bool container_output);

  // Counts what one batch loses: call for every batch written, before any
  // filtering that the user asked for (those records are not lost).
  void count(const RecordBatch& batch);
  void count(const std::vector<Record>& records);

  // One sentence for each kind of loss, naming how many records or markers
  // it touched and its consequence; empty when nothing was lost.
  std::vector<std::string> warnings() const;

 private:
  std::string source_;
  RecordForm input_form_;
  RecordForm output_form_;
  bool header_lost_ = false;
  bool row_sampled_ = false;
  bool had_layout_ = false;
  unsigned units_ = 1;             // the traversal units a lost header said the records carry
  std::uint64_t sizes_lost_ = 0;   // din output: records of another size than din's 4
  std::uint64_t tags_lost_ = 0;    // binary output: tagged records
  std::uint64_t units_lost_ = 0;   // binary output: records of units above 0
  std::uint64_t markers_lost_ = 0;
  std::uint64_t windows_lost_ = 0;
  std::uint64_t treelet_maps_lost_ = 0;
};

}  // namespace nodetrace::formats
