// The JIT's long-lived state of OrcState.h: the LLJIT and its host symbols, code generation with
// kept TargetMachines, ORC's own support objects kept between runs, and the end of a loaded version.
#include "jit/OrcState.h"
#include <llvm/ExecutionEngine/Orc/DebugObjectManagerPlugin.h>
#include <llvm/ExecutionEngine/Orc/EPCDebugObjectRegistrar.h>
#include <llvm/ExecutionEngine/Orc/TargetProcess/JITLoaderGDB.h>
#include "support/CacheFiles.h"
#include "jit/CompilerImpl.h"
#include "jit/IRPipeline.h"
#include "jit/ModelMemory.h"
#include "support/InputFile.h"

#include <llvm/ADT/StringExtras.h>
#include <llvm/Config/llvm-config.h>
#include <llvm/ExecutionEngine/Orc/CompileUtils.h>
#include <llvm/ExecutionEngine/Orc/IRCompileLayer.h>
#include <llvm/Object/ELFObjectFile.h>
#include <llvm/Support/Endian.h>
#include <llvm/Support/SHA256.h>
#include <llvm/Support/raw_ostream.h>

#include <filesystem>
#include <map>
#include <optional>

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

namespace {

// ORC's generic platform compiles small IR modules of its own on first use: the __cxa_atexit
// wrapper, and per JITDylib its __dso_handle and atexit helpers. Compiling them was 1.5 ms of a
// run whose model came from the object cache (most of it making a TargetMachine that run needs
// for nothing else), and again on every reload. Their object code is kept by the module's text,
// in memory and in the cache folder. The one value that differs between JITDylibs, __dso_handle
// (the JITDylib's address), is compiled as a marker and written into a copy of the object.
class PlatformObjects {
public:
  PlatformObjects(const orc::JITTargetMachineBuilder& b, std::string objectsDir) : dir_(std::move(objectsDir)) {
    target_ = b.getTargetTriple().str() + " " + b.getCPU() + " " + b.getFeatures().getString() + " " +
              LLVM_VERSION_STRING;
  }

  // The target's data layout, which LLJIT would make a TargetMachine to learn (0.15 ms of a run
  // whose code comes from the cache): kept beside the objects, by the same key.
  std::optional<llvm::DataLayout> dataLayout(const orc::JITTargetMachineBuilder& b) {
    llvm::SHA256 h;
    h.update("lcjit-data-layout 1\n" + target_);
    const std::string file = path(llvm::toHex(h.final(), /*LowerCase=*/true) + ".dl");
    std::unique_ptr<llvm::MemoryBuffer> kept;
    if (!file.empty())
      if (auto read = support::readInputFile(file))
        kept = std::move(*read);
    if (kept) {
      auto dl = llvm::DataLayout::parse(kept->getBuffer());
      if (dl)
        return *dl;
      llvm::consumeError(dl.takeError());  // damaged: made again
    }
    auto dl = orc::JITTargetMachineBuilder(b).getDefaultDataLayoutForTarget();
    if (!dl) {
      llvm::consumeError(dl.takeError());
      return std::nullopt;  // LLJIT finds out why
    }
    write(file, dl->getStringRepresentation(), /*checked=*/false);  // checked by parsing it
    return *dl;
  }

  llvm::Expected<std::unique_ptr<llvm::MemoryBuffer>> compile(llvm::Module& m,
                                                               const std::function<llvm::Expected<std::unique_ptr<llvm::MemoryBuffer>>(llvm::Module&)>& codegen) {
    // The JITDylib's address, replaced by the marker while the module is hashed and compiled.
    std::optional<uint64_t> dsoHandle;
    llvm::GlobalVariable* handle = m.getNamedGlobal("__dso_handle");
    if (handle && handle->hasInitializer()) {
      auto* value = llvm::dyn_cast<llvm::ConstantInt>(handle->getInitializer());
      if (!value || value->getBitWidth() != 64)
        return codegen(m);
      dsoHandle = value->getZExtValue();
      handle->setInitializer(llvm::ConstantInt::get(value->getType(), kMarker));
    }
    std::string text;
    llvm::raw_string_ostream os(text);
    m.print(os, nullptr);
    llvm::SHA256 h;
    h.update("lcjit-platform-object 1\n" + target_ + "\n");
    h.update(text);
    std::string key = llvm::toHex(h.final(), /*LowerCase=*/true);

    std::string object = find(key);
    if (object.empty()) {
      auto compiled = codegen(m);
      if (!compiled)
        return compiled.takeError();
      object = (*compiled)->getBuffer().str();
      keep(key, object);
    }
    if (dsoHandle && !patchDsoHandle(object, *dsoHandle))
      return llvm::createStringError("lcjit: __dso_handle not found in ORC's support object");
    return llvm::MemoryBuffer::getMemBufferCopy(object, m.getModuleIdentifier());
  }

private:
  static constexpr uint64_t kMarker = 0x6c636a69745f6473;  // "lcjit_ds": not zero, so not in .bss

  // A file of ours in the objects folder ("" without one).
  std::string path(const std::string& name) const { return dir_.empty() ? "" : dir_ + "/platform-" + name; }
  void write(const std::string& file, llvm::StringRef bytes, bool checked) {
    if (file.empty())
      return;
    std::error_code ec;
    std::filesystem::create_directories(dir_, ec);
    if (checked)
      support::writeCheckedCacheFile(file, bytes);
    else
      support::writeCacheFile(file, bytes);
  }

  std::string find(const std::string& key) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (auto it = memory_.find(key); it != memory_.end())
        return it->second;
    }
    if (dir_.empty())
      return {};
    support::CheckedRead read = support::readCheckedCacheFile(path(key + ".obj"));
    if (!read.bytes)
      return {};
    std::lock_guard<std::mutex> lock(mutex_);
    return memory_[key] = std::move(*read.bytes);
  }

  void keep(const std::string& key, const std::string& object) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      memory_[key] = object;
    }
    write(path(key + ".obj"), object, /*checked=*/true);
  }

  // Writes `value` over the marker that __dso_handle holds in the relocatable object `object`.
  static bool patchDsoHandle(std::string& object, uint64_t value) {
    auto file = llvm::object::ELF64LEObjectFile::create(llvm::MemoryBufferRef(object, "platform"));
    if (!file) {
      llvm::consumeError(file.takeError());
      return false;
    }
    for (const llvm::object::ELFSymbolRef& sym : file->symbols()) {
      auto name = sym.getName();
      if (!name || *name != "__dso_handle") {
        if (!name)
          llvm::consumeError(name.takeError());
        continue;
      }
      auto elfSym = file->getSymbol(sym.getRawDataRefImpl());
      if (!elfSym) {
        llvm::consumeError(elfSym.takeError());
        return false;
      }
      auto section = file->getELFFile().getSection((*elfSym)->st_shndx);
      if (!section) {
        llvm::consumeError(section.takeError());
        return false;
      }
      uint64_t at = (*section)->sh_offset + (*elfSym)->st_value;
      if ((*section)->sh_type != llvm::ELF::SHT_PROGBITS || at + 8 > object.size() ||
          llvm::support::endian::read64le(object.data() + at) != kMarker)
        return false;
      llvm::support::endian::write64le(object.data() + at, value);
      return true;
    }
    return false;
  }

  std::string dir_;
  std::string target_;
  std::mutex mutex_;
  std::map<std::string, std::string> memory_;
};

}  // namespace

llvm::Expected<std::shared_ptr<JitState>> JitState::create(const orc::JITTargetMachineBuilder& jtmb,
                                                           const std::vector<HostSymbol>& hostSymbols,
                                                           const std::string& objectsDir, bool debugger) {
  auto state = std::make_shared<JitState>();
  // Model code arrives as object files (Impl::emitObject); what ORC still compiles from IR is
  // its own small support modules, with the quick tiers' TargetMachine, once (PlatformObjects).
  struct SupportCompiler : orc::IRCompileLayer::IRCompiler {
    SupportCompiler(orc::JITTargetMachineBuilder b, Codegen& cg, std::shared_ptr<PlatformObjects> kept)
        : IRCompiler(orc::irManglingOptionsFromTargetOptions(b.getOptions())), jtmb(std::move(b)), cg(cg),
          kept(std::move(kept)) {}
    llvm::Expected<std::unique_ptr<llvm::MemoryBuffer>> operator()(llvm::Module& m) override {
      return kept->compile(m, [&](llvm::Module& mod) { return cg.compile(mod, jtmb, llvm::CodeGenOptLevel::None); });
    }
    orc::JITTargetMachineBuilder jtmb;
    Codegen& cg;
    std::shared_ptr<PlatformObjects> kept;
  };
  auto kept = std::make_shared<PlatformObjects>(jtmb, objectsDir);
  Codegen& fast = state->codegen[0];
  // This process runs the code, linked into lcjit's own memory manager (ModelMemory.h), which
  // leaves a model's zero-filled data untouched.
  auto epc = orc::SelfExecutorProcessControl::Create(nullptr, nullptr, std::make_unique<ModelMemory>());
  if (!epc)
    return epc.takeError();
  auto jit = orc::LLJITBuilder()
                 .setExecutorProcessControl(std::move(*epc))
                 .setJITTargetMachineBuilder(jtmb)
                 .setDataLayout(kept->dataLayout(jtmb))
                 .setCompileFunctionCreator([&fast, kept](orc::JITTargetMachineBuilder b)
                                                -> llvm::Expected<std::unique_ptr<orc::IRCompileLayer::IRCompiler>> {
                   return std::make_unique<SupportCompiler>(std::move(b), fast, kept);
                 })
                 .create();
  if (!jit)
    return jit.takeError();
  state->jit = std::move(*jit);
  state->codeMap = std::make_shared<CodeMap>();
  if (auto* linker = llvm::dyn_cast<orc::ObjectLinkingLayer>(&state->jit->getObjLinkingLayer()))
    linker->addPlugin(state->codeMap);
  // The GDB JIT interface (__jit_debug_register_code), which gdb and lldb watch. Its
  // registration function is named by address: with LLVM linked statically and no -rdynamic,
  // orc::enableDebuggerSupport's lookup of it by name in the process finds nothing.
  if (debugger)
    if (auto* linker = llvm::dyn_cast<orc::ObjectLinkingLayer>(&state->jit->getObjLinkingLayer())) {
      auto& es = state->jit->getExecutionSession();
      auto registrar = std::make_unique<orc::EPCDebugObjectRegistrar>(
          es, orc::ExecutorAddr::fromPtr(&llvm_orc_registerJITLoaderGDBWrapper));
      linker->addPlugin(std::make_unique<orc::DebugObjectManagerPlugin>(es, std::move(registrar), /*RequireDebugSections=*/true,
                                                                        /*AutoRegisterCode=*/true));
    }
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
