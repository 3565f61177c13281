#include "record_array.hpp"

#include <pybind11/numpy.h>

namespace nodetrace::python {

pybind11::array to_array(RecordVector&& records) {
  auto* owned = new RecordVector(std::move(records));
  pybind11::capsule free_when_done(owned, [](void* p) { delete static_cast<RecordVector*>(p); });
  return pybind11::array_t<ArrayRecord>(static_cast<pybind11::ssize_t>(owned->size()), owned->data(), free_when_done);
}

void register_record_dtype(pybind11::module_& module) {
  PYBIND11_NUMPY_DTYPE(ArrayRecord, address, size, kind, unit, level, frame);
  module.attr("RECORD_DTYPE") = pybind11::dtype::of<ArrayRecord>();
  module.attr("TAG_PRIMITIVE_LIST") = formats::kTagPrimitiveList;
  module.attr("TAG_TRIANGLE") = formats::kTagTriangle;
  module.attr("TAG_NONE") = formats::kTagNone;
  module.attr("MAX_LEVEL") = formats::kMaxLevel;
}

}  // namespace nodetrace::python
