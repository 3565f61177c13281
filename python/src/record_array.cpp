#include "record_array.hpp"

#include <pybind11/numpy.h>
#include <sys/mman.h>

#include <algorithm>
#include <new>

namespace nodetrace::python {

pybind11::array to_array(RecordVector&& records) {
  auto* owned = new RecordVector(std::move(records));
  pybind11::capsule free_when_done(owned, [](void* p) { delete static_cast<RecordVector*>(p); });
  return pybind11::array_t<ArrayRecord>(static_cast<pybind11::ssize_t>(owned->size()), owned->data(), free_when_done);
}

namespace {

std::size_t mapped_bytes(std::size_t capacity) { return capacity * sizeof(ArrayRecord); }

// Huge pages for the whole mapping, not base::ask_for_huge_pages' whole 2 MiB
// pages inside it: advice on part of a mapping splits it in two, and mremap
// does not grow a range that spans more than one mapping.
void ask_for_huge_pages_on_all(void* start, std::size_t size) {
#ifdef MADV_HUGEPAGE
  ::madvise(start, size, MADV_HUGEPAGE);
#endif
}

}  // namespace

// At least one record: mmap takes no empty mapping.
RecordBuffer::RecordBuffer(std::size_t capacity) : capacity_(std::max<std::size_t>(capacity, 1)) {
  void* mapped = ::mmap(nullptr, mapped_bytes(capacity_), PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (mapped == MAP_FAILED) throw std::bad_alloc();
  data_ = static_cast<ArrayRecord*>(mapped);
  ask_for_huge_pages_on_all(data_, mapped_bytes(capacity_));
}

RecordBuffer::~RecordBuffer() { ::munmap(data_, mapped_bytes(capacity_)); }

void RecordBuffer::grow(std::size_t capacity) {
  void* moved = ::mremap(data_, mapped_bytes(capacity_), mapped_bytes(capacity), MREMAP_MAYMOVE);
  if (moved == MAP_FAILED) throw std::bad_alloc();
  data_ = static_cast<ArrayRecord*>(moved);
  capacity_ = capacity;
  ask_for_huge_pages_on_all(data_, mapped_bytes(capacity_));
}

void RecordBuffer::append(std::span<const formats::Record> records, std::uint64_t frame) {
  if (size_ + records.size() > capacity_) grow(std::max(2 * capacity_, size_ + records.size()));
  write_records(data_ + size_, records, frame);
  size_ += records.size();
}

pybind11::array to_array(std::unique_ptr<RecordBuffer> records) {
  RecordBuffer* owned = records.release();
  pybind11::capsule free_when_done(owned, [](void* p) { delete static_cast<RecordBuffer*>(p); });
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
