// Memory for the largest tables an engine fills — millions of shapes waiting to be expanded or
// finished — asked of the kernel in transparent huge pages (madvise: the mode Debian's kernels
// default to), and faulted in ahead of need by a thread of its own. The first write to a fresh
// page costs a fault and a cleared page: for the hundreds of megabytes a large design writes that
// was a tenth of its run on a desktop and a third on a virtual machine (whose host backs each
// fresh page too), all of it on the one core that expands while the others wait for the picture.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace lcjit::support {

// Blocks of kBlock bytes mapped and written once by a thread of their own, as many kept ready as
// a quarter of those taken so far, up to a number: an arena fed from it takes its blocks already in
// memory. Made for the length of a run that fills arenas; never waited for (an arena maps its
// own block when none is ready).
class HugePageReserve {
 public:
  explicit HugePageReserve(size_t keepReady);
  HugePageReserve(const HugePageReserve&) = delete;
  HugePageReserve& operator=(const HugePageReserve&) = delete;
  ~HugePageReserve();  // stops the thread, gives back the blocks not taken

  // A ready block, or null when none is.
  void* takeBlock();

 private:
  void fill();

  const size_t keepReady_;
  std::mutex mutex_;
  std::condition_variable taken_;
  std::vector<void*> ready_;
  size_t takenCount_ = 0;
  bool stop_ = false;
  std::thread thread_;
};

// Memory handed out in order from blocks of 2 MiB pages, given back when the arena dies; a
// request of a block or more gets a mapping of its own, which give() returns at once (a growing
// vector's old buffers). Not shared between threads while it hands out memory.
class HugePageArena {
 public:
  static constexpr size_t kBlock = size_t(2) << 20;

  HugePageArena() = default;
  HugePageArena(const HugePageArena&) = delete;
  HugePageArena& operator=(const HugePageArena&) = delete;
  ~HugePageArena();

  // `bytes` aligned to `align` (at most a page); throws std::bad_alloc when the kernel refuses.
  void* take(size_t bytes, size_t align);
  // Back to the arena: a mapping of its own is unmapped, the rest waits for the arena's end.
  void give(void* p, size_t bytes);
  // Where new blocks come from while `reserve` lives (null: mapped here, as they are needed).
  void feedFrom(HugePageReserve* reserve) { reserve_ = reserve; }

 private:
  std::vector<void*> blocks_;  // the shared blocks, kept to the end
  char* next_ = nullptr;
  char* end_ = nullptr;
  HugePageReserve* reserve_ = nullptr;
};

// A standard allocator on a shared arena: a std::deque of a million shapes, or a heap's vector,
// grows without a fault per page. Copies share the arena, and it lives as long as one of them.
template <class T>
class HugePageAllocator {
 public:
  using value_type = T;
  using propagate_on_container_move_assignment = std::true_type;
  using propagate_on_container_copy_assignment = std::true_type;
  using propagate_on_container_swap = std::true_type;

  HugePageAllocator() : arena_(std::make_shared<HugePageArena>()) {}
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>& other) noexcept : arena_(other.arena_) {}

  T* allocate(size_t n) { return static_cast<T*>(arena_->take(n * sizeof(T), alignof(T))); }
  void deallocate(T* p, size_t n) noexcept { arena_->give(p, n * sizeof(T)); }
  HugePageArena& arena() const { return *arena_; }

  template <class U>
  bool operator==(const HugePageAllocator<U>& other) const noexcept {
    return arena_ == other.arena_;
  }

 private:
  template <class U>
  friend class HugePageAllocator;
  std::shared_ptr<HugePageArena> arena_;
};

}  // namespace lcjit::support
