// The nodetrace Python module: bindings over the libraries' public headers
// (formats, tracer, cachesim), with no logic of their own.
#include <pybind11/pybind11.h>

#include "errors.hpp"
#include "record_array.hpp"
#include "render.hpp"
#include "simulate.hpp"
#include "trace_file.hpp"

PYBIND11_MODULE(nodetrace, module) {
  module.doc() = "nodetrace: read node-fetch traces, render scenes and simulate node caches from Python.";
  module.attr("__version__") = NODETRACE_VERSION;
  nodetrace::python::register_errors(module);
  nodetrace::python::register_record_dtype(module);
  nodetrace::python::bind_trace_file(module);
  nodetrace::python::bind_render(module);
  nodetrace::python::bind_simulate(module);
}
