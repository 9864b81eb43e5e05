// ModelCode: a loaded model version as its users see it (symbol lookup, state reset), over the
// JITDylib it holds (detail::Dylib).
#include "jit/Compiler.h"
#include "jit/OrcState.h"

#include <cstring>

namespace lcjit::jit {

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
  for (auto& [at, bytes] : d.initialState)
    std::memcpy(at, bytes.data(), bytes.size());
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
