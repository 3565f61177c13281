// A JSON value (a trace's header, trailer, a marker) as the Python object
// json.loads gives for its text: dicts, lists, ints, floats, str, None.
#pragma once

#include <pybind11/pybind11.h>

#include <nlohmann/json.hpp>

namespace nodetrace::python {

inline pybind11::object to_python(const nlohmann::json& value) {
  return pybind11::module_::import("json").attr("loads")(value.dump());
}

}  // namespace nodetrace::python
