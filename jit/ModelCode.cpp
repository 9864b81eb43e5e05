// ModelCode: a loaded model version as its users see it (symbol lookup, state reset), over the
// JITDylib it holds (detail::Dylib).
#include "jit/Compiler.h"
#include "jit/OrcState.h"

#include <cstring>

#include <sys/mman.h>
#include <unistd.h>

namespace lcjit::jit {

namespace {

// Zeroes [at, at + size) of the JIT's memory (anonymous, private: ModelMemory.cpp) without making
// it resident: its whole pages are handed back, to come back zero when next touched, as a
// variable that was never used is; only the partial pages at its ends are written.
void zero(char* at, uint64_t size) {
  static const uintptr_t page = uintptr_t(sysconf(_SC_PAGESIZE));
  const uintptr_t begin = uintptr_t(at), end = begin + size;
  const uintptr_t first = (begin + page - 1) & ~(page - 1), last = end & ~(page - 1);
  if (first >= last || madvise(reinterpret_cast<void*>(first), last - first, MADV_DONTNEED) != 0) {
    std::memset(at, 0, size);
    return;
  }
  std::memset(at, 0, first - begin);
  std::memset(reinterpret_cast<void*>(last), 0, end - last);
}

}  // namespace

ModelCode::ModelCode(std::shared_ptr<detail::Dylib> dylib) : dylib_(std::move(dylib)) {}
ModelCode::~ModelCode() = default;
const std::string& ModelCode::name() const { return dylib_->name; }

llvm::Error ModelCode::resetState() {
  detail::Dylib& d = *dylib_;
  auto& state = *d.state;
  std::lock_guard<std::mutex> lock(state.mutex);
  auto& J = *state.jit;
  if (auto err = d.asModelCode([&] { return runOwnAtExits(J, *d.jd); }))
    return err;
  for (const detail::Dylib::Initial& g : d.initialState)
    if (g.zero)
      zero(g.at, g.size);
    else
      std::memcpy(g.at, g.bytes.data(), g.bytes.size());
  // Its initializers again (ORC runs them once per JITDylib; this is the same function).
  auto init = state.jit->lookup(*d.jd, "__orc_init_func.lcjit");
  if (!init) {
    llvm::consumeError(init.takeError());  // no constructors
    state.takeSessionErrors();
    return llvm::Error::success();
  }
  return d.asModelCode([&] {
    return callCatching(
        [&] {
          init->toPtr<void (*)()>()();
          return llvm::Error::success();
        },
        "static initializer");
  });
}

llvm::Expected<void*> ModelCode::lookup(llvm::StringRef cName) {
  auto& state = *dylib_->state;
  auto addr = state.jit->lookup(*dylib_->jd, cName);
  if (!addr) {
    state.takeSessionErrors();
    return addr.takeError();
  }
  return addr->toPtr<void*>();
}

}  // namespace lcjit::jit
