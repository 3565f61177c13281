// Trace records as a numpy structured array, one element per record:
// address (uint64), size (uint32: bytes; din records 4, as Dinero IV reads
// them), kind (uint8: the access type, din's label 0-5), unit (uint8: the
// traversal unit), level (uint16: the node level, or the tag values
// TAG_PRIMITIVE_LIST, TAG_TRIANGLE, TAG_NONE), frame (uint64: the animation
// frame of the marker before the record; 0 in a trace without markers).
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <memory>
#include <new>
#include <utility>
#include <span>
#include <vector>

#include "nodetrace/formats/record/record.hpp"

namespace nodetrace::python {

struct ArrayRecord {
  std::uint64_t address;
  std::uint32_t size;
  std::uint8_t kind;
  std::uint8_t unit;
  std::uint16_t level;
  std::uint64_t frame;
};

// A vector whose resize leaves the new records unwritten (they are written
// next): value-initialising them first would write the array twice.
template <class T>
struct UninitializedAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = UninitializedAllocator<U>;
  };
  template <class U>
  void construct(U* place) noexcept {
    ::new (static_cast<void*>(place)) U;
  }
  template <class U, class... Args>
  void construct(U* place, Args&&... args) {
    ::new (static_cast<void*>(place)) U(std::forward<Args>(args)...);
  }
};
using RecordVector = std::vector<ArrayRecord, UninitializedAllocator<ArrayRecord>>;

inline void write_records(ArrayRecord* to, std::span<const formats::Record> records, std::uint64_t frame) {
  for (const formats::Record& r : records) {
    *to++ = {r.address, r.size, static_cast<std::uint8_t>(r.type), static_cast<std::uint8_t>(formats::unit_index(r.unit)),
             r.tag, frame};
  }
}

inline void append_records(RecordVector& out, std::span<const formats::Record> records, std::uint64_t frame) {
  const std::size_t start = out.size();
  out.resize(start + records.size());
  write_records(out.data() + start, records, frame);
}

// The whole read's array: mapped memory on huge pages, grown in place by
// mremap when the trace did not say how many records it holds (a plain
// trace): the kernel moves the pages, where a vector's growth would copy
// every record and hold both copies at its peak.
class RecordBuffer {
 public:
  explicit RecordBuffer(std::size_t capacity);
  RecordBuffer(const RecordBuffer&) = delete;
  RecordBuffer& operator=(const RecordBuffer&) = delete;
  ~RecordBuffer();
  void append(std::span<const formats::Record> records, std::uint64_t frame);
  ArrayRecord* data() const { return data_; }
  std::size_t size() const { return size_; }

 private:
  void grow(std::size_t capacity);
  ArrayRecord* data_ = nullptr;
  std::size_t size_ = 0;
  std::size_t capacity_ = 0;
};

inline void append_records(RecordBuffer& out, std::span<const formats::Record> records, std::uint64_t frame) {
  out.append(records, frame);
}

// The records as the inverse: what simulate() takes from arrays.
inline formats::Record to_record(const ArrayRecord& r) {
  formats::Record record;
  record.address = r.address;
  record.size = r.size;
  record.type = static_cast<formats::AccessType>(r.kind);
  record.unit = formats::traversal_unit(r.unit);
  record.tag = r.level;
  return record;
}

// The array owns the vector's memory, or the mapping (no copy).
pybind11::array to_array(RecordVector&& records);
pybind11::array to_array(std::unique_ptr<RecordBuffer> records);

void register_record_dtype(pybind11::module_& module);

}  // namespace nodetrace::python
