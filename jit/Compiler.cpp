// Compiler::create, and compile(): from C++ text to loaded model code, as a sequence of stages
// defined below it. How the JIT works, and the measurements behind its design: docs/jit.md.
#include "jit/Compiler.h"
#include "jit/CompilerImpl.h"
#include "support/Elapsed.h"
#include "jit/IRRewrites.h"
#include "jit/StaticData.h"

#include <clang/Basic/Stack.h>
#include <llvm/ADT/ScopeExit.h>
#include <llvm/ADT/Twine.h>
#include <llvm/Demangle/Demangle.h>
#include <llvm/Support/FormatVariadic.h>
#include <llvm/Support/FileSystem.h>
#include <llvm/Support/MemoryBuffer.h>
#include <llvm/Support/Path.h>
#include <llvm/Support/TargetSelect.h>

#include <cctype>
#include <cstdlib>
#include <functional>
#include <mutex>
#include <set>
#include <unistd.h>

namespace lcjit::jit {

namespace {

std::string defaultCacheDir() {
  if (const char* d = std::getenv("LCJIT_CACHE_DIR"); d && *d)
    return d;
  if (const char* d = std::getenv("XDG_CACHE_HOME"); d && *d)
    return std::string(d) + "/lcjit";
  if (const char* d = std::getenv("HOME"); d && *d)
    return std::string(d) + "/.cache/lcjit";
  return "/tmp/lcjit-cache-" + std::to_string(::getuid());
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

// The error of a failed link (`what` failed: `cause`), in the model's terms rather than those of
// lcjit's JITDylibs and the linker's fixups. x86-64 code reaches 2 GB around it (the small code
// model, which JITLink wants): static data beyond that (many large arrays) fail the link with a
// relocation "out of range", which is said as what it is, at the declaration of the variable the
// linker named (or of the largest).
std::string linkFailure(llvm::StringRef what, std::string cause, const CachedObject& object, const StaticData& data) {
  if (cause.find("out of range") != std::string::npos && data.bytes >= (uint64_t(1) << 31)) {
    std::string name = data.largest, at = data.declaredAt;
    const llvm::StringRef marker = "relocation target \"";
    if (size_t from = cause.find(marker.str()); from != std::string::npos)
      if (size_t to = cause.find('"', from + marker.size()); to != std::string::npos) {
        const std::string symbol = cause.substr(from + marker.size(), to - from - marker.size());
        auto it = object.declaredAt.find(symbol);
        name = llvm::demangle(symbol);
        at = it == object.declaredAt.end() ? "" : it->second;
      }
    const std::string gb = llvm::formatv("{0:F2} GB", double(data.bytes) / double(uint64_t(1) << 30)).str();
    return (at.empty() ? "" : at + ": ") + "error: '" + name +
           "' lies farther from the model's code than x86-64 code reaches (2 GB): the model's static data take " + gb +
           "; allocate the large arrays while the model runs (new, std::vector)";
  }
  // "In graph lcjit.model.3, section .text: ...": the graph is the JITDylib's, a name of lcjit's.
  if (llvm::StringRef(cause).starts_with("In graph "))
    if (size_t comma = cause.find(", "); comma != std::string::npos)
      cause.erase(0, comma + 2);
  return "error: " + what.str() + ": " + cause;
}

}  // namespace

// One compile(): its inputs, and what each stage hands to the next.
struct Compiler::Impl::Job {
  Job(llvm::StringRef source, const CompileOptions& options, CompileStats* statsOut)
      : source(source), options(options), level(options.optLevel),
        bufferName(options.bufferName.empty() ? std::string("model.cpp") : options.bufferName), statsOut(statsOut) {}

  const llvm::StringRef source;
  const CompileOptions& options;
  const int level;
  const std::string bufferName;
  std::vector<std::shared_ptr<detail::Dylib>> stateOwners;  // the versions whose globals this one uses
  std::vector<std::shared_ptr<detail::Dylib>> linked;       // the versions whose functions it calls
  std::set<std::string> shared;                             // the globals the stateOwners define
  LevelSetup used;  // the invocation and PCH the object is compiled with (or was, if cached)
  std::string key;  // the object cache's
  bool beginNext = false;  // begin the next front end ahead when this compile is over
  std::shared_ptr<const CachedObject> object;
  CompileStats stats;

  // Hands the stats, as far as they got, to compile()'s caller along with `result`.
  template <class T>
  T report(T result) {
    if (statsOut)
      *statsOut = stats;
    return result;
  }

private:
  CompileStats* const statsOut;
};

Compiler::Compiler(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Compiler::~Compiler() = default;
const std::string& Compiler::cacheDir() const { return impl_->cacheDir; }
std::string Compiler::objectsDir() const { return impl_->objectsDir(); }
void Compiler::settleAtExit() { impl_->settle(); }

const std::string& Compiler::cacheWarning() const { return impl_->cacheWarning; }

std::vector<SourcePlace> Compiler::sourceAt(uintptr_t address, bool returnAddress) const {
  return impl_->state->codeMap->placesAt(address, returnAddress);
}

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
  // Objects in the cache are loaded and run: only a folder that is the user's alone is trusted.
  if (auto err = support::useAsCacheFolder(impl->cacheDir)) {
    impl->cacheWarning = llvm::toString(std::move(err)) +
                         "; this run keeps its compiled code in a private folder, removed when it ends";
    auto own = support::privateCacheFolder();
    if (!own)
      return own.takeError();
    impl->cacheDir = *own;
    impl->privateCache = true;
  }
  impl->config = std::move(config);

  auto jtmb = orc::JITTargetMachineBuilder::detectHost();
  if (!jtmb)
    return jtmb.takeError();
  // JITLink on x86-64 wants PIC + small code model (LLJIT sets the same on its own copy).
  jtmb->setCodeModel(llvm::CodeModel::Small);
  jtmb->setRelocationModel(llvm::Reloc::PIC_);
  // No fused multiply-add in code generation either (see -ffp-contract=off in setupLevel).
  jtmb->getOptions().AllowFPOpFusion = llvm::FPOpFusion::Strict;
  // One section per function: JITLink (LLVM 19) splits a shared .text block at every function's
  // unwind entry, which grows with the square of the functions: 10,000 productions took 1.4 GB
  // and seconds to link, 115 MB with their own sections.
  jtmb->getOptions().FunctionSections = true;
  // And one per variable: the linker then places each by itself (ModelMemory.h lays zero-filled
  // ones out smallest first), so that one huge array does not push the others it would share
  // a .bss with out of the code's reach (2 GB).
  jtmb->getOptions().DataSections = true;
  impl->jtmb = *jtmb;

  auto state = detail::JitState::create(*jtmb, impl->config.hostSymbols, impl->objectsDir(), impl->config.debugger);
  if (!state)
    return state.takeError();
  impl->state = std::move(*state);
  return std::unique_ptr<Compiler>(new Compiler(std::move(impl)));
}

llvm::Expected<std::unique_ptr<ModelCode>> Compiler::compile(llvm::StringRef cppSource,
                                                             const CompileOptions& options,
                                                             CompileStats* statsOut) {
  // Lets clang move deep recursion onto a bigger stack instead of overflowing ours.
  clang::noteBottomOfStack();
  if (options.optLevel < 0 || options.optLevel > 2)
    return llvm::createStringError("lcjit: optLevel must be 0, 1 or 2, got " + llvm::Twine(options.optLevel));
  // An object keyed on a PCH that is not there cannot be in the cache: no PCH is built for it.
  if (options.onlyFromCache && (!options.useObjectCache || (!options.plainUnit && !impl_->pchExists(options.optLevel))))
    return nullptr;
  Impl::Job job(cppSource, options, statsOut);
  for (const ModelCode* code : options.shareStateWith) {
    job.stateOwners.push_back(code->dylib_);
    job.shared.insert(code->dylib_->stateNames.begin(), code->dylib_->stateNames.end());
  }
  for (const ModelCode* code : options.linkAgainst)
    job.linked.push_back(code->dylib_);

  // setUp → the level's invocation and PCH (job.used), the object cache's key (job.key).
  if (auto err = impl_->setUp(job))
    return std::move(err);
  // reusedObject → the object code of an identical earlier compile, if there is one.
  job.object = impl_->reusedObject(job);
  if (options.onlyFromCache && !job.object)
    return nullptr;
  // A quick tier begins its next front end once this compile is over (not during it: on two
  // cores it would slow this one's code generation down).
  auto aheadOnExit = llvm::make_scope_exit([&] {
    if (job.beginNext)
      impl_->beginAhead(impl_->levels[job.level], job.used, job.bufferName, cppSource.size());
  });
  // A reused object that does not load (damaged in memory or on disk, made by a broken build) is
  // forgotten and the source compiled: once.
  for (bool again = false;; again = true) {
    if (!job.object) {
      // parse → the module, its LLVMContext and where its back end reports errors.
      auto ir = impl_->parse(job);
      if (!ir)
        return job.report(ir.takeError());
      // optimize → the module rewritten and optimised; the globals it owns, in `fresh`.
      CachedObject fresh;
      fresh.declaredAt = std::move(ir->declaredAt);
      if (auto err = impl_->optimize(job, *ir->module, fresh))
        return job.report(std::move(err));
      // generateCode → the object code and its anchor, in `fresh`.
      if (auto err = impl_->generateCode(job, *ir, fresh))
        return job.report(std::move(err));
      job.object = std::make_shared<const CachedObject>(std::move(fresh));
    }

    // checkStaticData → what the object's data would take, refused before any of it is
    // allocated if the caller says so (a reused object stays cached: it is not at fault).
    ObjectData data = dataOf(*job.object);
    if (options.checkStaticData)
      if (auto err = options.checkStaticData(data.data))
        return job.report(std::move(err));

    auto loadStart = support::Clock::now();
    // supportCode → the JITDylib of the runtime header's code at level 0 (waited for before the
    // JIT's lock: loading it takes that lock).
    auto support = impl_->supportCode(job);
    if (!support)
      return job.report(support.takeError());
    std::unique_lock<std::mutex> jitLock(impl_->state->mutex);
    // newDylib → an empty JITDylib that looks up the versions this one uses, then the runtime.
    auto jd = impl_->newDylib(job, *support);
    if (!jd)
      return jd.takeError();
    // load → the object linked in it, the model's globals recorded and constructed.
    auto dylib = impl_->load(job, **jd, data, loadStart);
    jitLock.unlock();  // ~Dylib takes it
    const bool reused = job.stats.object != CompileStats::ObjectFrom::Compiled;
    if (!dylib && reused && !again) {
      std::string why = llvm::toString(dylib.takeError());
      const bool fromDisk = job.stats.object == CompileStats::ObjectFrom::Disk;
      impl_->dropObject(job.key);
      job.object = nullptr;
      job.stats.object = CompileStats::ObjectFrom::Compiled;
      job.stats.notes.push_back(cacheNote(fromDisk ? impl_->objectPath(job.key) : "(kept in memory)",
                                          "it would not load (" + why + ")"));
      if (options.onlyFromCache)
        return nullptr;
      continue;
    }
    if (!dylib) {
      if (again)  // the source fails as the reused object did: the cache was not the cause
        job.stats.notes.pop_back();
      return job.report(dylib.takeError());
    }
    // cacheObject → an object compiled here that loaded, kept for an identical later compile.
    if (!reused)
      impl_->cacheObject(job);
    return std::unique_ptr<ModelCode>(new ModelCode(std::move(*job.report(std::move(dylib)))));
  }
}

// Under the level's lock: the level's cc1 line (set up on first use), its PCH made sure of and,
// at level 0, the PCH's support code started; then the object cache's key from what the object
// is to be made with.
llvm::Error Compiler::Impl::setUp(Job& job) {
  LevelSetup& L = levels[job.level];
  std::lock_guard<std::mutex> lock(L.mutex);
  if (auto err = setupLevel(L, job.level))
    return err;
  if (!job.options.plainUnit) {
    ensurePch(L, job.level, false, job.stats);
    job.used.pchPath = L.pchPath;
    job.used.pchFallback = L.pchFallback;
    if (pchCodegen(job.level) && !job.used.pchFallback) {
      if (auto err = ensureBase(L, job.level))
        return err;
      job.used.base = L.base;
      startSupport(job.used, job.used.pchPath);
    }
  }
  std::string unitKind = job.options.plainUnit ? "plain" : job.used.pchFallback ? "text" : "pch";
  if (!job.options.lineTables) unitKind += " without line tables";
  else if (config.debugger) unitKind += " with full debug information";
  job.key = objectKey(job.used.pchPath, unitKind, job.bufferName, job.source, job.shared, job.level);
  if (job.options.useObjectCache)
    job.stats.objectKey = job.key;
  return llvm::Error::success();
}

// The object code of an identical earlier compile, from memory or from the disk cache, if the
// options allow it.
std::shared_ptr<const CachedObject> Compiler::Impl::reusedObject(Job& job) {
  if (!job.options.useObjectCache)
    return nullptr;
  bool fromDisk = false;
  std::string problem;
  std::shared_ptr<const CachedObject> object = findObject(job.key, fromDisk, problem);
  if (!problem.empty())
    job.stats.notes.push_back(cacheNote(objectPath(job.key), problem));
  if (object)
    job.stats.object = fromDisk ? CompileStats::ObjectFrom::Disk : CompileStats::ObjectFrom::Memory;
  return object;
}

// The front end, from the C++ text to an LLVM module: with a front end begun ahead if one fits,
// and once more after rebuilding a stale or corrupt PCH. The level lock only covers setup/PCH
// decisions; clang runs unlocked so that compiles on several threads may overlap.
llvm::Expected<Frontend::Result> Compiler::Impl::parse(Job& job) {
  LevelSetup& L = levels[job.level];
  const CompileOptions& options = job.options;
  bool quickTier = job.level < 2 && !options.plainUnit;
  for (int attempt = 0;; ++attempt) {
    if (attempt > 0) {
      std::lock_guard<std::mutex> lock(L.mutex);
      ensurePch(L, job.level, true, job.stats);
    }
    auto t0 = support::Clock::now();
    // Snapshot the PCH decision; another thread may rebuild concurrently.
    {
      std::lock_guard<std::mutex> lock(L.mutex);
      if (auto err = ensureBase(L, job.level))
        return std::move(err);
      job.used.base = L.base;
      if (!options.plainUnit) {
        job.used.pchPath = L.pchPath;
        job.used.pchFallback = L.pchFallback;
      }
    }
    std::unique_ptr<Frontend> fe;
    if (quickTier && attempt == 0 && options.lineTables && !config.debugger)  // those begun ahead have them
      fe = takeAhead(L, job.used, job.bufferName, job.source.size());
    job.stats.frontendBegunAhead = fe != nullptr;
    if (!fe) {
      fe = std::make_unique<Frontend>(job.used.base, job.used.pchPath, job.used.pchFallback, config.runtimeHeader,
                                      job.bufferName, job.source.size());
      fe->lineTables = options.lineTables;
      fe->fullDebugInfo = config.debugger;
      fe->begin();
    }
    Frontend::Result fr = fe->finish(job.source);
    job.stats.frontendMs += support::msSince(t0);
    job.beginNext = quickTier && options.beginNextAhead && options.lineTables && !config.debugger;
    if (fr.module)
      return fr;
    if (fr.pchProblem && attempt == 0 && !job.used.pchFallback && !options.plainUnit) {
      // Stale (header edited, mtime changed) or corrupt PCH: rebuild it and try once more.
      continue;
    }
    return llvm::createStringError(trimTrailingNewlines(fr.diagnostics));
  }
}

// The module made ready to share its state and to load as an object (IRRewrites.h), then the
// level's IR passes. The globals it owns (not the shared ones) go into `fresh`.
llvm::Error Compiler::Impl::optimize(Job& job, llvm::Module& module, CachedObject& fresh) {
  auto t1 = support::Clock::now();
  for (std::string& name : exportState(module))
    if (!job.shared.count(name)) {
      const llvm::GlobalVariable* gv = module.getGlobalVariable(name, true);
      fresh.stateSizes.push_back(module.getDataLayout().getTypeAllocSize(gv->getValueType()));
      fresh.stateNames.push_back(std::move(name));
    }
  if (!job.shared.empty())
    useSharedState(module, job.shared);
  gatherInitializers(module);
  int level = job.level;
  if (auto err = state->codegen[level >= 2 ? 1 : 0].optimize(
          module, level, jtmb, level >= 2 ? llvm::CodeGenOptLevel::Default : llvm::CodeGenOptLevel::None))
    return err;
  job.stats.optimizeMs = support::msSince(t1);
  return llvm::Error::success();
}

// Instruction selection into an object file, and a symbol to link it by. An error the back end
// reported (e.g. bad inline asm) fails the compile even when an object came out.
llvm::Error Compiler::Impl::generateCode(Job& job, Frontend::Result& ir, CachedObject& fresh) {
  auto t2 = support::Clock::now();
  // Any external definition will do: looking it up links the whole object, so link errors
  // (unresolved symbols) surface in compile() instead of at the first call.
  for (const llvm::GlobalValue& gv : ir.module->global_values())
    if (!gv.isDeclaration() && !gv.hasLocalLinkage() && !gv.getName().starts_with("llvm.")) {
      fresh.anchor = gv.getName().str();
      break;
    }
  auto bytes = emitObject(*ir.module, job.level);
  job.stats.codegenMs = support::msSince(t2);
  if (!bytes || !ir.backendErrors->empty()) {
    std::string msg = bytes ? "" : "error: code generation failed: " + llvm::toString(bytes.takeError());
    if (!ir.backendErrors->empty())
      msg = trimTrailingNewlines(*ir.backendErrors);  // the real cause (e.g. bad inline asm)
    return llvm::createStringError(msg);
  }
  fresh.object = std::move(*bytes);
  return llvm::Error::success();
}

// The object compiled here, kept in memory and in the disk cache if the options allow it.
void Compiler::Impl::cacheObject(Job& job) {
  if (job.options.useObjectCache) {
    keepObject(job.key, job.object);
    storeObject(job.key, *job.object);
  }
}

// At level 0 against a PCH: the JITDylib of the PCH's support code, once it is ready. Else none.
llvm::Expected<orc::JITDylib*> Compiler::Impl::supportCode(Job& job) {
  if (!pchCodegen(job.level) || job.used.pchFallback || job.options.plainUnit)
    return nullptr;
  return supportDylib(job.used, job.used.pchPath, &job.stats.notes);
}

// A fresh JITDylib for this version, looking up the versions whose functions it calls, then
// those whose state it uses, then the support code, then the runtime. Called with the JIT's lock.
llvm::Expected<orc::JITDylib*> Compiler::Impl::newDylib(const Job& job, orc::JITDylib* support) {
  auto& J = *state->jit;
  std::string name = "lcjit.model." + std::to_string(++state->counter);
  auto jdOrErr = J.createJITDylib(name);
  if (!jdOrErr)
    return jdOrErr.takeError();
  orc::JITDylib& JD = *jdOrErr;
  orc::JITDylibSearchOrder order;
  for (const auto& code : job.linked)
    order.push_back({code->jd, orc::JITDylibLookupFlags::MatchExportedSymbolsOnly});
  for (const auto& owner : job.stateOwners)
    order.push_back({owner->jd, orc::JITDylibLookupFlags::MatchExportedSymbolsOnly});
  if (support)
    order.push_back({support, orc::JITDylibLookupFlags::MatchExportedSymbolsOnly});
  state->appendRuntime(order);
  JD.setLinkOrder(std::move(order), /*LinkAgainstThisJITDylibFirst=*/true);
  return &JD;
}

// Adds the object to JD and links it, records the bytes of the globals it owns, and runs its
// static constructors; on failure, undoes what ran and removes JD. Called with the JIT's lock.
llvm::Expected<std::shared_ptr<detail::Dylib>> Compiler::Impl::load(Job& job, orc::JITDylib& JD, const ObjectData& data,
                                                                    support::Clock::time_point loadStart) {
  auto& J = *state->jit;
  auto& ES = J.getExecutionSession();
  const CachedObject& object = *job.object;
  const CompileOptions& options = job.options;

  // ORC's lookup error only says which symbols failed to materialize; the cause (e.g. "Symbols
  // not found: [ foo ]") went to the session's error reporter.
  bool initAttempted = false;
  auto runModelCode = [&](const std::function<llvm::Error()>& f) -> llvm::Error {
    return options.runModelCode ? options.runModelCode(f) : f();
  };
  auto fail = [&](llvm::Error err, llvm::StringRef what) -> llvm::Error {
    std::string msg = llvm::toString(std::move(err));
    std::string cause = trimTrailingNewlines(state->takeSessionErrors());
    msg = linkFailure(what, cause.empty() ? msg : cause, object, data.data);
    if (initAttempted) {
      // Destroy what the initializers managed to construct (registered atexit handlers).
      llvm::consumeError(runModelCode([&] { return runOwnAtExits(J, JD); }));
    }
    state->failedDylibs.push_back(&JD);
    if (auto e = ES.removeJITDylib(JD))
      llvm::consumeError(std::move(e));
    state->takeSessionErrors();
    job.stats.loadMs += support::msSince(loadStart);
    return llvm::createStringError(demangleMentions(msg));
  };

  state->takeSessionErrors();
  state->codeMap->expect(JD, job.object);
  auto buffer = llvm::MemoryBuffer::getMemBuffer(object.object, JD.getName(), /*RequiresNullTerminator=*/false);
  if (auto err = J.addObjectFile(JD, std::move(buffer)))
    return fail(std::move(err), "cannot add module");
  if (!object.anchor.empty()) {
    auto sym = ES.lookup(orc::makeJITDylibSearchOrder(&JD, orc::JITDylibLookupFlags::MatchAllSymbols),
                         J.mangleAndIntern(object.anchor));
    if (!sym)
      return fail(sym.takeError(), "JIT link failed");
  }
  // The owned globals' bytes before any constructor ran: what resetState() puts back.
  std::vector<detail::Dylib::Initial> initialState;
  if (!object.stateNames.empty()) {
    orc::SymbolLookupSet names;
    for (const std::string& n : object.stateNames)
      names.add(J.mangleAndIntern(n));
    auto found = ES.lookup(orc::makeJITDylibSearchOrder(&JD, orc::JITDylibLookupFlags::MatchAllSymbols), names);
    if (!found)
      return fail(found.takeError(), "JIT link failed");
    for (size_t i = 0; i < object.stateNames.size(); ++i) {
      char* at = (*found)[J.mangleAndIntern(object.stateNames[i])].getAddress().toPtr<char*>();
      const bool zero = data.zeroFilled.count(object.stateNames[i]) > 0;
      initialState.push_back({at, object.stateSizes[i], zero, zero ? std::string() : std::string(at, object.stateSizes[i])});
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
  job.stats.loadMs += support::msSince(loadStart);
  auto dylib = std::make_shared<detail::Dylib>();
  dylib->state = state;
  dylib->jd = &JD;
  dylib->name = JD.getName();
  dylib->stateNames = object.stateNames;
  dylib->stateOwners = std::move(job.stateOwners);
  dylib->linked = std::move(job.linked);
  dylib->initialState = std::move(initialState);
  dylib->runModelCode = options.runModelCode;
  return dylib;
}

}  // namespace lcjit::jit
