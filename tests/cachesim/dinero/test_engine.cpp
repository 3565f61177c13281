// The Dinero-IV-exact engine on small reference streams whose results are
// worked out by hand in the comments.
#include <gtest/gtest.h>

#include <vector>

#include "nodetrace/cachesim/dinero/engine.hpp"
#include "nodetrace/base/error.hpp"

namespace nodetrace::cachesim {
namespace {

using formats::AccessType;
using formats::Record;

constexpr int kRead = 0, kWrite = 1, kInstr = 2;

Record read(std::uint64_t address, std::uint32_t size = 4) {
  return Record{address, size, AccessType::Read, formats::TraversalUnit{}, formats::kTagNone};
}
Record write(std::uint64_t address, std::uint32_t size = 4) {
  return Record{address, size, AccessType::Write, formats::TraversalUnit{}, formats::kTagNone};
}
Record of_type(AccessType type, std::uint64_t address, std::uint32_t size = 4) {
  return Record{address, size, type, formats::TraversalUnit{}, formats::kTagNone};
}

CacheConfig cache(std::uint64_t size, std::uint32_t block, std::uint32_t assoc,
                  ReplacementPolicy replacement = ReplacementPolicy::Lru) {
  CacheConfig c;
  c.size = size;
  c.block_size = block;
  c.assoc = assoc;
  c.replacement = replacement;
  return c;
}

Stats run(const HierarchyConfig& config, const std::vector<Record>& records, bool finish = true) {
  Hierarchy h(config);
  for (const Record& r : records) h.access(r);
  if (finish) h.finish();
  return h.stats(1, config.levels[0].unified ? CacheKind::Unified : CacheKind::Data);
}

TEST(Engine, DirectMappedConflictsAndHits) {
  // 4 sets of 8 bytes: 0 and 32 share set 0; 8 is in set 1.
  const Stats s = run(single_level(cache(32, 8, 1)), {read(0), read(32), read(0), read(8), read(12)});
  EXPECT_EQ(s.fetches[kRead], 5u);
  EXPECT_EQ(s.misses[kRead], 4u);  // 0, 32, 0 again, 8; 12 hits 8's block
  EXPECT_EQ(s.block_misses[kRead], 4u);
  EXPECT_EQ(s.bytes_from_memory, 32u);
  EXPECT_EQ(s.bytes_to_memory, 0u);
}

TEST(Engine, LruKeepsTheRecentlyUsedBlock) {
  // One set of two ways. A B A C B: C evicts B (least recently used), B misses.
  const Stats s = run(single_level(cache(16, 8, 2)), {read(0), read(8), read(0), read(16), read(8)});
  EXPECT_EQ(s.misses[kRead], 4u);
}

TEST(Engine, FifoEvictsTheOldestInsertion) {
  // A B A C B: C evicts A (inserted first, the hit does not count), B hits.
  const Stats s = run(single_level(cache(16, 8, 2, ReplacementPolicy::Fifo)),
                      {read(0), read(8), read(0), read(16), read(8)});
  EXPECT_EQ(s.misses[kRead], 3u);
}

TEST(Engine, RandomIsDeterministicAndBeatsLruOnACycle) {
  // Cycling over three blocks in two ways: LRU misses every time; random
  // keeps a block now and then.
  std::vector<Record> cycle;
  for (int i = 0; i < 300; ++i) cycle.push_back(read(static_cast<std::uint64_t>(i % 3) * 8));
  const Stats lru = run(single_level(cache(16, 8, 2)), cycle);
  const Stats random1 = run(single_level(cache(16, 8, 2, ReplacementPolicy::Random)), cycle);
  const Stats random2 = run(single_level(cache(16, 8, 2, ReplacementPolicy::Random)), cycle);
  EXPECT_EQ(lru.misses[kRead], 300u);
  EXPECT_LT(random1.misses[kRead], 300u);
  EXPECT_GE(random1.misses[kRead], 3u);
  EXPECT_EQ(random1, random2);
}

TEST(Engine, WriteBackWriteAllocate) {
  // Two sets of 8 bytes. Write 0 allocates (fetches 8) and dirties; read 16
  // evicts it (writes back 8) and fetches 8. The end copy-back finds nothing.
  const Stats s = run(single_level(cache(16, 8, 1)), {write(0), read(16)});
  EXPECT_EQ(s.misses[kWrite], 1u);
  EXPECT_EQ(s.misses[kRead], 1u);
  EXPECT_EQ(s.bytes_from_memory, 16u);
  EXPECT_EQ(s.bytes_to_memory, 8u);
}

TEST(Engine, FinishCopiesBackDirtyBlocks) {
  // A dirty block left at the end is written back by finish(), as Dinero does.
  HierarchyConfig config = single_level(cache(16, 8, 1));
  Hierarchy h(config);
  h.access(write(0));
  EXPECT_EQ(h.stats(1, CacheKind::Unified).bytes_to_memory, 0u);
  h.finish();
  EXPECT_EQ(h.stats(1, CacheKind::Unified).bytes_to_memory, 8u);
}

TEST(Engine, WriteThroughNoAllocate) {
  // Write 0 misses and is not allocated: 4 bytes written through, nothing
  // fetched. Read 0 misses (8 fetched). Write 0 hits and writes through 4.
  CacheConfig c = cache(16, 8, 1);
  c.write_allocate = WriteAllocate::Never;
  c.write_back = WriteBack::Never;
  const Stats s = run(single_level(c), {write(0), read(0), write(0)});
  EXPECT_EQ(s.fetches[kWrite], 2u);
  EXPECT_EQ(s.misses[kWrite], 1u);
  EXPECT_EQ(s.misses[kRead], 1u);
  EXPECT_EQ(s.bytes_from_memory, 8u);
  EXPECT_EQ(s.bytes_to_memory, 8u);
}

TEST(Engine, SubBlocksFetchOnlyWhatIsMissing) {
  // 16-byte blocks of four 4-byte sub-blocks. Read 0: block miss, fetch 4.
  // Read 4: sub-block miss in a present block, fetch 4. Read 0: hit.
  CacheConfig c = cache(64, 16, 1);
  c.sub_block_size = 4;
  const Stats s = run(single_level(c), {read(0), read(4), read(0)});
  EXPECT_EQ(s.misses[kRead], 2u);
  EXPECT_EQ(s.block_misses[kRead], 1u);
  EXPECT_EQ(s.bytes_from_memory, 8u);
}

TEST(Engine, WriteAllocateNoFetchSkipsTheFetchOfAWholeSubBlock) {
  // A 4-byte write covering a whole sub-block is allocated without a fetch;
  // a 2-byte one is not allocated and goes to memory as a write-through.
  CacheConfig c = cache(64, 16, 1);
  c.sub_block_size = 4;
  c.write_allocate = WriteAllocate::NoFetch;
  const Stats s = run(single_level(c), {write(0, 4), write(32, 2)}, false);
  EXPECT_EQ(s.misses[kWrite], 2u);
  EXPECT_EQ(s.bytes_from_memory, 0u);
  EXPECT_EQ(s.bytes_to_memory, 2u);  // the unallocated write, written through
}

TEST(Engine, MultiBlockReferencesCountOneFetchPerBlock) {
  // 4 bytes at 6 span blocks 0 and 8: two fetches, two misses, one split.
  const Stats s = run(single_level(cache(64, 8, 1)), {read(6, 4)});
  EXPECT_EQ(s.fetches[kRead], 2u);
  EXPECT_EQ(s.misses[kRead], 2u);
  EXPECT_EQ(s.multi_block_refs, 1u);
}

TEST(Engine, ALongReferenceIsOneFetchPerBlock) {
  // 0xFFFF bytes from 0 over 4-byte blocks: 16384 blocks, 16383 splits.
  const Stats s = run(single_level(cache(1024, 4, 1)), {read(0, 0xFFFF)});
  EXPECT_EQ(s.fetches[kRead], 16384u);
  EXPECT_EQ(s.multi_block_refs, 16383u);
  EXPECT_EQ(s.bytes_from_memory, 65536u);
}

TEST(Engine, DinRoundingKeepsAReferenceInOneBlock) {
  // Read through the din view, address 6 becomes 4 with size 4: one block.
  Hierarchy h(single_level(cache(64, 8, 1)));
  const std::vector<Record> records{read(6, 4)};
  EXPECT_EQ(h.access_batch(records, formats::RecordForm::Din), 1u);
  EXPECT_EQ(h.stats(1, CacheKind::Unified).fetches[kRead], 1u);
  EXPECT_EQ(h.stats(1, CacheKind::Unified).multi_block_refs, 0u);
}

TEST(Engine, MissClassification) {
  // Two sets of one 8-byte block. 0, 8, 16 are compulsory; 16 evicted 0 from
  // set 0. A fully associative LRU cache of two blocks then holds {8, 16},
  // so 0 again is a capacity miss. Then 16 misses in the direct-mapped
  // cache but a two-block LRU cache holds {16, 0}: a conflict miss.
  CacheConfig c = cache(16, 8, 1);
  c.classify_misses = true;
  const Stats s = run(single_level(c), {read(0), read(8), read(16), read(0), read(16)});
  EXPECT_EQ(s.misses[kRead], 5u);
  EXPECT_EQ(s.compulsory[kRead], 3u);
  EXPECT_EQ(s.capacity[kRead], 1u);
  EXPECT_EQ(s.conflict[kRead], 1u);
}

TEST(Engine, ThreeLevels) {
  // L1: 2 sets x 8 B; L2: 4 sets x 8 B; L3: 8 sets x 8 B. Reads 0 16 0 16:
  // 0 and 16 collide in L1 (4 misses) but not in L2 (2 misses, 2 hits);
  // L3 sees L2's two misses.
  HierarchyConfig config;
  for (std::uint64_t size : {16, 32, 64}) {
    LevelConfig level;
    level.unified = cache(size, 8, 1);
    config.levels.push_back(level);
  }
  Hierarchy h(config);
  for (std::uint64_t a : {0, 16, 0, 16}) h.access(read(a));
  h.finish();
  EXPECT_EQ(h.stats(1, CacheKind::Unified).misses[kRead], 4u);
  EXPECT_EQ(h.stats(1, CacheKind::Unified).bytes_from_memory, 32u);
  EXPECT_EQ(h.stats(2, CacheKind::Unified).fetches[kRead], 4u);
  EXPECT_EQ(h.stats(2, CacheKind::Unified).misses[kRead], 2u);
  EXPECT_EQ(h.stats(3, CacheKind::Unified).fetches[kRead], 2u);
  EXPECT_EQ(h.stats(3, CacheKind::Unified).misses[kRead], 2u);
  EXPECT_EQ(h.stats(3, CacheKind::Unified).bytes_from_memory, 16u);
}

TEST(Engine, WriteBacksReachTheNextLevel) {
  // L1 write-back: the eviction of dirty block 0 is a write of 8 bytes at L2.
  HierarchyConfig config;
  LevelConfig l1, l2;
  l1.unified = cache(16, 8, 1);
  l2.unified = cache(64, 8, 1);
  config.levels = {l1, l2};
  Hierarchy h(config);
  h.access(write(0));
  h.access(read(16));
  EXPECT_EQ(h.stats(2, CacheKind::Unified).fetches[kRead], 2u);  // the two miss fetches
  EXPECT_EQ(h.stats(2, CacheKind::Unified).fetches[kWrite], 1u);  // the write-back
}

TEST(Engine, AMissFetchReachesTheNextLevelBeforeItsWriteThrough) {
  // L1 write-through with write-allocate: a 4-byte write miss to an 8-byte
  // block queues a write-through and then a fetch of the block; Dinero sends
  // the last queued first, so the one-block L2 misses on the fetch (a read)
  // and the write-through then hits.
  HierarchyConfig config;
  LevelConfig l1, l2;
  l1.unified = cache(16, 8, 1);
  l1.unified->write_back = WriteBack::Never;
  l2.unified = cache(8, 8, 1);
  config.levels = {l1, l2};
  Hierarchy h(config);
  h.access(write(0));
  const Stats& s2 = h.stats(2, CacheKind::Unified);
  EXPECT_EQ(s2.fetches[kRead], 1u);
  EXPECT_EQ(s2.fetches[kWrite], 1u);
  EXPECT_EQ(s2.misses[kRead], 1u);
  EXPECT_EQ(s2.misses[kWrite], 0u);
}

TEST(Engine, DirtySubBlocksAreWrittenBackInContiguousRuns) {
  // One 16-byte block of four sub-blocks. Writes to sub-blocks 0 and 2 need
  // no fetch and dirty them; evicting the block writes two runs of 4 bytes.
  HierarchyConfig config;
  LevelConfig l1, l2;
  l1.unified = cache(16, 16, 1);
  l1.unified->sub_block_size = 4;
  l2.unified = cache(256, 16, 1);
  config.levels = {l1, l2};
  Hierarchy h(config);
  h.access(write(0));
  h.access(write(8));
  h.access(read(64));
  const Stats& s1 = h.stats(1, CacheKind::Unified);
  EXPECT_EQ(s1.misses[kWrite], 2u);
  EXPECT_EQ(s1.block_misses[kWrite], 1u);
  EXPECT_EQ(s1.bytes_to_memory, 8u);
  EXPECT_EQ(s1.bytes_from_memory, 4u);  // only the read's sub-block
  EXPECT_EQ(h.stats(2, CacheKind::Unified).fetches[kWrite], 2u);
}

TEST(Engine, SeparateInstructionAndDataCaches) {
  // Instruction fetches go to the i-cache; with only a d-cache they go
  // straight to memory and the d-cache never sees them.
  HierarchyConfig split;
  LevelConfig level;
  level.instruction = cache(64, 8, 1);
  level.data = cache(64, 8, 1);
  split.levels = {level};
  Hierarchy h(split);
  h.access(of_type(AccessType::InstructionFetch, 0));
  h.access(read(0));
  EXPECT_EQ(h.stats(1, CacheKind::Instruction).fetches[kInstr], 1u);
  EXPECT_EQ(h.stats(1, CacheKind::Data).fetches[kInstr], 0u);
  EXPECT_EQ(h.stats(1, CacheKind::Data).misses[kRead], 1u);

  Hierarchy data_only(single_level(cache(64, 8, 1), CacheKind::Data));
  data_only.access(of_type(AccessType::InstructionFetch, 0));
  EXPECT_EQ(data_only.stats(1, CacheKind::Data).demand_fetches(), 0u);
}

TEST(Engine, CopyBackAndInvalidateRecordsAreNotDemandFetches) {
  // Copy-back of a dirty block writes it back; invalidate drops a block so
  // the next read misses. Neither counts as a fetch.
  const Stats s = run(single_level(cache(64, 8, 1)),
                      {write(0), of_type(AccessType::CopyBack, 0), read(8),
                       of_type(AccessType::Invalidate, 8), read(8)},
                      false);
  EXPECT_EQ(s.demand_fetches(), 3u);
  EXPECT_EQ(s.bytes_to_memory, 8u);
  EXPECT_EQ(s.misses[kRead], 2u);
}

TEST(Engine, SkipCount) {
  HierarchyConfig config = single_level(cache(64, 8, 1));
  config.skip_count = 2;
  Hierarchy h(config);
  for (std::uint64_t a : {0, 8, 16, 24, 0}) h.access(read(a));
  EXPECT_EQ(h.references_skipped(), 2u);
  EXPECT_EQ(h.references_simulated(), 3u);
  EXPECT_EQ(h.stats(1, CacheKind::Unified).misses[kRead], 3u);  // 16, 24, 0 (0 was skipped)
}

TEST(Engine, MaxCount) {
  HierarchyConfig config = single_level(cache(64, 8, 1));
  config.max_count = 3;
  Hierarchy h(config);
  EXPECT_TRUE(h.access(read(0)));
  EXPECT_TRUE(h.access(read(8)));
  EXPECT_TRUE(h.access(read(16)));
  EXPECT_FALSE(h.max_count_exceeded());
  EXPECT_FALSE(h.access(read(24)));
  EXPECT_TRUE(h.max_count_exceeded());
  EXPECT_EQ(h.stats(1, CacheKind::Unified).demand_fetches(), 3u);
}

TEST(Engine, FlushCountEmptiesTheCache) {
  // Flushing every 2 references: 0 misses, hits, is flushed, misses again.
  HierarchyConfig config = single_level(cache(64, 8, 1));
  config.flush_count = 2;
  const Stats s = run(config, {read(0), read(0), read(0), read(0)});
  EXPECT_EQ(s.misses[kRead], 2u);
  // A flush copies dirty blocks back.
  const Stats w = run(config, {write(0), read(8)}, false);
  EXPECT_EQ(w.bytes_to_memory, 8u);
}

TEST(Engine, TriggersDiscardOutsideTheWindow) {
  HierarchyConfig config = single_level(cache(64, 8, 1));
  config.on_trigger = 0x100;
  config.off_trigger = 0x200;
  Hierarchy h(config);
  for (std::uint64_t a : {0x8, 0x100, 0x10, 0x18, 0x200, 0x20}) h.access(read(a));
  EXPECT_EQ(h.references_simulated(), 2u);  // 0x10 and 0x18
  EXPECT_TRUE(h.trigger_toggled());
}

TEST(Engine, ImpossibleGeometryIsAUsageError) {
  auto fails = [](CacheConfig c) {
    EXPECT_THROW(Hierarchy{single_level(c)}, base::UsageError) << c.size << "/" << c.block_size;
  };
  fails(cache(1000, 8, 1));      // size not a power of two
  fails(cache(1024, 12, 1));     // block not a power of two
  fails(cache(1024, 16, 3));     // size not a multiple of block x assoc
  fails(cache(64, 16, 8));       // assoc above the 4 blocks
  fails(cache(8, 16, 1));        // smaller than one block
  CacheConfig sub = cache(1024, 16, 1);
  sub.sub_block_size = 32;       // larger than the block
  fails(sub);
  sub.sub_block_size = 6;        // not a power of two
  fails(sub);
  sub = cache(4096, 256, 1);
  sub.sub_block_size = 4;        // 64 sub-blocks per block
  fails(sub);

  HierarchyConfig mixed;
  LevelConfig level;
  level.unified = cache(64, 8, 1);
  level.data = cache(64, 8, 1);
  mixed.levels = {level};
  EXPECT_THROW(Hierarchy{mixed}, base::UsageError);
  HierarchyConfig too_deep;
  LevelConfig u;
  u.unified = cache(64, 8, 1);
  too_deep.levels.assign(6, u);
  EXPECT_THROW(Hierarchy{too_deep}, base::UsageError);
  EXPECT_THROW(Hierarchy{HierarchyConfig{}}, base::UsageError);
}

TEST(Engine, StatsOfAnAbsentCacheThrow) {
  Hierarchy h(single_level(cache(64, 8, 1), CacheKind::Data));
  EXPECT_FALSE(h.has_cache(1, CacheKind::Unified));
  EXPECT_THROW(h.stats(1, CacheKind::Unified), std::out_of_range);
  EXPECT_THROW(h.stats(2, CacheKind::Data), std::out_of_range);
}

}  // namespace
}  // namespace nodetrace::cachesim
