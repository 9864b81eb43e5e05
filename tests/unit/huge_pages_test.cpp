// support/HugePages: the arena the shape engines' largest tables live in, the reserve that
// faults its blocks in on another thread, and the allocator standard containers use it through.
#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <deque>
#include <thread>
#include <vector>

#include "support/HugePages.h"

using lcjit::support::HugePageAllocator;
using lcjit::support::HugePageArena;
using lcjit::support::HugePageReserve;

namespace {

const size_t kPage = size_t(sysconf(_SC_PAGESIZE));

// Whether [p, p + bytes) is mapped (mincore fails with ENOMEM on a hole), and how many of its
// pages are in memory.
bool mapped(void* p, size_t bytes, size_t* resident = nullptr) {
  uintptr_t from = reinterpret_cast<uintptr_t>(p) / kPage * kPage;
  size_t pages = (reinterpret_cast<uintptr_t>(p) + bytes - from + kPage - 1) / kPage;
  std::vector<unsigned char> in(pages);
  if (mincore(reinterpret_cast<void*>(from), pages * kPage, in.data()) != 0) return false;
  if (resident) {
    *resident = 0;
    for (unsigned char c : in) *resident += c & 1;
  }
  return true;
}

TEST(HugePageArena, SmallRequestsAreAlignedApartAndWritable) {
  HugePageArena arena;
  std::vector<std::pair<char*, size_t>> taken;
  size_t total = 0;
  for (size_t k = 0; total < 3 * HugePageArena::kBlock; ++k) {  // over several blocks
    const size_t bytes = 1 + (k * 7919) % 5000, align = size_t(1) << (k % 7);
    char* p = static_cast<char*>(arena.take(bytes, align));
    EXPECT_EQ(reinterpret_cast<uintptr_t>(p) % align, 0u);
    std::memset(p, int(k & 0xff), bytes);
    taken.push_back({p, bytes});
    total += bytes;
  }
  // Each still holds what was written into it: no two overlap.
  for (size_t k = 0; k < taken.size(); ++k)
    for (size_t i = 0; i < taken[k].second; ++i) ASSERT_EQ(uint8_t(taken[k].first[i]), uint8_t(k & 0xff)) << k;
}

TEST(HugePageArena, ALargeRequestIsItsOwnMappingGivenBackAtOnce) {
  HugePageArena arena;
  const size_t bytes = 3 * HugePageArena::kBlock + 5;
  void* p = arena.take(bytes, 8);
  std::memset(p, 1, bytes);
  EXPECT_TRUE(mapped(p, bytes));
  arena.give(p, bytes);
  EXPECT_FALSE(mapped(p, bytes));
  // A small one is kept until the arena ends.
  void* q = arena.take(64, 8);
  arena.give(q, 64);
  EXPECT_TRUE(mapped(q, 64));
}

TEST(HugePageReserve, ItsBlocksAreInMemoryBeforeTheyAreTaken) {
  HugePageReserve reserve(4);
  void* block = nullptr;
  while (!(block = reserve.takeBlock())) std::this_thread::yield();  // its thread makes the first
  size_t resident = 0;
  ASSERT_TRUE(mapped(block, HugePageArena::kBlock, &resident));
  EXPECT_EQ(resident, HugePageArena::kBlock / kPage);
  EXPECT_EQ(static_cast<char*>(block)[HugePageArena::kBlock - 1], 0);
  munmap(block, HugePageArena::kBlock);  // a taken block is the taker's
}

TEST(HugePageReserve, AnArenaFedFromItTakesItsReadyBlocks) {
  HugePageReserve reserve(4);
  HugePageArena arena;
  arena.feedFrom(&reserve);
  // Each round starts a new block: mapped by the arena itself (nothing in memory yet) until the
  // reserve's thread has one ready, which is in memory as it is taken.
  while (true) {
    void* p = arena.take(HugePageArena::kBlock / 2, 64);
    size_t resident = 0;
    ASSERT_TRUE(mapped(p, HugePageArena::kBlock / 2, &resident));
    if (resident == HugePageArena::kBlock / 2 / kPage) break;  // from the reserve
    std::this_thread::yield();
    arena.take(HugePageArena::kBlock / 2 + 1, 64);  // more than is left: the next round's block
  }
  arena.feedFrom(nullptr);
}

TEST(HugePageAllocator, StandardContainersGrowOnIt) {
  std::deque<int64_t, HugePageAllocator<int64_t>> d;
  std::vector<int64_t, HugePageAllocator<int64_t>> v;  // past kBlock: old buffers given back
  for (int64_t k = 0; k < 1000000; ++k) d.push_back(k * 3), v.push_back(k * 5);
  for (int64_t k = 0; k < 1000000; k += 997) {
    EXPECT_EQ(d[size_t(k)], k * 3);
    EXPECT_EQ(v[size_t(k)], k * 5);
  }
  // Copies share an arena; each default-made allocator has its own.
  HugePageAllocator<int> a, b;
  HugePageAllocator<double> c(a);
  EXPECT_TRUE(a == c);
  EXPECT_FALSE(a == b);
  EXPECT_EQ(&a.arena(), &c.arena());
}

}  // namespace
