// nodetrace.simulate(): see simulate.cpp.
#pragma once

#include <pybind11/pybind11.h>

namespace nodetrace::python {

void bind_simulate(pybind11::module_& module);

}  // namespace nodetrace::python
