// nodetrace.render(): see render.cpp.
#pragma once

#include <pybind11/pybind11.h>

namespace nodetrace::python {

void bind_render(pybind11::module_& module);

}  // namespace nodetrace::python
