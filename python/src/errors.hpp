// The library's errors as Python exceptions, with the programs' messages:
// bad usage (base::UsageError, an option parse error) ValueError, as exit 2;
// files (base::IoError) OSError; bad or damaged data (base::FormatError)
// nodetrace.FormatError, a subclass of ValueError, as exit 1; a scene that
// cannot be read or used (tracer::SceneError, a missing scene file included)
// nodetrace.SceneError, a subclass of ValueError.
#pragma once

#include <pybind11/pybind11.h>

namespace nodetrace::python {

void register_errors(pybind11::module_& module);

}  // namespace nodetrace::python
