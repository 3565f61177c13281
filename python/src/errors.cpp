#include "errors.hpp"

#include <CLI/CLI.hpp>

#include <cstring>

#include "nodetrace/base/error.hpp"
#include "nodetrace/tracer/scene/scene_loader.hpp"

namespace nodetrace::python {

namespace {

// Messages quote damaged bytes as they are: bytes that are not UTF-8 are
// shown as backslash escapes rather than losing the message.
void set_error(PyObject* type, const char* message) {
  PyObject* text = PyUnicode_DecodeUTF8(message, static_cast<Py_ssize_t>(std::strlen(message)), "backslashreplace");
  PyErr_SetObject(type, text);
  Py_XDECREF(text);
}

}  // namespace

void register_errors(pybind11::module_& module) {
  static pybind11::exception<base::FormatError> format_error(module, "FormatError", PyExc_ValueError);
  format_error.doc() = "Bad or damaged trace data; the message names the file and the record or byte.";
  static pybind11::exception<tracer::SceneError> scene_error(module, "SceneError", PyExc_ValueError);
  scene_error.doc() = "A scene that cannot be read or used; the message names the file and line.";
  pybind11::register_exception_translator([](std::exception_ptr error) {
    try {
      if (error) std::rethrow_exception(error);
    } catch (const base::FormatError& e) {
      set_error(format_error.ptr(), e.what());
    } catch (const tracer::SceneError& e) {
      set_error(scene_error.ptr(), e.what());
    } catch (const base::IoError& e) {
      set_error(PyExc_OSError, e.what());
    } catch (const base::UsageError& e) {
      set_error(PyExc_ValueError, e.what());
    } catch (const CLI::ParseError& e) {
      set_error(PyExc_ValueError, e.what());
    }
  });
}

}  // namespace nodetrace::python
