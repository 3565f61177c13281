#include "nodetrace/base/huge_pages.hpp"

#include <sys/mman.h>

#include <algorithm>
#include <cstdint>
#include <thread>
#include <vector>

namespace nodetrace::base {

void ask_for_huge_pages(void* start, std::size_t size) {
#ifdef MADV_HUGEPAGE
  constexpr std::uintptr_t kHugePage = std::uintptr_t{2} << 20;
  const auto first = reinterpret_cast<std::uintptr_t>(start);
  const auto begin = (first + kHugePage - 1) & ~(kHugePage - 1);
  const auto end = (first + size) & ~(kHugePage - 1);
  if (end > begin) ::madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
  (void)start;
  (void)size;
#endif
}

void touch_pages_in_parallel(void* start, std::size_t size, unsigned threads) {
  constexpr std::size_t kPage = 4096;
  // Below this, a thread costs more than the zeroing it would share.
  constexpr std::size_t kLeastShare = std::size_t{4} << 20;
  threads = static_cast<unsigned>(std::clamp<std::size_t>(size / kLeastShare, 1, std::max(threads, 1u)));
  if (threads < 2) return;  // the filling thread touches the pages itself
  auto* const bytes = static_cast<volatile unsigned char*>(start);
  const auto touch = [&](unsigned share) {
    const std::size_t begin = size / threads * share;
    const std::size_t end = share + 1 == threads ? size : size / threads * (share + 1);
    for (std::size_t at = begin; at < end; at += kPage) bytes[at] = 0;
  };
  std::vector<std::thread> others;
  for (unsigned share = 1; share < threads; ++share) others.emplace_back(touch, share);
  touch(0);
  for (auto& other : others) other.join();
}

}  // namespace nodetrace::base
