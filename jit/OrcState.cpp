// The JIT's long-lived state of OrcState.h: the LLJIT and its host symbols, code generation with
// kept TargetMachines, and the end of a loaded version.
#include "jit/OrcState.h"
#include "jit/CompilerImpl.h"
#include "jit/IRPipeline.h"

#include <llvm/ExecutionEngine/Orc/CompileUtils.h>
#include <llvm/ExecutionEngine/Orc/IRCompileLayer.h>
#include <llvm/Support/raw_ostream.h>

namespace lcjit::jit {

llvm::Error runOwnAtExits(orc::LLJIT& J, orc::JITDylib& JD) {
  auto& ES = J.getExecutionSession();
  auto run = ES.lookup(orc::makeJITDylibSearchOrder(&JD, orc::JITDylibLookupFlags::MatchAllSymbols),
                       J.mangleAndIntern("__lljit_run_atexits"));
  if (!run)
    return run.takeError();
  return callCatching(
      [&] {
        run->getAddress().toPtr<void (*)()>()();
        return llvm::Error::success();
      },
      "static destructor");
}

namespace detail {

llvm::Error Codegen::ensure(orc::JITTargetMachineBuilder& b, llvm::CodeGenOptLevel level) {
  if (tm)
    return llvm::Error::success();
  b.setCodeGenOptLevel(level);
  auto t = b.createTargetMachine();
  if (!t)
    return t.takeError();
  tm = std::move(*t);
  return llvm::Error::success();
}

llvm::Expected<std::unique_ptr<llvm::MemoryBuffer>> Codegen::compile(llvm::Module& m, orc::JITTargetMachineBuilder b,
                                                                     llvm::CodeGenOptLevel level) {
  std::lock_guard<std::mutex> lock(mutex);
  if (auto err = ensure(b, level))
    return std::move(err);
  m.setDataLayout(tm->createDataLayout());
  return orc::SimpleCompiler(*tm)(m);
}

llvm::Error Codegen::optimize(llvm::Module& m, int level, orc::JITTargetMachineBuilder b,
                              llvm::CodeGenOptLevel cgLevel) {
  std::lock_guard<std::mutex> lock(mutex);
  if (auto err = ensure(b, cgLevel))
    return err;
  runIRPipeline(m, level, tm.get());
  return llvm::Error::success();
}

llvm::Expected<std::shared_ptr<JitState>> JitState::create(const orc::JITTargetMachineBuilder& jtmb,
                                                           const std::vector<HostSymbol>& hostSymbols) {
  auto state = std::make_shared<JitState>();
  // Model code arrives as object files (Impl::emitObject); what ORC still compiles from IR is
  // its own small support modules (__dso_handle, the atexit helpers of each JITDylib), with the
  // quick tiers' TargetMachine.
  struct SupportCompiler : orc::IRCompileLayer::IRCompiler {
    SupportCompiler(orc::JITTargetMachineBuilder b, Codegen& cg)
        : IRCompiler(orc::irManglingOptionsFromTargetOptions(b.getOptions())), jtmb(std::move(b)), cg(cg) {}
    llvm::Expected<std::unique_ptr<llvm::MemoryBuffer>> operator()(llvm::Module& m) override {
      return cg.compile(m, jtmb, llvm::CodeGenOptLevel::None);
    }
    orc::JITTargetMachineBuilder jtmb;
    Codegen& cg;
  };
  Codegen& fast = state->codegen[0];
  auto jit = orc::LLJITBuilder()
                 .setJITTargetMachineBuilder(jtmb)
                 .setCompileFunctionCreator([&fast](orc::JITTargetMachineBuilder b)
                                                -> llvm::Expected<std::unique_ptr<orc::IRCompileLayer::IRCompiler>> {
                   return std::make_unique<SupportCompiler>(std::move(b), fast);
                 })
                 .create();
  if (!jit)
    return jit.takeError();
  state->jit = std::move(*jit);
  JitState* raw = state.get();
  state->jit->getExecutionSession().setErrorReporter([raw](llvm::Error err) {
    std::string msg = llvm::toString(std::move(err));
    std::lock_guard<std::mutex> lock(raw->errorMutex);
    raw->sessionErrors += msg + "\n";
  });

  // Host functions get their own JITDylib, defined explicitly: no process-symbol generator on a
  // model's dylib (the latency study saw JIT'd static destructors crash or hang at exit with
  // one; docs/jit.md).
  auto hostJD = state->jit->createJITDylib("lcjit.host");
  if (!hostJD)
    return hostJD.takeError();
  state->hostJD = &*hostJD;
  if (!hostSymbols.empty()) {
    orc::SymbolMap syms;
    for (const auto& s : hostSymbols)
      syms[state->jit->mangleAndIntern(s.name)] = {orc::ExecutorAddr::fromPtr(s.address),
                                                    llvm::JITSymbolFlags::Exported};
    if (auto err = state->hostJD->define(orc::absoluteSymbols(std::move(syms))))
      return std::move(err);
  }
  return state;
}

void JitState::appendRuntime(orc::JITDylibSearchOrder& order) const {
  order.push_back({hostJD, orc::JITDylibLookupFlags::MatchExportedSymbolsOnly});
  if (auto p = jit->getPlatformJITDylib())
    order.push_back({p.get(), orc::JITDylibLookupFlags::MatchExportedSymbolsOnly});
  if (auto p = jit->getProcessSymbolsJITDylib())
    order.push_back({p.get(), orc::JITDylibLookupFlags::MatchExportedSymbolsOnly});
}

JitState::~JitState() {
  failedDylibs.clear();
  jit.reset();  // before the mutexes the error reporter uses
}

std::string JitState::takeSessionErrors() {
  std::lock_guard<std::mutex> lock(errorMutex);
  return std::exchange(sessionErrors, {});
}

Dylib::~Dylib() {
  std::lock_guard<std::mutex> lock(state->mutex);
  auto& J = *state->jit;
  // Static destructors / atexit handlers of this version only, then free its memory.
  if (llvm::Error err = asModelCode([&] { return runOwnAtExits(J, *jd); }))
    llvm::logAllUnhandledErrors(std::move(err), llvm::errs(), "lcjit: deinitializing " + name + ": ");
  if (auto err = J.getExecutionSession().removeJITDylib(*jd))
    llvm::logAllUnhandledErrors(std::move(err), llvm::errs(), "lcjit: removing " + name + ": ");
  state->takeSessionErrors();
}

}  // namespace detail

llvm::Expected<std::string> Compiler::Impl::emitObject(llvm::Module& m, int level) {
  // Fast instruction selection for the quick tiers: on lightly optimised IR the SelectionDAG
  // backend was the slowest part of a compile (docs/jit.md).
  auto buffer = state->codegen[level >= 2 ? 1 : 0].compile(
      m, jtmb, level >= 2 ? llvm::CodeGenOptLevel::Default : llvm::CodeGenOptLevel::None);
  if (!buffer)
    return buffer.takeError();
  return (*buffer)->getBuffer().str();
}

}  // namespace lcjit::jit
