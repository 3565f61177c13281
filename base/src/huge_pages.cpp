#include "nodetrace/base/huge_pages.hpp"

#include <sys/mman.h>

#include <cstdint>

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

}  // namespace nodetrace::base
