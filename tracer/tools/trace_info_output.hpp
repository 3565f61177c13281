// tracer render --trace-info FILE: what a study needs to know of a trace it
// does not keep. For each layout, once the render is over, a JSON object
// {"header": ..., "totals": ...}: the container header its trace carries and
// the render's totals of its trailer (rays by kind, node fetches, ...), the
// keys `tracetool info --format json` shows them under.
#pragma once

#include <string>
#include <vector>

#include "nodetrace/tracer/render/record_sink.hpp"

namespace nodetrace::tracer::tools {

// `files[i]`: layout i's file (written under the output rules).
RecordSinkMaker trace_info_maker(std::vector<std::string> files);

}  // namespace nodetrace::tracer::tools
