// HugePageReserve and HugePageArena (HugePages.h): mappings advised to the kernel as huge pages.
#include "support/HugePages.h"

#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <new>

namespace lcjit::support {
namespace {

size_t roundUp(size_t n, size_t to) { return (n + to - 1) / to * to; }

// A fresh mapping of whole 2 MiB pages. The kernel places mappings of that size on 2 MiB
// boundaries itself (since Linux 6.7); on older ones part of it may stay in small pages.
void* mapHuge(size_t bytes) {
  void* at = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (at == MAP_FAILED) throw std::bad_alloc();
  madvise(at, bytes, MADV_HUGEPAGE);  // only advice: without it the pages are small, no more
  return at;
}

}  // namespace

// ---- HugePageReserve ----

HugePageReserve::HugePageReserve(size_t keepReady) : keepReady_(keepReady), thread_([this] { fill(); }) {}

HugePageReserve::~HugePageReserve() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  taken_.notify_one();
  thread_.join();
  for (void* block : ready_) munmap(block, HugePageArena::kBlock);
}

void* HugePageReserve::takeBlock() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (ready_.empty()) return nullptr;
  void* block = ready_.back();
  ready_.pop_back();
  ++takenCount_;
  taken_.notify_one();
  return block;
}

void HugePageReserve::fill() {
  const size_t page = size_t(sysconf(_SC_PAGESIZE));
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stop_) {
    // Ahead by a quarter of what was taken so far, up to keepReady_: a small design is not given the
    // memory a large one needs.
    if (ready_.size() >= std::min(keepReady_, 1 + takenCount_ / 4)) {
      taken_.wait(lock);
      continue;
    }
    lock.unlock();
    void* block = nullptr;
    try {
      block = mapHuge(HugePageArena::kBlock);
      // Written once, so that the kernel's faults and cleared pages are this thread's.
      volatile char* bytes = static_cast<char*>(block);
      for (size_t at = 0; at < HugePageArena::kBlock; at += page) bytes[at] = 0;
    } catch (const std::bad_alloc&) {
      return;  // the arenas map their own, and meet the refusal themselves
    }
    lock.lock();
    ready_.push_back(block);
  }
}

// ---- HugePageArena ----

HugePageArena::~HugePageArena() {
  for (void* block : blocks_) munmap(block, kBlock);
}

void* HugePageArena::take(size_t bytes, size_t align) {
  if (bytes >= kBlock) return mapHuge(roundUp(bytes, kBlock));
  char* at = reinterpret_cast<char*>(roundUp(reinterpret_cast<uintptr_t>(next_), align));
  if (!next_ || at + bytes > end_) {
    void* block = reserve_ ? reserve_->takeBlock() : nullptr;
    next_ = static_cast<char*>(block ? block : mapHuge(kBlock));
    end_ = next_ + kBlock;
    blocks_.push_back(next_);
    at = next_;
  }
  next_ = at + bytes;
  return at;
}

void HugePageArena::give(void* p, size_t bytes) {
  if (bytes >= kBlock) munmap(p, roundUp(bytes, kBlock));
}

}  // namespace lcjit::support
