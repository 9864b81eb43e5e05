// The memory the JIT links code and data into (a JITLinkMemoryManager for ORC's
// ObjectLinkingLayer), laid out as a static linker lays out a program:
//
//  - zero-filled data (.bss) stay as a fresh mapping gives them: zero, and not resident until the
//    model touches them, as in a process that lpfg's g++ build makes. ORC's own manager
//    (InProcessMemoryManager) zeroes the whole mapping first, which made a model's 1 GB static
//    array resident before any of its code ran, where --max-memory does not look;
//  - code first, then read-only data, then data, then zero-filled data, the smallest first;
//  - a zero-filled variable of kFarData bytes or more (a voxel space of gigabytes) gets a mapping
//    of its own, away from the one every object's code and data share. Code reaches ±2 GB
//    (x86-64's small code model, which JITLink wants) of what it refers to directly: such an
//    array between two objects, or between an object's code and its data, would put them out of
//    each other's reach. Model code refers to it through the GOT (a 64-bit address: exportState
//    marks it so), and only a block that nothing reaches otherwise is moved.
//
// One mapping per linked object (and one per far variable), released when its code is removed.
// See docs/jit.md.
#pragma once

#include <llvm/ExecutionEngine/JITLink/JITLinkMemoryManager.h>

#include <cstdint>

namespace lcjit::jit::detail {

// The size from which a zero-filled variable is placed in a mapping of its own (and reached
// through the GOT): big enough that the extra load costs nothing next to what it addresses, small
// enough that what stays near takes more than a hundred variables to pass 2 GB.
constexpr uint64_t kFarData = uint64_t(16) << 20;

class ModelMemory : public llvm::jitlink::JITLinkMemoryManager {
 public:
  void allocate(const llvm::jitlink::JITLinkDylib* jd, llvm::jitlink::LinkGraph& g,
                OnAllocatedFunction onAllocated) override;
  void deallocate(std::vector<FinalizedAlloc> allocs, OnDeallocatedFunction onDeallocated) override;
  using JITLinkMemoryManager::allocate;
  using JITLinkMemoryManager::deallocate;
};

}  // namespace lcjit::jit::detail
