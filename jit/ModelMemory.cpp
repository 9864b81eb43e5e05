// The JIT's memory for linked code and data (ModelMemory.h).
#include "jit/ModelMemory.h"

#include <llvm/ExecutionEngine/JITLink/JITLink.h>
#include <llvm/ExecutionEngine/JITLink/x86_64.h>
#include <llvm/ExecutionEngine/Orc/Shared/AllocationActions.h>
#include <llvm/Support/Memory.h>
#include <llvm/Support/Process.h>

#include <sys/mman.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <set>
#include <tuple>

namespace lcjit::jit::detail {

namespace jitlink = llvm::jitlink;
namespace orc = llvm::orc;

namespace {

const auto kReadWrite = static_cast<orc::MemProt>(unsigned(orc::MemProt::Read) | unsigned(orc::MemProt::Write));

// The blocks of one protection and lifetime, at `offset` in the mapping, `size` whole pages.
struct Segment {
  orc::AllocGroup group;
  std::vector<jitlink::Block*> content, zeroFill;
  uint64_t offset = 0, size = 0;
};

// Where a segment goes: those kept while the code is loaded first (code, read-only data, data),
// then those released once it is finalized.
int rank(const orc::AllocGroup& g) {
  const auto p = static_cast<unsigned>(g.getMemProt());
  const int kind = p & static_cast<unsigned>(orc::MemProt::Exec) ? 0 : p & static_cast<unsigned>(orc::MemProt::Write) ? 2 : 1;
  return (g.getMemLifetime() == orc::MemLifetime::Standard ? 0 : 3) + kind;
}

// Where the segment's blocks go, from its start: content, then zero fill. Returns the end.
template <class Place>
uint64_t layOut(const Segment& s, Place place) {
  uint64_t at = 0;
  for (const auto* blocks : {&s.content, &s.zeroFill})
    for (jitlink::Block* b : *blocks) {
      at = jitlink::alignToBlock(at, *b);
      place(*b, at);
      at += b->getSize();
    }
  return at;
}

// A mapping of ours: where it is and how big (size 0: none).
struct Mapping {
  char* base = nullptr;
  uint64_t size = 0;
};

llvm::Expected<Mapping> map(uint64_t size, void* hint, const char* what) {
  if (!size) return Mapping{};
  void* at = ::mmap(hint, size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (at == MAP_FAILED)
    return llvm::createStringError("mapping " + std::to_string(size) + " bytes for its " + what + " failed: " + std::strerror(errno));
  return Mapping{static_cast<char*>(at), size};
}

llvm::Error unmap(char* at, uint64_t size) {
  if (size && ::munmap(at, size) != 0) return llvm::errorCodeToError(std::error_code(errno, std::generic_category()));
  return llvm::Error::success();
}

// Where far variables are asked to go: 16 TiB up, away from where mmap places everything else
// (down from the top of the address space), so that the objects linked later stay next to the
// earlier ones they refer to. Only a hint: taken elsewhere, they are reached all the same.
std::atomic<uintptr_t> gNextFar{uintptr_t(1) << 44};

// A finalized allocation (FinalizedAlloc's address points at it): its mappings, which stay while
// the code is loaded, and what to run when it goes.
struct Finalized {
  Mapping kept, far;
  std::vector<orc::shared::WrapperFunctionCall> deallocActions;
};

class InFlight : public jitlink::JITLinkMemoryManager::InFlightAlloc {
 public:
  InFlight(jitlink::LinkGraph& g, Mapping all, uint64_t kept, Mapping far, std::vector<Segment> segments)
      : g_(g), all_(all), kept_(kept), far_(far), segments_(std::move(segments)) {}

  void finalize(OnFinalizedFunction done) override {
    for (const Segment& s : segments_) {
      const auto prot = orc::toSysMemoryProtectionFlags(s.group.getMemProt());
      llvm::sys::MemoryBlock block(all_.base + s.offset, s.size);
      if (auto ec = llvm::sys::Memory::protectMappedMemory(block, prot)) return fail(std::move(done), llvm::errorCodeToError(ec));
      if (prot & llvm::sys::Memory::MF_EXEC) llvm::sys::Memory::InvalidateInstructionCache(block.base(), block.allocatedSize());
    }
    auto deallocActions = orc::shared::runFinalizeActions(g_.allocActions());
    if (!deallocActions) return fail(std::move(done), deallocActions.takeError());
    if (auto err = unmap(all_.base + kept_, all_.size - kept_)) return fail(std::move(done), std::move(err));
    auto* f = new Finalized{{all_.base, kept_}, far_, std::move(*deallocActions)};
    done(jitlink::JITLinkMemoryManager::FinalizedAlloc(orc::ExecutorAddr::fromPtr(f)));
  }

  void abandon(OnAbandonedFunction done) override { done(llvm::joinErrors(unmap(all_.base, all_.size), unmap(far_.base, far_.size))); }

 private:
  void fail(OnFinalizedFunction done, llvm::Error err) {
    llvm::consumeError(llvm::joinErrors(unmap(all_.base, all_.size), unmap(far_.base, far_.size)));
    done(std::move(err));
  }

  jitlink::LinkGraph& g_;
  Mapping all_;    // every segment; the first kept_ bytes stay after finalizing
  uint64_t kept_;
  Mapping far_;    // the far variables
  std::vector<Segment> segments_;
};

// The zero-filled blocks of `g` that can go far: large, and reached only through 64-bit
// addresses (the GOT's entries, pointers in data), never by code's 32-bit displacements.
std::set<const jitlink::Block*> farBlocks(jitlink::LinkGraph& g) {
  std::set<const jitlink::Block*> far;
  if (g.getTargetTriple().getArch() != llvm::Triple::x86_64) return far;
  for (jitlink::Block* b : g.blocks())
    if (b->isZeroFill() && b->getSize() >= kFarData && b->getSection().getMemLifetime() == orc::MemLifetime::Standard &&
        b->getSection().getMemProt() == kReadWrite)
      far.insert(b);
  for (jitlink::Block* b : g.blocks())
    for (const jitlink::Edge& e : b->edges())
      if (e.getTarget().isDefined() && e.getKind() != jitlink::x86_64::Pointer64 && e.getKind() != jitlink::x86_64::Delta64)
        far.erase(&e.getTarget().getBlock());
  return far;
}

}  // namespace

void ModelMemory::allocate(const jitlink::JITLinkDylib*, jitlink::LinkGraph& g, OnAllocatedFunction onAllocated) {
  static const uint64_t page = llvm::sys::Process::getPageSizeEstimate();
  const std::set<const jitlink::Block*> far = farBlocks(g);
  std::vector<Segment> segments;
  std::vector<jitlink::Block*> farOnes;
  for (jitlink::Section& sec : g.sections()) {
    if (sec.blocks().empty() || sec.getMemLifetime() == orc::MemLifetime::NoAlloc) continue;
    const orc::AllocGroup group(sec.getMemProt(), sec.getMemLifetime());
    auto it = std::find_if(segments.begin(), segments.end(), [&](const Segment& s) { return s.group == group; });
    if (it == segments.end()) it = segments.insert(segments.end(), Segment{group, {}, {}});
    for (jitlink::Block* b : sec.blocks())
      (far.count(b) ? farOnes : b->isZeroFill() ? it->zeroFill : it->content).push_back(b);
  }
  std::erase_if(segments, [](const Segment& s) { return s.content.empty() && s.zeroFill.empty(); });
  std::stable_sort(segments.begin(), segments.end(), [](const Segment& a, const Segment& b) { return rank(a.group) < rank(b.group); });
  auto inObject = [](const jitlink::Block* b) { return std::make_tuple(b->getSection().getOrdinal(), b->getAddress(), b->getSize()); };
  uint64_t total = 0, kept = 0;
  for (Segment& s : segments) {
    std::sort(s.content.begin(), s.content.end(), [&](auto* a, auto* b) { return inObject(a) < inObject(b); });
    std::sort(s.zeroFill.begin(), s.zeroFill.end(), [&](auto* a, auto* b) {
      return std::make_tuple(a->getSize(), inObject(a)) < std::make_tuple(b->getSize(), inObject(b));
    });
    for (const auto* blocks : {&s.content, &s.zeroFill})
      for (const jitlink::Block* b : *blocks)
        if (b->getAlignment() > page)
          return onAllocated(llvm::createStringError("a block of section " + b->getSection().getName() +
                                                     " wants an alignment greater than a page"));
    s.offset = total;
    s.size = llvm::alignTo(layOut(s, [](jitlink::Block&, uint64_t) {}), page);
    total += s.size;
    if (rank(s.group) < 3) kept = total;
  }
  Segment farSegment{orc::AllocGroup(kReadWrite), {}, std::move(farOnes)};
  const uint64_t farSize = llvm::alignTo(layOut(farSegment, [](jitlink::Block&, uint64_t) {}), page);
  // A fresh anonymous mapping is zero: what is not copied into it is never touched here.
  auto all = map(total, nullptr, "code and data");
  if (!all) return onAllocated(all.takeError());
  auto farMapping = map(farSize, farSize ? reinterpret_cast<void*>(gNextFar.fetch_add(llvm::alignTo(farSize, uint64_t(1) << 30))) : nullptr,
                        "largest variables");
  if (!farMapping) {
    llvm::consumeError(unmap(all->base, all->size));
    return onAllocated(farMapping.takeError());
  }
  auto place = [](char* segmentBase) {
    return [segmentBase](jitlink::Block& b, uint64_t at) {
      char* mem = segmentBase + at;
      b.setAddress(orc::ExecutorAddr::fromPtr(mem));
      if (!b.isZeroFill()) {
        std::memcpy(mem, b.getContent().data(), b.getSize());
        b.setMutableContent({mem, size_t(b.getSize())});
      }
    };
  };
  for (Segment& s : segments) layOut(s, place(all->base + s.offset));
  layOut(farSegment, place(farMapping->base));
  onAllocated(std::make_unique<InFlight>(g, *all, kept, *farMapping, std::move(segments)));
}

void ModelMemory::deallocate(std::vector<FinalizedAlloc> allocs, OnDeallocatedFunction onDeallocated) {
  llvm::Error err = llvm::Error::success();
  for (FinalizedAlloc& a : allocs) {
    auto* f = a.release().toPtr<Finalized*>();
    err = llvm::joinErrors(std::move(err), orc::shared::runDeallocActions(f->deallocActions));
    err = llvm::joinErrors(std::move(err), unmap(f->kept.base, f->kept.size));
    err = llvm::joinErrors(std::move(err), unmap(f->far.base, f->far.size));
    delete f;
  }
  onDeallocated(std::move(err));
}

}  // namespace lcjit::jit::detail
