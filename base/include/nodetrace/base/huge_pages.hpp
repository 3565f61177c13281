// Large arrays on huge pages where the system has them (transparent huge
// pages in `madvise` mode, Debian's default): the first touch of each 4 KiB
// page of a large, freshly allocated array costs more than filling it, and a
// short render (a row sample, a tree from the tree cache) is mostly such
// first touches.
#pragma once

#include <cstddef>
#include <vector>

namespace nodetrace::base {

// Advice only: asks for huge pages for the whole 2 MiB pages inside
// [start, start + size); a system without them changes nothing.
void ask_for_huge_pages(void* start, std::size_t size);

// Reserves room for `count` elements in `values` and asks for huge pages for
// it before any of it is touched (a large reservation is fresh memory).
template <class T, class Allocator>
void reserve_on_huge_pages(std::vector<T, Allocator>& values, std::size_t count) {
  values.reserve(count);
  ask_for_huge_pages(values.data(), values.capacity() * sizeof(T));
}

// Touches each 4 KiB page of [start, start + size) once (writing a zero to
// its first byte), the range cut into `threads` shares touched at once. The
// kernel zeroes a fresh page on its first touch: a large array then filled by
// one thread (a resize, a copy) would pay all of that zeroing alone. Only for
// memory that holds no values yet and that will be filled.
void touch_pages_in_parallel(void* start, std::size_t size, unsigned threads);

// reserve_on_huge_pages, with the room past the vector's current values
// touched by `threads` threads at once: for an array about to be filled to
// `count` by one thread.
template <class T, class Allocator>
void reserve_touched_on_huge_pages(std::vector<T, Allocator>& values, std::size_t count, unsigned threads) {
  reserve_on_huge_pages(values, count);
  touch_pages_in_parallel(values.data() + values.size(), (values.capacity() - values.size()) * sizeof(T), threads);
}

}  // namespace nodetrace::base
