// Clang-as-a-library front end + per-level IR pipelines + one LLJIT, with a disk-cached PCH of
// the runtime header. See docs in Compiler.h and /work/shared/notes/jit-latency-study.md.
#include "jit/Compiler.h"
#include "frontend/CacheFiles.h"
#include "frontend/ClangDiagnostics.h"
#include "jit/Elapsed.h"

#include <clang/Basic/Diagnostic.h>
#include <clang/Basic/DiagnosticFrontend.h>
#include <clang/Basic/DiagnosticIDs.h>
#include <clang/Basic/DiagnosticOptions.h>
#include <clang/Basic/SourceManager.h>
#include <clang/Basic/Stack.h>
#include <clang/Basic/Version.h>
#include <clang/CodeGen/CodeGenAction.h>
#include <clang/Frontend/CompilerInstance.h>
#include <clang/Frontend/CompilerInvocation.h>
#include <clang/Frontend/FrontendActions.h>
#include <clang/Frontend/Utils.h>
#include <clang/Lex/PreprocessorOptions.h>

#include <llvm/ADT/ScopeExit.h>
#include <llvm/Analysis/InlineCost.h>
#include <llvm/Config/llvm-config.h>
#include <llvm/Demangle/Demangle.h>
#include <llvm/ExecutionEngine/Orc/CompileUtils.h>
#include <llvm/ExecutionEngine/Orc/Core.h>
#include <llvm/ExecutionEngine/Orc/IRCompileLayer.h>
#include <llvm/ExecutionEngine/Orc/JITTargetMachineBuilder.h>
#include <llvm/ExecutionEngine/Orc/LLJIT.h>
#include <llvm/ExecutionEngine/Orc/ObjectFileInterface.h>
#include <llvm/ExecutionEngine/Orc/ThreadSafeModule.h>
#include <llvm/CodeGen/TargetSubtargetInfo.h>
#include <llvm/IR/Constants.h>
#include <llvm/IR/IntrinsicInst.h>
#include <llvm/IR/DiagnosticHandler.h>
#include <llvm/IR/DiagnosticInfo.h>
#include <llvm/IR/DiagnosticPrinter.h>
#include <llvm/IR/IRBuilder.h>
#include <llvm/IR/LLVMContext.h>
#include <llvm/IR/Module.h>
#include <llvm/Passes/OptimizationLevel.h>
#include <llvm/Passes/PassBuilder.h>
#include <llvm/Support/FileSystem.h>
#include <llvm/Support/MemoryBuffer.h>
#include <llvm/Support/Path.h>
#include <llvm/Support/Process.h>
#include <llvm/Support/SHA256.h>
#include <llvm/Support/TargetSelect.h>
#include <llvm/Support/raw_ostream.h>
#include <llvm/Transforms/Utils/Cloning.h>
#include <llvm/Target/TargetMachine.h>
#include <llvm/TargetParser/Host.h>
#include <llvm/Transforms/Coroutines/CoroCleanup.h>
#include <llvm/Transforms/Coroutines/CoroConditionalWrapper.h>
#include <llvm/Transforms/Coroutines/CoroEarly.h>
#include <llvm/Transforms/Coroutines/CoroSplit.h>
#include <llvm/Transforms/IPO/GlobalDCE.h>
#include <llvm/Transforms/IPO/ElimAvailExtern.h>
#include <llvm/Transforms/IPO/Inliner.h>
#include <llvm/Transforms/InstCombine/InstCombine.h>
#include <llvm/Transforms/Scalar/EarlyCSE.h>
#include <llvm/Transforms/Scalar/SROA.h>
#include <llvm/Transforms/Scalar/SimplifyCFG.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <optional>
#include <future>
#include <map>
#include <set>
#include <unistd.h>

namespace lcjit::jit {

namespace orc = llvm::orc;
using frontend::DiagCollector;

// The driver derives the resource dir and the GCC installation from argv[0]; Debian's clang 19
// lives here (packages clang-19 / libclang-common-19-dev), and the host toolchain must match.
static constexpr const char* kClangPath = LCJIT_CLANG_EXECUTABLE;
static constexpr const char* kResourceDir = LCJIT_CLANG_RESOURCE_DIR;
// Name given to the driver for the (placeholder) input; the real buffer replaces it per compile.
static constexpr const char* kPlaceholderInput = "lcjit-input.cpp";

namespace {

// Records LLVM back-end errors (e.g. bad inline asm) instead of LLVMContext's default of exit(1).
struct BackendDiagHandler : llvm::DiagnosticHandler {
  explicit BackendDiagHandler(std::shared_ptr<std::string> out) : out(std::move(out)) {}
  bool handleDiagnostics(const llvm::DiagnosticInfo& di) override {
    if (di.getSeverity() == llvm::DS_Error) {
      llvm::raw_string_ostream os(*out);
      llvm::DiagnosticPrinterRawOStream dp(os);
      os << "error: ";
      di.print(dp);
      os << '\n';
    }
    return true;
  }
  std::shared_ptr<std::string> out;
};

// Runs an ORC call that executes model code (static constructors/destructors); a C++ exception
// thrown by that code becomes an Error instead of unwinding through ORC into the caller.
template <class Fn>
llvm::Error callCatching(Fn fn, const char* who) {
  try {
    return fn();
  } catch (...) {
    return llvm::createStringError(llvm::Twine("a ") + who + " threw an exception");
  }
}

std::string trimTrailingNewlines(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r'))
    s.pop_back();
  return s;
}

// ORC reports unresolved symbols by their mangled names; add readable ones for the user.
std::string demangleMentions(const std::string& msg) {
  std::string out;
  size_t i = 0;
  while (i < msg.size()) {
    if (msg.compare(i, 2, "_Z") == 0 && (i == 0 || !(std::isalnum((unsigned char)msg[i - 1]) || msg[i - 1] == '_'))) {
      size_t j = i;
      while (j < msg.size() && (std::isalnum((unsigned char)msg[j]) || msg[j] == '_' || msg[j] == '.'))
        ++j;
      std::string sym = msg.substr(i, j - i);
      std::string dem = llvm::demangle(sym);
      out += sym;
      if (dem != sym)
        out += " (" + dem + ")";
      i = j;
    } else {
      out += msg[i++];
    }
  }
  return out;
}

// Gives the module's mutable globals names another compile of the same source can refer to:
// internal ones become external under the same (deterministic) name, discardable ones stay.
// Returns the names: the model's state, which a better-optimised tier shares (CompileOptions::
// shareStateWith).
std::vector<std::string> exportState(llvm::Module& m) {
  std::vector<std::string> state;
  for (llvm::GlobalVariable& gv : m.globals()) {
    // thread_local ones stay each version's own: ORC reaches them through emulated TLS.
    if (gv.isDeclaration() || gv.isConstant() || gv.isThreadLocal() || !gv.hasName() ||
        gv.getName().starts_with("llvm."))
      continue;
    if (gv.hasLocalLinkage()) {
      gv.setLinkage(llvm::GlobalValue::ExternalLinkage);
      gv.setVisibility(llvm::GlobalValue::DefaultVisibility);
    } else if (gv.hasLinkOnceODRLinkage()) {
      gv.setLinkage(llvm::GlobalValue::WeakODRLinkage);
    } else if (gv.hasLinkOnceLinkage()) {
      gv.setLinkage(llvm::GlobalValue::WeakAnyLinkage);
    }
    state.push_back(gv.getName().str());
  }
  // The productions' functions too (static in the generated C++): an incremental recompile
  // declares the unchanged ones and links against these.
  for (llvm::Function& f : m.functions())
    if (!f.isDeclaration() && f.hasLocalLinkage() && f.getName().contains("__lc_rule_")) {
      f.setLinkage(llvm::GlobalValue::ExternalLinkage);
      f.setVisibility(llvm::GlobalValue::DefaultVisibility);
    }
  return state;
}

// Whether `fn` (an initializer clang emitted) touches one of `globals`.
bool touches(const llvm::Function& fn, const std::set<const llvm::GlobalVariable*>& globals) {
  std::vector<const llvm::Value*> work;
  std::set<const llvm::Value*> seen;
  for (const llvm::BasicBlock& bb : fn)
    for (const llvm::Instruction& inst : bb)
      for (const llvm::Value* op : inst.operands())
        work.push_back(op);
  while (!work.empty()) {
    const llvm::Value* v = work.back();
    work.pop_back();
    if (!seen.insert(v).second)
      continue;
    if (auto* gv = llvm::dyn_cast<llvm::GlobalVariable>(v); gv && globals.count(gv))
      return true;
    if (auto* ce = llvm::dyn_cast<llvm::ConstantExpr>(v))
      for (const llvm::Value* op : ce->operands())
        work.push_back(op);
  }
  return false;
}

// The globals other loaded code owns become declarations here (resolved against that code's
// JITDylib), and their dynamic initializers are not run again: clang calls one function per
// initialized global from the TU's constructor; the calls for shared globals are dropped.
void useSharedState(llvm::Module& m, const std::set<std::string>& shared) {
  std::set<const llvm::GlobalVariable*> declared;
  for (const std::string& name : shared)
    if (llvm::GlobalVariable* gv = m.getGlobalVariable(name, /*AllowInternal=*/true); gv && !gv->isDeclaration()) {
      gv->setInitializer(nullptr);
      gv->setComdat(nullptr);
      gv->setLinkage(llvm::GlobalValue::ExternalLinkage);
      gv->setVisibility(llvm::GlobalValue::DefaultVisibility);
      declared.insert(gv);
    }
  llvm::GlobalVariable* ctors = m.getNamedGlobal("llvm.global_ctors");
  auto* array = ctors && ctors->hasInitializer() ? llvm::dyn_cast<llvm::ConstantArray>(ctors->getInitializer()) : nullptr;
  if (!array)
    return;
  for (const llvm::Use& u : array->operands()) {
    auto* entry = llvm::dyn_cast<llvm::ConstantStruct>(u.get());
    auto* ctor = entry ? llvm::dyn_cast<llvm::Function>(entry->getOperand(1)->stripPointerCasts()) : nullptr;
    if (!ctor || ctor->isDeclaration())
      continue;
    std::vector<llvm::CallInst*> drop;
    for (llvm::BasicBlock& bb : *ctor)
      for (llvm::Instruction& inst : bb)
        if (auto* call = llvm::dyn_cast<llvm::CallInst>(&inst))
          if (llvm::Function* f = call->getCalledFunction(); f && !f->isDeclaration() && touches(*f, declared))
            drop.push_back(call);
    for (llvm::CallInst* call : drop)
      call->eraseFromParent();
  }
}

// Object files reach ORC without its IR-level constructor scraping, so do it here: one function
// under the generic IR platform's init prefix (it runs those on JITDylib initialize) calls the
// constructors in priority order and registers the destructors with the JITDylib's own atexit
// (run on deinitialize).
void gatherInitializers(llvm::Module& m) {
  auto entries = [&](const char* list) {
    std::vector<std::pair<uint64_t, llvm::Function*>> fns;
    llvm::GlobalVariable* gv = m.getNamedGlobal(list);
    if (!gv)
      return fns;
    if (auto* array = llvm::dyn_cast_or_null<llvm::ConstantArray>(gv->hasInitializer() ? gv->getInitializer() : nullptr))
      for (const llvm::Use& u : array->operands()) {
        auto* entry = llvm::dyn_cast<llvm::ConstantStruct>(u.get());
        if (!entry || entry->getNumOperands() < 2)
          continue;
        auto* prio = llvm::dyn_cast<llvm::ConstantInt>(entry->getOperand(0));
        auto* fn = llvm::dyn_cast<llvm::Function>(entry->getOperand(1)->stripPointerCasts());
        if (prio && fn)
          fns.emplace_back(prio->getZExtValue(), fn);
      }
    gv->eraseFromParent();
    std::stable_sort(fns.begin(), fns.end(), [](auto& a, auto& b) { return a.first < b.first; });
    return fns;
  };
  auto ctors = entries("llvm.global_ctors");
  auto dtors = entries("llvm.global_dtors");
  if (ctors.empty() && dtors.empty())
    return;
  llvm::LLVMContext& ctx = m.getContext();
  auto* voidFn = llvm::FunctionType::get(llvm::Type::getVoidTy(ctx), false);
  auto* init = llvm::Function::Create(voidFn, llvm::GlobalValue::ExternalLinkage, "__orc_init_func.lcjit", m);
  llvm::IRBuilder<> b(llvm::BasicBlock::Create(ctx, "entry", init));
  for (auto& [prio, fn] : ctors)
    b.CreateCall(fn->getFunctionType(), fn);
  if (!dtors.empty()) {
    llvm::FunctionCallee atexit = m.getOrInsertFunction(
        "atexit", llvm::FunctionType::get(b.getInt32Ty(), {llvm::PointerType::getUnqual(ctx)}, false));
    for (auto it = dtors.rbegin(); it != dtors.rend(); ++it)
      b.CreateCall(atexit, {it->second});
  }
  b.CreateRetVoid();
}

// Model code is compiled with -ffp-contract=off (lpfg's x86-64 baseline has no fused multiply-add),
// so llvm.fmuladd comes only from a model's own `#pragma STDC FP_CONTRACT ON`. It becomes a
// multiply and an add, as on lpfg's target, at every tier: FastISel (the quick tiers' instruction
// selector) has no rule for it and would hand its whole block to the far slower SelectionDAG.
static void lowerFMulAdd(llvm::Module& m) {
  std::vector<llvm::CallInst*> calls;
  for (llvm::Function& f : m)
    if (f.getIntrinsicID() == llvm::Intrinsic::fmuladd)
      for (llvm::User* u : f.users())
        if (auto* call = llvm::dyn_cast<llvm::CallInst>(u))
          calls.push_back(call);
  for (llvm::CallInst* call : calls) {
    llvm::IRBuilder<> b(call);
    b.setFastMathFlags(call->getFastMathFlags());
    llvm::Value* r = b.CreateFAdd(b.CreateFMul(call->getArgOperand(0), call->getArgOperand(1)), call->getArgOperand(2));
    call->replaceAllUsesWith(r);
    call->eraseFromParent();
  }
}

void runIRPipeline(llvm::Module& m, int level, llvm::TargetMachine* tm) {
  // Declared in this order so they are destroyed in the right order (they reference each other).
  llvm::LoopAnalysisManager lam;
  llvm::FunctionAnalysisManager fam;
  llvm::CGSCCAnalysisManager cgam;
  llvm::ModuleAnalysisManager mam;

  llvm::PipelineTuningOptions pto;
  if (level >= 2) {
    // What clang's driver turns on at -O2.
    pto.LoopUnrolling = true;
    pto.LoopInterleaving = true;
    pto.LoopVectorization = true;
    pto.SLPVectorization = true;
  }
  llvm::PassBuilder pb(tm, pto);
  pb.registerModuleAnalyses(mam);
  pb.registerCGSCCAnalyses(cgam);
  pb.registerFunctionAnalyses(fam);
  pb.registerLoopAnalyses(lam);
  pb.crossRegisterProxies(lam, fam, cgam, mam);

  llvm::ModulePassManager mpm;
  if (level <= 0) {
    mpm = pb.buildO0DefaultPipeline(llvm::OptimizationLevel::O0);
  } else if (level >= 2) {
    mpm = pb.buildPerModuleDefaultPipeline(llvm::OptimizationLevel::O2);
  } else {
    // Light pipeline: enough to remove the abstraction overhead of small helper calls and
    // allocas (most of the -O2 speed-up on model code) while keeping IR small for fast isel.
    {
      llvm::ModulePassManager coro;
      coro.addPass(llvm::CoroEarlyPass());
      mpm.addPass(llvm::CoroConditionalWrapper(std::move(coro)));
    }
    llvm::FunctionPassManager early;
    early.addPass(llvm::SROAPass(llvm::SROAOptions::ModifyCFG));
    early.addPass(llvm::EarlyCSEPass());
    early.addPass(llvm::SimplifyCFGPass());
    mpm.addPass(llvm::createModuleToFunctionPassAdaptor(std::move(early)));

    llvm::ModuleInlinerWrapperPass inliner(llvm::getInlineParams(1, 0));
    llvm::FunctionPassManager post;
    post.addPass(llvm::SROAPass(llvm::SROAOptions::ModifyCFG));
    post.addPass(llvm::EarlyCSEPass());
    post.addPass(llvm::InstCombinePass());
    post.addPass(llvm::SimplifyCFGPass());
    inliner.getPM().addPass(llvm::createCGSCCToFunctionPassAdaptor(std::move(post)));
    // Required for correctness whenever the model contains C++20 coroutines.
    inliner.getPM().addPass(llvm::CoroSplitPass(false));
    mpm.addPass(std::move(inliner));
    {
      llvm::ModulePassManager coro;
      coro.addPass(llvm::CoroCleanupPass());
      mpm.addPass(llvm::CoroConditionalWrapper(std::move(coro)));
    }
    // Bodies kept only for inlining (extern templates: libstdc++'s std::string in C++14) become
    // declarations again, as in the standard pipelines: left available_externally, their
    // references did not resolve in the JIT link.
    mpm.addPass(llvm::EliminateAvailableExternallyPass());
    // Inlined linkonce_odr helpers (most of the runtime header) would otherwise be codegen'd.
    mpm.addPass(llvm::GlobalDCEPass());
  }
  mpm.run(m, mam);
  lowerFMulAdd(m);
}

std::string defaultCacheDir() {
  if (const char* d = std::getenv("LCJIT_CACHE_DIR"); d && *d)
    return d;
  if (const char* d = std::getenv("XDG_CACHE_HOME"); d && *d)
    return std::string(d) + "/lcjit";
  if (const char* d = std::getenv("HOME"); d && *d)
    return std::string(d) + "/.cache/lcjit";
  return "/tmp/lcjit-cache-" + std::to_string(::getuid());
}

} // namespace

// Runs the destructors this JITDylib's own code registered (its atexit list), and only those:
// LLJIT::deinitialize would also run those of every JITDylib in its link order, which for a
// version sharing another's globals destroys them while the other still runs.
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
// Instruction selection at one level, with one TargetMachine kept for it (creating one costs
// about a millisecond; one is not reentrant, hence the lock).
// One TargetMachine, kept: creating one and its subtarget costs ~1 ms, a tenth of a quick
// compile. It is not thread-safe (subtargets are created on demand), hence the mutex.
struct Codegen {
  std::mutex mutex;
  std::unique_ptr<llvm::TargetMachine> tm;

  llvm::Error ensure(orc::JITTargetMachineBuilder& b, llvm::CodeGenOptLevel level) {
    if (tm)
      return llvm::Error::success();
    b.setCodeGenOptLevel(level);
    auto t = b.createTargetMachine();
    if (!t)
      return t.takeError();
    tm = std::move(*t);
    return llvm::Error::success();
  }

  llvm::Expected<std::unique_ptr<llvm::MemoryBuffer>> compile(llvm::Module& m, orc::JITTargetMachineBuilder b,
                                                              llvm::CodeGenOptLevel level) {
    std::lock_guard<std::mutex> lock(mutex);
    if (auto err = ensure(b, level))
      return std::move(err);
    m.setDataLayout(tm->createDataLayout());
    return orc::SimpleCompiler(*tm)(m);
  }

  // The IR passes of `level` (runIRPipeline) with this TargetMachine.
  llvm::Error optimize(llvm::Module& m, int level, orc::JITTargetMachineBuilder b, llvm::CodeGenOptLevel cgLevel) {
    std::lock_guard<std::mutex> lock(mutex);
    if (auto err = ensure(b, cgLevel))
      return err;
    runIRPipeline(m, level, tm.get());
    return llvm::Error::success();
  }
};

// Everything ModelCode needs after the Compiler is gone: the LLJIT is destroyed only after the
// last ModelCode released its JITDylib (the reverse order is a use-after-free).
struct JitState {
  std::unique_ptr<orc::LLJIT> jit;
  orc::JITDylib* hostJD = nullptr;

  // What every JITDylib of lcjit's links against last: host symbols before the process's, so
  // that explicit definitions win over same-named process symbols.
  void appendRuntime(orc::JITDylibSearchOrder& order) const {
    order.push_back({hostJD, orc::JITDylibLookupFlags::MatchExportedSymbolsOnly});
    if (auto p = jit->getPlatformJITDylib())
      order.push_back({p.get(), orc::JITDylibLookupFlags::MatchExportedSymbolsOnly});
    if (auto p = jit->getProcessSymbolsJITDylib())
      order.push_back({p.get(), orc::JITDylibLookupFlags::MatchExportedSymbolsOnly});
  }
  // Serializes JITDylib creation, initialization, deinitialization and removal; lookups on
  // materialized code don't take it (ORC's session is thread-safe for those).
  std::mutex mutex;
  std::atomic<uint64_t> counter{0};
  std::mutex errorMutex;
  std::string sessionErrors;
  // JITDylibs of failed compiles, kept allocated: the generic IR platform keys its init/atexit
  // tables by JITDylib address and only clears them on a full initialize/deinitialize, so a
  // reused address could inherit stale entries.
  std::vector<orc::JITDylibSP> failedDylibs;
  // [0] fast instruction selection (the quick tiers, and ORC's own small IR modules), [1] default.
  std::array<Codegen, 2> codegen;

  ~JitState() {
    failedDylibs.clear();
    jit.reset(); // before the mutexes the error reporter uses
  }

  std::string takeSessionErrors() {
    std::lock_guard<std::mutex> lock(errorMutex);
    return std::exchange(sessionErrors, {});
  }
};

// One loaded model version. A version sharing another's state keeps that one alive (its globals
// live there), and is destroyed first.
struct Dylib {
  std::shared_ptr<JitState> state;
  orc::JITDylib* jd = nullptr;
  std::string name;
  std::vector<std::string> stateNames;              // the mutable globals this version defines
  std::vector<std::shared_ptr<Dylib>> stateOwners;  // the versions whose globals this one uses
  std::vector<std::shared_ptr<Dylib>> linked;       // the versions whose functions it calls
  // Each owned global's address and its bytes as loaded, before the constructors ran.
  std::vector<std::pair<void*, std::string>> initialState;
  std::function<llvm::Error(const std::function<llvm::Error()>&)> runModelCode;  // CompileOptions'

  llvm::Error asModelCode(const std::function<llvm::Error()>& f) const { return runModelCode ? runModelCode(f) : f(); }

  ~Dylib() {
    std::lock_guard<std::mutex> lock(state->mutex);
    auto& J = *state->jit;
    // Static destructors / atexit handlers of this version only, then free its memory.
    if (llvm::Error err = asModelCode([&] { return runOwnAtExits(J, *jd); }))
      llvm::logAllUnhandledErrors(std::move(err), llvm::errs(), "lcjit: deinitializing " + name + ": ");
    if (auto err = J.getExecutionSession().removeJITDylib(*jd))
      llvm::logAllUnhandledErrors(std::move(err), llvm::errs(), "lcjit: removing " + name + ": ");
    state->takeSessionErrors();
  }
};
} // namespace detail

namespace {
// What the object cache keeps of a compile: the object file and what loading it needs to know.
struct CachedObject {
  std::string object;
  std::string anchor;                   // a defined symbol: looking it up links the whole object
  std::vector<std::string> stateNames;  // see exportState
  std::vector<uint64_t> stateSizes;     // their sizes in bytes
};

// Cache files: "lcjit-object 2\n", the anchor line, a count line, "SIZE NAME" per state global,
// then the object bytes.
std::string serialize(const CachedObject& c) {
  std::string out = "lcjit-object 2\n" + c.anchor + "\n" + std::to_string(c.stateNames.size()) + "\n";
  for (size_t i = 0; i < c.stateNames.size(); ++i)
    out += std::to_string(c.stateSizes[i]) + " " + c.stateNames[i] + "\n";
  return out + c.object;
}

std::optional<CachedObject> deserialize(llvm::StringRef text) {
  CachedObject c;
  auto line = [&]() -> std::optional<llvm::StringRef> {
    size_t nl = text.find('\n');
    if (nl == llvm::StringRef::npos)
      return std::nullopt;
    llvm::StringRef l = text.substr(0, nl);
    text = text.substr(nl + 1);
    return l;
  };
  auto magic = line(), anchor = line(), count = line();
  size_t n = 0;
  if (!magic || *magic != "lcjit-object 2" || !anchor || !count || count->getAsInteger(10, n))
    return std::nullopt;
  c.anchor = anchor->str();
  for (size_t i = 0; i < n; ++i) {
    auto entry = line();
    uint64_t size = 0;
    if (!entry)
      return std::nullopt;
    auto [number, name] = entry->split(' ');
    if (number.getAsInteger(10, size) || name.empty())
      return std::nullopt;
    c.stateSizes.push_back(size);
    c.stateNames.push_back(name.str());
  }
  c.object = text.str();
  return c;
}
} // namespace

// Per opt level: the driver-derived invocation (built once) and the PCH state.
// One clang front end run, in two halves. begin() does all that does not need the unit's text:
// the CompilerInstance, the target, the PCH loaded and validated, the builtins registered
// (~3-4 ms of a ~10 ms quick compile). finish() puts the text into the buffer the main file
// already points at (padded with spaces to the capacity it was begun with) and parses and
// generates IR. So a quick tier can begin the next compile's front end ahead, while the
// modeller is still typing.
// Runs `action` on `inv` to the end, its diagnostics into `dc`; true when there was no error.
static bool executeClang(std::shared_ptr<clang::CompilerInvocation> inv, clang::FrontendAction& action,
                         DiagCollector& dc) {
  clang::CompilerInstance ci;
  ci.setInvocation(std::move(inv));
  ci.createDiagnostics(&dc, false);
  return ci.ExecuteAction(action) && dc.getNumErrors() == 0;
}

class Frontend {
public:
  struct Result {
    std::unique_ptr<llvm::LLVMContext> ctx;
    std::unique_ptr<llvm::Module> module;
    std::shared_ptr<std::string> backendErrors;  // what the LLVM back end reports later
    std::string diagnostics;
    bool pchProblem = false;
  };

  Frontend(std::shared_ptr<clang::CompilerInvocation> base, std::string pchPath, bool pchFallback,
           const std::string& runtimeHeader, std::string bufferName, size_t capacity)
      : pchPath(std::move(pchPath)), pchFallback(pchFallback), bufferName(std::move(bufferName)), capacity(capacity),
        base(std::move(base)), runtimeHeader(runtimeHeader) {}
  Frontend(const Frontend&) = delete;
  Frontend& operator=(const Frontend&) = delete;
  ~Frontend() {
    if (begun)
      action->EndSourceFile();
  }

  bool begin() {
    text = std::make_unique<char[]>(capacity + 1);
    std::memset(text.get(), ' ', capacity);
    text[capacity] = '\0';
    auto inv = std::make_shared<clang::CompilerInvocation>(*base);
    auto& fo = inv->getFrontendOpts();
    fo.Inputs.clear();
    fo.Inputs.emplace_back(bufferName, clang::InputKind(clang::Language::CXX));
    fo.OutputFile.clear();
    fo.DisableFree = false;
    auto& ppo = inv->getPreprocessorOpts();
    remapped = llvm::MemoryBuffer::getMemBuffer(llvm::StringRef(text.get(), capacity), bufferName,
                                                /*RequiresNullTerminator=*/true);
    ppo.RetainRemappedFileBuffers = true;  // ours
    ppo.addRemappedFile(bufferName, remapped.get());
    if (pchFallback)
      ppo.Includes.push_back(runtimeHeader);
    else
      ppo.ImplicitPCHInclude = pchPath;
    inv->getCodeGenOpts().MainFileName = bufferName;
    ctx = std::make_unique<llvm::LLVMContext>();
    backendErrors = std::make_shared<std::string>();
    ctx->setDiagnosticHandler(std::make_unique<BackendDiagHandler>(backendErrors));
    ci = std::make_unique<clang::CompilerInstance>();
    ci->setInvocation(inv);
    ci->createDiagnostics(&dc, false);
    action = std::make_unique<clang::EmitLLVMOnlyAction>(ctx.get());
    // What CompilerInstance::ExecuteAction does, up to the parse.
    if (!action->PrepareToExecute(*ci) || !ci->createTarget())
      return false;
    begun = action->BeginSourceFile(*ci, ci->getFrontendOpts().Inputs[0]);
    return begun && dc.getNumErrors() == 0;
  }

  Result finish(llvm::StringRef source) {
    Result r;
    r.backendErrors = backendErrors;
    if (begun && dc.getNumErrors() == 0) {
      std::memcpy(text.get(), source.data(), std::min(source.size(), capacity));
      if (llvm::Error err = action->Execute())
        dc.text += "error: " + llvm::toString(std::move(err)) + "\n";
      action->EndSourceFile();
      begun = false;
    }
    r.pchProblem = dc.pchProblem;
    if (dc.getNumErrors() != 0 || !dc.text.empty()) {
      r.diagnostics = dc.text.empty() ? std::string("error: compilation failed\n") : dc.text;
      return r;
    }
    r.module = action->takeModule();
    if (!r.module) {
      r.diagnostics = "error: compilation produced no module\n";
      return r;
    }
    r.ctx = std::move(ctx);
    return r;
  }

  const std::string pchPath;
  const bool pchFallback;
  const std::string bufferName;
  const size_t capacity;

private:
  std::shared_ptr<clang::CompilerInvocation> base;
  std::string runtimeHeader;
  std::unique_ptr<char[]> text;
  std::unique_ptr<llvm::MemoryBuffer> remapped;
  std::unique_ptr<llvm::LLVMContext> ctx;
  std::shared_ptr<std::string> backendErrors;
  DiagCollector dc;
  std::unique_ptr<clang::CompilerInstance> ci;
  std::unique_ptr<clang::EmitLLVMOnlyAction> action;
  bool begun = false;
};

struct LevelSetup {
  std::mutex mutex;
  std::shared_ptr<clang::CompilerInvocation> base;
  std::vector<std::string> cc1Args;
  std::string pchPath;
  bool pchReady = false;    // pchPath holds a PCH this process built or already used successfully
  bool pchFallback = false; // PCH unusable (unwritable cache...): include the header as text
  // The quick tiers' next front end, begun on another thread after each compile (Frontend).
  std::future<std::unique_ptr<Frontend>> ahead;
};

// Level 0 builds its PCH with clang's -fpch-codegen: the runtime header's inline functions and
// the templates the PCH instantiated are compiled once, into a support object loaded into its
// own JITDylib, and every model compiled against that PCH links to it instead of emitting its
// own copies. At -O0 nothing is inlined, so those copies were most of a small model's object
// (sunflower: 51 functions, 24 its own) and of its instruction selection time. Higher levels
// keep their own copies, which they inline.
static bool pchCodegen(int level) { return level == 0; }

struct Compiler::Impl {
  CompilerConfig config;
  std::string headerDir;
  std::string cacheDir;
  orc::JITTargetMachineBuilder jtmb{llvm::Triple()};
  std::shared_ptr<detail::JitState> state;
  std::array<LevelSetup, 3> levels;
  // Objects of recent compiles by key, newest last (a reload of unchanged source, a tier swap
  // back and forth); older ones come from the disk cache.
  std::mutex objectsMutex;
  std::vector<std::pair<std::string, std::shared_ptr<const CachedObject>>> objects;
  static constexpr size_t kObjectsInMemory = 16;
  static constexpr size_t kObjectsOnDisk = 256;

  llvm::Expected<std::string> emitObject(llvm::Module& m, int level);
  std::shared_ptr<const CachedObject> findObject(const std::string& key, bool& fromDisk);
  void keepObject(const std::string& key, std::shared_ptr<const CachedObject> object);

  llvm::Error setupLevel(LevelSetup& L, int level);
  std::string pchKey(const LevelSetup& L, int level);
  // Makes sure L has a usable PCH (or falls back); reports whether one from disk was reused.
  void ensurePch(LevelSetup& L, int level, bool forceRebuild, CompileStats& st);
  // The JITDylib holding the support object of the -fpch-codegen PCH at pchPath: loaded from
  // the cache (pchPath + ".o") or compiled from the PCH and stored there first.
  // Building it takes ~0.4 s and loading it ~3 ms, so the first compile against a PCH starts
  // it on another thread (startSupport) and only waits for it (supportDylib) before linking.
  struct Support {
    std::shared_future<void> ready;
    orc::JITDylib* jd = nullptr;
    std::string error;
  };
  std::shared_ptr<Support> startSupport(const LevelSetup& L, const std::string& pchPath);
  llvm::Expected<orc::JITDylib*> supportDylib(const LevelSetup& L, const std::string& pchPath);
  llvm::Expected<orc::JITDylib*> loadSupport(std::shared_ptr<clang::CompilerInvocation> base,
                                             const std::string& pchPath, unsigned number);
  static constexpr size_t kSupportPartSize = 32;
  std::mutex supportMutex;
  std::map<std::string, std::shared_ptr<Support>> supports;
  unsigned supportsStarted = 0;

  ~Impl() {
    for (auto& [path, support] : supports)
      support->ready.wait();
    for (auto& L : levels)
      if (L.ahead.valid())
        L.ahead.wait();
  }
  bool buildPch(LevelSetup& L, int level, const std::string& finalPath, std::string& diagnostics);
  static constexpr size_t kPchsKept = 3;
  static void prunePchs(const std::string& built);

  // The quick tiers' front end begun ahead (Frontend) if there is one that fits this compile;
  // a mismatched or failed one is dropped.
  std::unique_ptr<Frontend> takeAhead(LevelSetup& L, const LevelSetup& used, const std::string& bufferName,
                                      size_t size);
  // Begins the next front end of a quick tier on another thread, unless one is under way.
  void beginAhead(LevelSetup& L, const LevelSetup& used, const std::string& bufferName, size_t size);
  static constexpr size_t kAheadCapacity = 64 * 1024;

};

llvm::Error Compiler::Impl::setupLevel(LevelSetup& L, int level) {
  if (L.base)
    return llvm::Error::success();
  std::vector<std::string> args = {kClangPath,
                                   // gnu++14 unless the model asks (CompilerConfig).
                                   "-std=" + config.languageStandard,
                                   "-w",
                                   // g++ warns about narrowing in braces; clang refuses it.
                                   "-Wno-c++11-narrowing",
                                   "-O" + std::to_string(level),
                                   "-march=native",
                                   // lpfg builds models with g++ -O3 for the x86-64 baseline, which
                                   // has no fused multiply-add: a*b+c is rounded twice there, so
                                   // it must be here too, or the last bits (and, through
                                   // thresholds, whole strings) differ from lpfg's.
                                   "-ffp-contract=off",
                                   "-fpch-instantiate-templates",
                                   "-resource-dir",
                                   kResourceDir,
                                   "-I",
                                   headerDir};
  // Level 0 (the quick tier) without library builtins: with them, clang looks up every builtin
  // name (printf, sqrt, memcpy ...) in the PCH before Sema exists and then deserializes each
  // declaration it finds, ~2 ms of every compile. Unoptimised code gains nothing from them.
  if (level == 0)
    args.push_back("-fno-builtin");
  for (const auto& d : config.includeDirs) {
    args.push_back("-I");
    args.push_back(d);
  }
  args.insert(args.end(), {"-c", kPlaceholderInput, "-o", "lcjit-output.o"});
  std::vector<const char*> argv;
  for (const auto& a : args)
    argv.push_back(a.c_str());

  DiagCollector dc;
  clang::CreateInvocationOptions opts;
  opts.Diags = clang::CompilerInstance::createDiagnostics(new clang::DiagnosticOptions, &dc, false);
  opts.CC1Args = &L.cc1Args;
  std::unique_ptr<clang::CompilerInvocation> inv = clang::createInvocation(argv, std::move(opts));
  if (!inv)
    return llvm::createStringError("lcjit: cannot set up the clang invocation:\n" + trimTrailingNewlines(dc.text));
  inv->getFrontendOpts().DisableFree = false; // createInvocation leaves it on: ~6 MB leak per compile
  inv->getCodeGenOpts().DisableFree = false;  // and this one: clang's back end buried a TargetMachine (~28 KB) per compile
  inv->getLangOpts().PCHInstantiateTemplates = true;
  // IR passes run in runIRPipeline so that their time is measured and level 1 can differ.
  inv->getCodeGenOpts().DisableLLVMPasses = true;
  // Otherwise ExecuteAction prints "N errors generated." to stderr.
  inv->getDiagnosticOpts().ShowCarets = false;
  L.base = std::shared_ptr<clang::CompilerInvocation>(std::move(inv));
  return llvm::Error::success();
}

// Hash of everything a PCH depends on: the runtime header's directory tree (content), the
// compiler version, the full cc1 command line (opt level, -D, target CPU + features).
std::string Compiler::Impl::pchKey(const LevelSetup& L, int level) {
  llvm::SHA256 h;
  h.update(clang::getClangFullVersion());
  h.update(LLVM_VERSION_STRING);
  h.update(config.runtimeHeader);
  for (const auto& a : L.cc1Args) {
    // The working directory reaches the cc1 line but not the PCH; keep it out of the key so the
    // cache is shared between directories.
    if (llvm::StringRef(a).starts_with("-fdebug-compilation-dir") ||
        llvm::StringRef(a).starts_with("-fcoverage-compilation-dir"))
      continue;
    h.update(a);
    h.update(llvm::StringRef("\0", 1));
  }
  h.update(llvm::sys::getHostCPUName());
  if (pchCodegen(level))
    h.update(llvm::StringRef("pch-codegen"));
  frontend::hashDirectoryTree(h, headerDir);
  auto digest = h.final();
  std::string hex = llvm::toHex(digest, /*LowerCase=*/true).substr(0, 24);
  std::string stem = llvm::sys::path::stem(config.runtimeHeader).str();
  return stem + "-O" + std::to_string(level) + "-" + hex + ".pch";
}

bool Compiler::Impl::buildPch(LevelSetup& L, int level, const std::string& finalPath, std::string& diagnostics) {
  std::error_code ec = llvm::sys::fs::create_directories(cacheDir);
  if (ec) {
    diagnostics = "cannot create cache directory '" + cacheDir + "': " + ec.message();
    return false;
  }
  // Unique temp name in the same directory, then rename: readers never see a partial file even
  // when several processes (ctest -j) build the same PCH at once.
  llvm::SmallString<256> tmp;
  int fd = -1;
  ec = llvm::sys::fs::createUniqueFile(finalPath + ".tmp-%%%%%%%%", fd, tmp);
  if (ec) {
    diagnostics = "cannot create a temporary file in '" + cacheDir + "': " + ec.message();
    return false;
  }
  ::close(fd);

  auto inv = std::make_shared<clang::CompilerInvocation>(*L.base);
  auto& fo = inv->getFrontendOpts();
  fo.Inputs.clear();
  fo.Inputs.emplace_back(config.runtimeHeader,
                         clang::InputKind(clang::Language::CXX, clang::InputKind::Source, false,
                                          clang::InputKind::HeaderUnit_None, /*HD=*/true));
  fo.OutputFile = std::string(tmp);
  fo.ProgramAction = clang::frontend::GeneratePCH;
  fo.DisableFree = false;
  if (pchCodegen(level))
    inv->getLangOpts().ModulesCodegen = true;

  DiagCollector dc;
  clang::GeneratePCHAction action;
  bool ok = executeClang(inv, action, dc);
  if (ok) {
    // A support object beside it belongs to the PCH it replaces; a JITDylib loaded from that one
    // stays with the models already linked to it.
    llvm::sys::fs::remove(finalPath + ".o");
    {
      std::lock_guard<std::mutex> lock(supportMutex);
      if (auto it = supports.find(finalPath); it != supports.end()) {
        it->second->ready.wait();
        supports.erase(it);
      }
    }
    ec = llvm::sys::fs::rename(tmp, finalPath);
    if (ec) {
      dc.text += "cannot move the PCH into place: " + ec.message() + "\n";
      ok = false;
    }
  }
  if (!ok)
    llvm::sys::fs::remove(tmp);
  else
    prunePchs(finalPath);
  diagnostics = dc.text;
  return ok;
}

// Each runtime-header version (and each checkout) gets its own ~9 MB PCH per level; keep the
// newest kPchsKept of a level beside a new one. A process still using a removed one keeps its
// mapping; one about to use it rebuilds it (compile()'s retry).
void Compiler::Impl::prunePchs(const std::string& built) {
  namespace fs = std::filesystem;
  std::string name = fs::path(built).filename().string();  // STEM-O<level>-<hash>.pch
  std::string prefix = name.substr(0, name.rfind('-') + 1);
  std::vector<std::pair<fs::file_time_type, fs::path>> same;
  std::error_code ec;
  for (fs::directory_iterator it(fs::path(built).parent_path(), ec), end; !ec && it != end; it.increment(ec)) {
    std::string other = it->path().filename().string();
    if (other.rfind(prefix, 0) == 0 && it->path().extension() == ".pch" && other.find(".tmp-") == std::string::npos)
      same.emplace_back(it->last_write_time(ec), it->path());
  }
  if (same.size() <= kPchsKept)
    return;
  std::sort(same.begin(), same.end());
  for (size_t i = 0; i + kPchsKept < same.size(); ++i)
    if (same[i].second.filename() != name) {
      fs::remove(same[i].second, ec);
      fs::remove(same[i].second.string() + ".o", ec);  // its support object, if any
    }
}

void Compiler::Impl::ensurePch(LevelSetup& L, int level, bool forceRebuild, CompileStats& st) {
  if (L.pchFallback)
    return;
  if (L.pchReady && !forceRebuild) {
    st.pchCached = true;
    return;
  }
  auto t0 = Clock::now();
  // Recomputed here (not cached) so that a runtime header edited while we run gets a new key.
  std::string path = cacheDir + "/" + pchKey(L, level);
  L.pchPath = path;
  if (!forceRebuild && llvm::sys::fs::exists(path)) {
    // Validity is checked by the compile that uses it; a stale or corrupt file comes back here
    // with forceRebuild.
    L.pchReady = true;
    st.pchCached = true;
    st.pchBuildMs += msSince(t0);
    return;
  }
  if (L.ahead.valid())
    L.ahead.get();  // begun on the PCH being replaced
  std::string diags;
  if (buildPch(L, level, path, diags)) {
    L.pchReady = true;
    st.pchCached = false;
  } else {
    // Still compile, just slower; if the header itself is broken the model compile reports it.
    L.pchFallback = true;
    L.pchReady = false;
    if (std::getenv("LCJIT_VERBOSE"))
      llvm::errs() << "lcjit: PCH build failed, including the runtime header as text:\n" << diags;
  }
  st.pchBuildMs += msSince(t0);
}

std::unique_ptr<Frontend> Compiler::Impl::takeAhead(LevelSetup& L, const LevelSetup& used,
                                                     const std::string& bufferName, size_t size) {
  std::lock_guard<std::mutex> lock(L.mutex);
  if (!L.ahead.valid() || L.ahead.wait_for(std::chrono::seconds(0)) != std::future_status::ready)
    return nullptr;
  std::unique_ptr<Frontend> fe = L.ahead.get();
  if (!fe || fe->bufferName != bufferName || fe->pchPath != used.pchPath || fe->pchFallback != used.pchFallback ||
      fe->capacity < size)
    return nullptr;
  return fe;
}

void Compiler::Impl::beginAhead(LevelSetup& L, const LevelSetup& used, const std::string& bufferName, size_t size) {
  std::lock_guard<std::mutex> lock(L.mutex);
  if (L.ahead.valid())
    return;
  size_t capacity = std::max(kAheadCapacity, 2 * size);
  L.ahead = std::async(std::launch::async, [base = used.base, pch = used.pchPath, fallback = used.pchFallback,
                                            header = config.runtimeHeader, bufferName, capacity] {
    clang::noteBottomOfStack();
    auto fe = std::make_unique<Frontend>(base, pch, fallback, header, bufferName, capacity);
    if (!fe->begin())
      fe.reset();  // the compile that would have used it finds out why on its own
    return fe;
  });
}

std::shared_ptr<Compiler::Impl::Support> Compiler::Impl::startSupport(const LevelSetup& L, const std::string& pchPath) {
  std::lock_guard<std::mutex> lock(supportMutex);
  auto& support = supports[pchPath];
  if (!support) {
    support = std::make_shared<Support>();
    support->ready = std::async(std::launch::async, [this, s = support.get(), base = L.base, pchPath,
                                                     number = supportsStarted++] {
                       auto jd = loadSupport(base, pchPath, number);
                       if (jd)
                         s->jd = *jd;
                       else
                         s->error = llvm::toString(jd.takeError());
                     }).share();
  }
  return support;
}

llvm::Expected<orc::JITDylib*> Compiler::Impl::supportDylib(const LevelSetup& L, const std::string& pchPath) {
  std::shared_ptr<Support> support = startSupport(L, pchPath);
  support->ready.wait();
  if (!support->jd)
    return llvm::createStringError(support->error);
  return support->jd;
}

// Splits the support module into parts of `perPart` definitions, in order of their demangled
// names so that related functions (all of __lc_emit_*, one class's members) share a part. Each
// part is one object file and ORC links an object only when a symbol of it is first looked up,
// so a model pays for the parts it uses; the whole (~2,000 functions, mostly libstdc++ templates
// the header instantiated) took ~15 ms to link. Locals become hidden globals so that parts can
// reach each other's, and COMDATs go: each definition exists once.
static std::vector<std::unique_ptr<llvm::Module>> splitIntoParts(llvm::Module& m, size_t perPart) {
  for (llvm::GlobalValue& gv : m.global_values()) {
    if (gv.getName().starts_with("llvm."))
      continue;
    if (auto* go = llvm::dyn_cast<llvm::GlobalObject>(&gv))
      go->setComdat(nullptr);
    if (!gv.hasName())
      gv.setName("lcjit.support.unnamed");
    if (gv.hasLocalLinkage()) {
      gv.setLinkage(llvm::GlobalValue::ExternalLinkage);
      gv.setVisibility(llvm::GlobalValue::HiddenVisibility);
    } else if (gv.hasWeakLinkage() || gv.hasLinkOnceLinkage()) {
      gv.setLinkage(llvm::GlobalValue::ExternalLinkage);
    }
  }
  m.getComdatSymbolTable().clear();
  std::vector<std::pair<std::string, const llvm::GlobalObject*>> defs;
  for (const llvm::GlobalObject& go : m.global_objects())
    if (!go.isDeclaration() && !go.getName().starts_with("llvm."))
      defs.emplace_back(llvm::demangle(go.getName().str()), &go);
  std::sort(defs.begin(), defs.end());
  std::map<const llvm::GlobalValue*, size_t> partOf;
  for (size_t i = 0; i < defs.size(); ++i)
    partOf[defs[i].second] = i / perPart;
  for (const llvm::GlobalAlias& a : m.aliases())
    if (const llvm::GlobalObject* target = a.getAliaseeObject(); target && partOf.count(target))
      partOf[&a] = partOf[target];
  std::vector<std::unique_ptr<llvm::Module>> parts;
  for (size_t p = 0; p * perPart < defs.size(); ++p) {
    llvm::ValueToValueMapTy map;
    parts.push_back(llvm::CloneModule(m, map, [&](const llvm::GlobalValue* gv) {
      auto it = partOf.find(gv);
      return it != partOf.end() && it->second == p;
    }));
  }
  return parts;
}

// The support objects' cache file: "lcjit-support 1\n", then per object "SIZE\n" and its bytes.
static std::string serializeParts(const std::vector<std::string>& parts) {
  std::string out = "lcjit-support 1\n";
  for (const std::string& part : parts)
    out += std::to_string(part.size()) + "\n" + part;
  return out;
}

static std::optional<std::vector<std::string>> deserializeParts(llvm::StringRef in) {
  if (!in.consume_front("lcjit-support 1\n"))
    return std::nullopt;
  std::vector<std::string> parts;
  while (!in.empty()) {
    auto [size, rest] = in.split('\n');
    size_t n = 0;
    if (size.getAsInteger(10, n) || rest.size() < n)
      return std::nullopt;
    parts.push_back(rest.take_front(n).str());
    in = rest.drop_front(n);
  }
  return parts;
}

llvm::Expected<orc::JITDylib*> Compiler::Impl::loadSupport(std::shared_ptr<clang::CompilerInvocation> base,
                                                           const std::string& pchPath, unsigned number) {
  std::string cachePath = pchPath + ".o";
  std::optional<std::vector<std::string>> parts;
  if (auto file = llvm::MemoryBuffer::getFile(cachePath, /*IsText=*/false, /*RequiresNullTerminator=*/false))
    parts = deserializeParts((*file)->getBuffer());
  bool fresh = !parts;
  if (fresh) {
    // The PCH as the input: clang emits what it marked for codegen (as `clang -c x.pch`).
    auto inv = std::make_shared<clang::CompilerInvocation>(*base);
    auto& fo = inv->getFrontendOpts();
    fo.Inputs.clear();
    fo.Inputs.emplace_back(pchPath, clang::InputKind(clang::Language::CXX, clang::InputKind::Precompiled));
    fo.OutputFile.clear();
    fo.DisableFree = false;
    inv->getCodeGenOpts().MainFileName = pchPath;
    DiagCollector dc;
    llvm::LLVMContext ctx;
    clang::EmitLLVMOnlyAction action(&ctx);
    std::unique_ptr<llvm::Module> module;
    if (executeClang(inv, action, dc))
      module = action.takeModule();
    if (!module)
      return llvm::createStringError("lcjit: cannot compile the runtime header's support code from " + pchPath + ":\n" +
                       trimTrailingNewlines(dc.text));
    gatherInitializers(*module);
    // always_inline callees (libstdc++'s allocators) go
    if (auto err = state->codegen[0].optimize(*module, 0, jtmb, llvm::CodeGenOptLevel::None))
      return std::move(err);
    parts.emplace();
    for (auto& part : splitIntoParts(*module, kSupportPartSize)) {
      auto object = emitObject(*part, 0);
      if (!object)
        return object.takeError();
      parts->push_back(std::move(*object));
    }
    frontend::writeCacheFile(cachePath, serializeParts(*parts));  // failing only costs a later build
  }

  auto& J = *state->jit;
  std::lock_guard<std::mutex> jitLock(state->mutex);
  auto jd = J.createJITDylib("lcjit.support." + std::to_string(number));
  if (!jd)
    return jd.takeError();
  orc::JITDylibSearchOrder order;
  state->appendRuntime(order);
  jd->setLinkOrder(std::move(order), /*LinkAgainstThisJITDylibFirst=*/true);
  orc::SymbolLookupSet oneOfEach;
  for (size_t i = 0; i < parts->size(); ++i) {
    auto buffer = llvm::MemoryBuffer::getMemBufferCopy((*parts)[i], cachePath + "#" + std::to_string(i));
    if (fresh) {
      auto symbols = orc::getObjectFileInterface(J.getExecutionSession(), buffer->getMemBufferRef());
      if (!symbols)
        return symbols.takeError();
      if (!symbols->SymbolFlags.empty())
        oneOfEach.add(symbols->SymbolFlags.begin()->first);
    }
    if (auto err = J.addObjectFile(*jd, std::move(buffer)))
      return std::move(err);
  }
  // A freshly built support links every part once, so that a problem shows here rather than as
  // a bad call from the first model that uses the part.
  state->takeSessionErrors();
  if (fresh) {
    if (auto linked = J.getExecutionSession().lookup(
            orc::makeJITDylibSearchOrder(&*jd, orc::JITDylibLookupFlags::MatchAllSymbols), std::move(oneOfEach));
        !linked) {
      std::string cause = trimTrailingNewlines(state->takeSessionErrors());
      llvm::consumeError(linked.takeError());
      llvm::sys::fs::remove(cachePath);
      return llvm::createStringError("lcjit: cannot link the runtime header's support code: " + cause);
    }
  }
  if (auto err = J.initialize(*jd))
    return std::move(err);
  return &*jd;
}

Compiler::Compiler(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Compiler::~Compiler() = default;
const std::string& Compiler::cacheDir() const { return impl_->cacheDir; }

llvm::Expected<std::unique_ptr<Compiler>> Compiler::create(CompilerConfig config) {
  static std::once_flag targetsOnce;
  std::call_once(targetsOnce, [] {
    llvm::InitializeNativeTarget();
    llvm::InitializeNativeTargetAsmPrinter();
    llvm::InitializeNativeTargetAsmParser();
  });

  if (config.runtimeHeader.empty() || !llvm::sys::path::is_absolute(config.runtimeHeader))
    return llvm::createStringError("lcjit: runtimeHeader must be an absolute path, got '" + config.runtimeHeader + "'");
  if (!llvm::sys::fs::is_regular_file(config.runtimeHeader))
    return llvm::createStringError("lcjit: runtime header '" + config.runtimeHeader + "' not found");

  auto impl = std::make_unique<Impl>();
  impl->headerDir = llvm::sys::path::parent_path(config.runtimeHeader).str();
  impl->cacheDir = config.cacheDir.empty() ? defaultCacheDir() : config.cacheDir;
  impl->config = std::move(config);

  auto jtmb = orc::JITTargetMachineBuilder::detectHost();
  if (!jtmb)
    return jtmb.takeError();
  // JITLink on x86-64 wants PIC + small code model (LLJIT sets the same on its own copy).
  jtmb->setCodeModel(llvm::CodeModel::Small);
  jtmb->setRelocationModel(llvm::Reloc::PIC_);
  // No fused multiply-add in code generation either (see -ffp-contract=off in setupLevel).
  jtmb->getOptions().AllowFPOpFusion = llvm::FPOpFusion::Strict;
  impl->jtmb = *jtmb;

  auto state = std::make_shared<detail::JitState>();
  // Model code arrives as object files (Impl::emitObject); what ORC still compiles from IR is
  // its own small support modules (__dso_handle, the atexit helpers of each JITDylib), with the
  // quick tiers' TargetMachine.
  struct SupportCompiler : orc::IRCompileLayer::IRCompiler {
    SupportCompiler(orc::JITTargetMachineBuilder b, detail::Codegen& cg)
        : IRCompiler(orc::irManglingOptionsFromTargetOptions(b.getOptions())), jtmb(std::move(b)), cg(cg) {}
    llvm::Expected<std::unique_ptr<llvm::MemoryBuffer>> operator()(llvm::Module& m) override {
      return cg.compile(m, jtmb, llvm::CodeGenOptLevel::None);
    }
    orc::JITTargetMachineBuilder jtmb;
    detail::Codegen& cg;
  };
  detail::Codegen& fast = state->codegen[0];
  auto jit = orc::LLJITBuilder()
                 .setJITTargetMachineBuilder(*jtmb)
                 .setCompileFunctionCreator([&fast](orc::JITTargetMachineBuilder b)
                                                -> llvm::Expected<std::unique_ptr<orc::IRCompileLayer::IRCompiler>> {
                   return std::make_unique<SupportCompiler>(std::move(b), fast);
                 })
                 .create();
  if (!jit)
    return jit.takeError();
  state->jit = std::move(*jit);
  detail::JitState* raw = state.get();
  state->jit->getExecutionSession().setErrorReporter([raw](llvm::Error err) {
    std::string msg = llvm::toString(std::move(err));
    std::lock_guard<std::mutex> lock(raw->errorMutex);
    raw->sessionErrors += msg + "\n";
  });

  // Host functions get their own JITDylib, defined explicitly: no process-symbol generator on a
  // model's dylib (the study saw JIT'd static destructors crash or hang at exit with one).
  auto hostJD = state->jit->createJITDylib("lcjit.host");
  if (!hostJD)
    return hostJD.takeError();
  state->hostJD = &*hostJD;
  if (!impl->config.hostSymbols.empty()) {
    orc::SymbolMap syms;
    for (const auto& s : impl->config.hostSymbols)
      syms[state->jit->mangleAndIntern(s.name)] = {orc::ExecutorAddr::fromPtr(s.address),
                                                    llvm::JITSymbolFlags::Exported};
    if (auto err = state->hostJD->define(orc::absoluteSymbols(std::move(syms))))
      return std::move(err);
  }
  impl->state = std::move(state);
  return std::unique_ptr<Compiler>(new Compiler(std::move(impl)));
}

llvm::Expected<std::string> Compiler::Impl::emitObject(llvm::Module& m, int level) {
  // Fast instruction selection for the quick tiers: on lightly optimised IR the SelectionDAG
  // backend was the slowest part of a compile (see the latency study).
  auto buffer = state->codegen[level >= 2 ? 1 : 0].compile(
      m, jtmb, level >= 2 ? llvm::CodeGenOptLevel::Default : llvm::CodeGenOptLevel::None);
  if (!buffer)
    return buffer.takeError();
  return (*buffer)->getBuffer().str();
}

std::shared_ptr<const CachedObject> Compiler::Impl::findObject(const std::string& key, bool& fromDisk) {
  fromDisk = false;
  {
    std::lock_guard<std::mutex> lock(objectsMutex);
    for (auto& [k, object] : objects)
      if (k == key)
        return object;
  }
  auto file = llvm::MemoryBuffer::getFile(cacheDir + "/objects/" + key + ".o", /*IsText=*/false,
                                          /*RequiresNullTerminator=*/false);
  if (!file)
    return nullptr;
  auto object = deserialize((*file)->getBuffer());
  if (!object)
    return nullptr;  // a foreign or truncated file: compile again (and overwrite it)
  fromDisk = true;
  auto shared = std::make_shared<const CachedObject>(std::move(*object));
  keepObject(key, shared);
  return shared;
}

void Compiler::Impl::keepObject(const std::string& key, std::shared_ptr<const CachedObject> object) {
  std::lock_guard<std::mutex> lock(objectsMutex);
  std::erase_if(objects, [&](auto& e) { return e.first == key; });
  objects.emplace_back(key, std::move(object));
  if (objects.size() > kObjectsInMemory)
    objects.erase(objects.begin());
}

// Writes the object to the disk cache (temporary file + rename, as for the PCH) and, every so
// many stores (listing the folder is not free), keeps the cache to its newest `keep` entries.
// Failures only cost a later compile.
static void storeObject(const std::string& dir, const std::string& key, const CachedObject& object, size_t keep) {
  static std::atomic<unsigned> stores{0};
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!frontend::writeCacheFile(dir + "/" + key + ".o", serialize(object)))
    return;
  if (stores++ % 32 != 0)
    return;
  std::vector<std::pair<fs::file_time_type, fs::path>> files;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->path().extension() == ".o")
      files.emplace_back(it->last_write_time(ec), it->path());
  if (files.size() <= keep)
    return;
  std::sort(files.begin(), files.end());
  for (size_t i = 0; i + keep < files.size(); ++i)
    fs::remove(files[i].second, ec);
}

llvm::Expected<std::unique_ptr<ModelCode>> Compiler::compile(llvm::StringRef cppSource,
                                                             const CompileOptions& options,
                                                             CompileStats* statsOut) {
  // Lets clang move deep recursion onto a bigger stack instead of overflowing ours.
  clang::noteBottomOfStack();
  CompileStats st;
  auto finish = [&] {
    if (statsOut)
      *statsOut = st;
  };
  int level = options.optLevel;
  if (level < 0 || level > 2)
    return llvm::createStringError("lcjit: optLevel must be 0, 1 or 2, got " + llvm::Twine(level));
  std::string bufferName = options.bufferName.empty() ? std::string("model.cpp") : options.bufferName;
  LevelSetup& L = impl_->levels[level];
  std::vector<std::shared_ptr<detail::Dylib>> stateOwners, linked;
  std::set<std::string> shared;
  for (const ModelCode* code : options.shareStateWith) {
    stateOwners.push_back(code->dylib_);
    shared.insert(code->dylib_->stateNames.begin(), code->dylib_->stateNames.end());
  }
  for (const ModelCode* code : options.linkAgainst)
    linked.push_back(code->dylib_);

  // The object cache's key: everything the object depends on. The PCH's name hashes the
  // compiler, the cc1 line and the runtime header tree; quoted includes are already expanded
  // into the source by the preprocessor.
  std::string key;
  LevelSetup used;  // the invocation and PCH the object is compiled with (or was, if cached)
  {
    std::lock_guard<std::mutex> lock(L.mutex);
    if (auto err = impl_->setupLevel(L, level))
      return std::move(err);
    used.base = L.base;
    if (!options.plainUnit) {
      impl_->ensurePch(L, level, false, st);
      used.pchPath = L.pchPath;
      used.pchFallback = L.pchFallback;
      if (pchCodegen(level) && !used.pchFallback)
        impl_->startSupport(used, used.pchPath);
    }
    llvm::SHA256 h;
    // This build of lcjit's code generation too: an object made by an older one (other IR
    // passes) is not this one's.
    static constexpr const char* kBuild = __DATE__ " " __TIME__;
    for (llvm::StringRef part : {llvm::StringRef(kBuild), llvm::StringRef(used.pchPath),
                                 llvm::StringRef(options.plainUnit ? "plain" : used.pchFallback ? "text" : "pch"),
                                 llvm::StringRef(bufferName), cppSource}) {
      h.update(part);
      h.update(llvm::StringRef("\0", 1));
    }
    for (const std::string& name : shared) {  // which globals are declarations
      h.update(name);
      h.update(llvm::StringRef("\0", 1));
    }
    key = llvm::toHex(h.final(), /*LowerCase=*/true).substr(0, 32) + "-O" + std::to_string(level);
  }

  std::shared_ptr<const CachedObject> object;
  if (options.useObjectCache) {
    bool fromDisk = false;
    object = impl_->findObject(key, fromDisk);
    if (object)
      st.object = fromDisk ? CompileStats::ObjectFrom::Disk : CompileStats::ObjectFrom::Memory;
  }

  std::shared_ptr<std::string> backendErrors;
  // A quick tier begins its next front end once this compile is over (not during it: on two
  // cores it would slow this one's code generation down).
  bool beginNext = false;
  auto aheadOnExit = llvm::make_scope_exit([&] {
    if (beginNext)
      impl_->beginAhead(L, used, bufferName, cppSource.size());
  });
  if (!object) {
    // Front end. The level lock only covers setup/PCH decisions; clang runs unlocked so that
    // compiles on several threads may overlap.
    std::unique_ptr<llvm::LLVMContext> ctx;
    std::unique_ptr<llvm::Module> module;
    bool quickTier = level < 2 && !options.plainUnit;
    for (int attempt = 0;; ++attempt) {
      if (attempt > 0) {
        std::lock_guard<std::mutex> lock(L.mutex);
        impl_->ensurePch(L, level, true, st);
      }
      auto t0 = Clock::now();
      // Snapshot the PCH decision; another thread may rebuild concurrently.
      if (!options.plainUnit) {
        std::lock_guard<std::mutex> lock(L.mutex);
        used.base = L.base;
        used.pchPath = L.pchPath;
        used.pchFallback = L.pchFallback;
      }
      std::unique_ptr<Frontend> fe;
      if (quickTier && attempt == 0)
        fe = impl_->takeAhead(L, used, bufferName, cppSource.size());
      st.frontendBegunAhead = fe != nullptr;
      if (!fe) {
        fe = std::make_unique<Frontend>(used.base, used.pchPath, used.pchFallback, impl_->config.runtimeHeader,
                                        bufferName, cppSource.size());
        fe->begin();
      }
      Frontend::Result fr = fe->finish(cppSource);
      st.frontendMs += msSince(t0);
      beginNext = quickTier && options.beginNextAhead;
      if (fr.module) {
        module = std::move(fr.module);
        ctx = std::move(fr.ctx);
        backendErrors = std::move(fr.backendErrors);
        break;
      }
      if (fr.pchProblem && attempt == 0 && !used.pchFallback && !options.plainUnit) {
        // Stale (header edited, mtime changed) or corrupt PCH: rebuild it and try once more.
        continue;
      }
      finish();
      return llvm::createStringError(trimTrailingNewlines(fr.diagnostics));
    }

    auto t1 = Clock::now();
    CachedObject fresh;
    for (std::string& name : exportState(*module))
      if (!shared.count(name)) {
        const llvm::GlobalVariable* gv = module->getGlobalVariable(name, true);
        fresh.stateSizes.push_back(module->getDataLayout().getTypeAllocSize(gv->getValueType()));
        fresh.stateNames.push_back(std::move(name));
      }
    if (!shared.empty())
      useSharedState(*module, shared);
    gatherInitializers(*module);
    if (auto err = impl_->state->codegen[level >= 2 ? 1 : 0].optimize(
            *module, level, impl_->jtmb, level >= 2 ? llvm::CodeGenOptLevel::Default : llvm::CodeGenOptLevel::None)) {
      finish();
      return std::move(err);
    }
    st.optimizeMs = msSince(t1);

    auto t2 = Clock::now();
    // Any external definition will do: looking it up links the whole object, so link errors
    // (unresolved symbols) surface in compile() instead of at the first call.
    for (const llvm::GlobalValue& gv : module->global_values())
      if (!gv.isDeclaration() && !gv.hasLocalLinkage() && !gv.getName().starts_with("llvm.")) {
        fresh.anchor = gv.getName().str();
        break;
      }
    auto bytes = impl_->emitObject(*module, level);
    st.codegenMs = msSince(t2);
    if (!bytes || !backendErrors->empty()) {
      std::string msg = bytes ? "" : "error: code generation failed: " + llvm::toString(bytes.takeError());
      if (!backendErrors->empty())
        msg = trimTrailingNewlines(*backendErrors);  // the real cause (e.g. bad inline asm)
      finish();
      return llvm::createStringError(msg);
    }
    fresh.object = std::move(*bytes);
    object = std::make_shared<const CachedObject>(std::move(fresh));
    if (options.useObjectCache) {
      impl_->keepObject(key, object);
      storeObject(impl_->cacheDir + "/objects", key, *object, Impl::kObjectsOnDisk);
    }
  }

  // Load into a fresh JITDylib.
  auto t3 = Clock::now();
  orc::JITDylib* support = nullptr;
  if (pchCodegen(level) && !used.pchFallback && !options.plainUnit) {
    auto jd = impl_->supportDylib(used, used.pchPath);
    if (!jd) {
      finish();
      return jd.takeError();
    }
    support = *jd;
  }
  auto& state = *impl_->state;
  std::unique_lock<std::mutex> lock(state.mutex);
  auto& J = *state.jit;
  auto& ES = J.getExecutionSession();
  std::string name = "lcjit.model." + std::to_string(++state.counter);
  auto jdOrErr = J.createJITDylib(name);
  if (!jdOrErr)
    return jdOrErr.takeError();
  orc::JITDylib& JD = *jdOrErr;
  orc::JITDylibSearchOrder order;
  // The shared state first, the runtime last.
  for (const auto& code : linked)
    order.push_back({code->jd, orc::JITDylibLookupFlags::MatchExportedSymbolsOnly});
  for (const auto& owner : stateOwners)
    order.push_back({owner->jd, orc::JITDylibLookupFlags::MatchExportedSymbolsOnly});
  if (support)
    order.push_back({support, orc::JITDylibLookupFlags::MatchExportedSymbolsOnly});
  state.appendRuntime(order);
  JD.setLinkOrder(std::move(order), /*LinkAgainstThisJITDylibFirst=*/true);

  // ORC's lookup error only says which symbols failed to materialize; the cause (e.g. "Symbols
  // not found: [ foo ]") went to the session's error reporter.
  bool initAttempted = false;
  auto runModelCode = [&](const std::function<llvm::Error()>& f) -> llvm::Error {
    return options.runModelCode ? options.runModelCode(f) : f();
  };
  auto fail = [&](llvm::Error err, llvm::StringRef what) -> llvm::Error {
    std::string msg = llvm::toString(std::move(err));
    std::string cause = trimTrailingNewlines(state.takeSessionErrors());
    if (!cause.empty())
      msg = "error: " + what.str() + ": " + cause;
    else
      msg = "error: " + what.str() + ": " + msg;
    if (initAttempted) {
      // Destroy what the initializers managed to construct (registered atexit handlers).
      llvm::consumeError(runModelCode([&] { return runOwnAtExits(J, JD); }));
    }
    state.failedDylibs.push_back(&JD);
    if (auto e = ES.removeJITDylib(JD))
      llvm::consumeError(std::move(e));
    state.takeSessionErrors();
    st.codegenMs += msSince(t3);
    finish();
    return llvm::createStringError(demangleMentions(msg));
  };

  state.takeSessionErrors();
  auto buffer = llvm::MemoryBuffer::getMemBuffer(object->object, name, /*RequiresNullTerminator=*/false);
  if (auto err = J.addObjectFile(JD, std::move(buffer)))
    return fail(std::move(err), "cannot add module");
  if (!object->anchor.empty()) {
    auto sym = ES.lookup(orc::makeJITDylibSearchOrder(&JD, orc::JITDylibLookupFlags::MatchAllSymbols),
                         J.mangleAndIntern(object->anchor));
    if (!sym)
      return fail(sym.takeError(), "JIT link failed");
  }
  // The owned globals' bytes before any constructor ran: what resetState() puts back.
  std::vector<std::pair<void*, std::string>> initialState;
  if (!object->stateNames.empty()) {
    orc::SymbolLookupSet names;
    for (const std::string& n : object->stateNames)
      names.add(J.mangleAndIntern(n));
    auto found = ES.lookup(orc::makeJITDylibSearchOrder(&JD, orc::JITDylibLookupFlags::MatchAllSymbols), names);
    if (!found)
      return fail(found.takeError(), "JIT link failed");
    for (size_t i = 0; i < object->stateNames.size(); ++i) {
      char* at = (*found)[J.mangleAndIntern(object->stateNames[i])].getAddress().toPtr<char*>();
      initialState.emplace_back(at, std::string(at, object->stateSizes[i]));
    }
  }
  // Static constructors of the model. One that throws must not escape with the JITDylib half
  // set up (no ORC locks are held while initializers run, so catching here is safe).
  initAttempted = true;
  if (llvm::Error initErr =
          runModelCode([&] { return callCatching([&] { return J.initialize(JD); }, "static initializer"); }))
    return fail(std::move(initErr), "running static initializers failed");
  // The JITDylib's atexit runner is compiled from IR on first use: do it now rather than when
  // the version is dropped (a reload would wait for it, and at process exit LLVM may be gone).
  if (auto sym = ES.lookup(orc::makeJITDylibSearchOrder(&JD, orc::JITDylibLookupFlags::MatchAllSymbols),
                           J.mangleAndIntern("__lljit_run_atexits"));
      !sym)
    return fail(sym.takeError(), "JIT link failed");
  st.codegenMs += msSince(t3);
  finish();
  auto dylib = std::make_shared<detail::Dylib>();
  dylib->state = impl_->state;
  dylib->jd = &JD;
  dylib->name = std::move(name);
  dylib->stateNames = object->stateNames;
  dylib->stateOwners = std::move(stateOwners);
  dylib->linked = std::move(linked);
  dylib->initialState = std::move(initialState);
  dylib->runModelCode = options.runModelCode;
  lock.unlock();  // ~Dylib takes it
  return std::unique_ptr<ModelCode>(new ModelCode(std::move(dylib)));
}

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

} // namespace lcjit::jit
