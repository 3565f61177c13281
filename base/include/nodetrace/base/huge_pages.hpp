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

}  // namespace nodetrace::base
