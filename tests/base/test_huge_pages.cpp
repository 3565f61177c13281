#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "nodetrace/base/huge_pages.hpp"

namespace nodetrace::base {
namespace {

constexpr std::uintptr_t kHugePage = std::uintptr_t{2} << 20;

// The VmFlags of the mapping that holds `address`, from /proc/self/smaps.
std::string mapping_flags(std::uintptr_t address) {
  std::ifstream smaps("/proc/self/smaps");
  bool inside = false;
  for (std::string line; std::getline(smaps, line);) {
    std::uintptr_t begin = 0, end = 0;
    char dash = 0;
    std::istringstream range(line);
    if (range >> std::hex >> begin >> dash >> end && dash == '-') {
      inside = begin <= address && address < end;
    } else if (inside && line.starts_with("VmFlags:")) {
      return line;
    }
  }
  return "";
}

TEST(HugePages, ReservationHoldsTheCountAndLeavesTheVectorEmpty) {
  std::vector<std::uint64_t> values{1, 2, 3};
  values.clear();
  reserve_on_huge_pages(values, 3'000'000);
  EXPECT_TRUE(values.empty());
  EXPECT_GE(values.capacity(), 3'000'000u);
  values.assign(3'000'000, 7);
  EXPECT_EQ(values.front(), 7u);
  EXPECT_EQ(values.back(), 7u);
}

TEST(HugePages, TheWholeHugePagesOfAReservationAreAdvisedAsHuge) {
  if (!std::filesystem::exists("/sys/kernel/mm/transparent_hugepage/enabled")) {
    GTEST_SKIP() << "this kernel has no transparent huge pages: the advice is a no-op";
  }
  std::vector<char> bytes;
  reserve_on_huge_pages(bytes, 8 * kHugePage);
  const auto start = reinterpret_cast<std::uintptr_t>(bytes.data());
  const std::uintptr_t first_whole = (start + kHugePage - 1) & ~(kHugePage - 1);
  EXPECT_NE(mapping_flags(first_whole).find(" hg"), std::string::npos) << mapping_flags(first_whole);
}

TEST(HugePages, ARangeWithNoWholeHugePageIsLeftAlone) {
  std::vector<char> bytes(4096, 'x');
  ask_for_huge_pages(bytes.data(), bytes.size());
  ask_for_huge_pages(nullptr, 0);
  EXPECT_EQ(std::string(bytes.begin(), bytes.end()), std::string(4096, 'x'));
}

// How many of the pages of [start, start + size) are in memory (mincore).
std::size_t resident_pages(const void* start, std::size_t size) {
  const auto page = static_cast<std::uintptr_t>(::sysconf(_SC_PAGESIZE));
  const auto first = reinterpret_cast<std::uintptr_t>(start) & ~(page - 1);
  const std::size_t pages = (reinterpret_cast<std::uintptr_t>(start) + size - first + page - 1) / page;
  std::vector<unsigned char> in_memory(pages);
  if (::mincore(reinterpret_cast<void*>(first), pages * page, in_memory.data()) != 0) return 0;
  std::size_t resident = 0;
  for (unsigned char flag : in_memory) resident += flag & 1;
  return resident;
}

TEST(HugePages, ATouchedReservationIsInMemoryBeforeItIsFilledAndKeepsTheValuesBefore) {
  std::vector<std::uint32_t> values{5, 6, 7};
  const std::size_t count = 24u << 20;  // 96 MiB: large enough for every thread's share
  reserve_touched_on_huge_pages(values, count, 2);
  ASSERT_GE(values.capacity(), count);
  EXPECT_EQ(values, (std::vector<std::uint32_t>{5, 6, 7}));
  const auto page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
  const std::size_t room_pages = count * sizeof(std::uint32_t) / page;
  EXPECT_GE(resident_pages(values.data(), count * sizeof(std::uint32_t)), room_pages);
}

TEST(HugePages, AnUntouchedReservationIsNotInMemoryYet) {
  // The counterpart that makes the test above mean something: fresh memory
  // is not resident until touched.
  std::vector<std::uint32_t> values;
  const std::size_t count = 24u << 20;
  reserve_on_huge_pages(values, count);
  EXPECT_LT(resident_pages(values.data(), count * sizeof(std::uint32_t)), count * sizeof(std::uint32_t) / 4096 / 2);
}

TEST(HugePages, TouchingWithOneThreadOrASmallRangeLeavesItToTheFiller) {
  // Fresh anonymous mappings: none of their pages is in memory before a touch.
  const auto fresh = [](std::size_t size) {
    void* const start = ::mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    EXPECT_NE(start, MAP_FAILED);
    return start;
  };
  constexpr std::size_t kMiB = std::size_t{1} << 20;
  const std::size_t pages_of_16 = 16 * kMiB / static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
  void* const one_thread = fresh(16 * kMiB);
  touch_pages_in_parallel(one_thread, 16 * kMiB, 1);
  EXPECT_EQ(resident_pages(one_thread, 16 * kMiB), 0u);
  void* const small = fresh(6 * kMiB);  // under two shares of 4 MiB
  touch_pages_in_parallel(small, 6 * kMiB, 2);
  EXPECT_EQ(resident_pages(small, 6 * kMiB), 0u);
  void* const large = fresh(16 * kMiB);  // two shares: touched
  touch_pages_in_parallel(large, 16 * kMiB, 2);
  EXPECT_EQ(resident_pages(large, 16 * kMiB), pages_of_16);
  for (void* start : {one_thread, large}) ::munmap(start, 16 * kMiB);
  ::munmap(small, 6 * kMiB);
}

}  // namespace
}  // namespace nodetrace::base
