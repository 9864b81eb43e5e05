// Clang-as-a-library front end + per-level IR pipelines + one LLJIT, with a disk-cached PCH of
// the runtime header. See docs in Compiler.h and /work/shared/notes/jit-latency-study.md.
#include "jit/Compiler.h"

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

#include <llvm/Analysis/InlineCost.h>
#include <llvm/Config/llvm-config.h>
#include <llvm/Demangle/Demangle.h>
#include <llvm/ExecutionEngine/Orc/CompileUtils.h>
#include <llvm/ExecutionEngine/Orc/Core.h>
#include <llvm/ExecutionEngine/Orc/IRCompileLayer.h>
#include <llvm/ExecutionEngine/Orc/JITTargetMachineBuilder.h>
#include <llvm/ExecutionEngine/Orc/LLJIT.h>
#include <llvm/ExecutionEngine/Orc/ThreadSafeModule.h>
#include <llvm/IR/Constants.h>
#include <llvm/IR/DiagnosticHandler.h>
#include <llvm/IR/DiagnosticInfo.h>
#include <llvm/IR/DiagnosticPrinter.h>
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
#include <llvm/Target/TargetMachine.h>
#include <llvm/TargetParser/Host.h>
#include <llvm/Transforms/Coroutines/CoroCleanup.h>
#include <llvm/Transforms/Coroutines/CoroConditionalWrapper.h>
#include <llvm/Transforms/Coroutines/CoroEarly.h>
#include <llvm/Transforms/Coroutines/CoroSplit.h>
#include <llvm/Transforms/IPO/GlobalDCE.h>
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
#include <filesystem>
#include <mutex>
#include <unistd.h>

namespace lcjit::jit {

namespace orc = llvm::orc;

// The driver derives the resource dir and the GCC installation from argv[0]; Debian's clang 19
// lives here (packages clang-19 / libclang-common-19-dev), and the host toolchain must match.
static constexpr const char* kClangPath = LCJIT_CLANG_EXECUTABLE;
static constexpr const char* kResourceDir = LCJIT_CLANG_RESOURCE_DIR;
// Name given to the driver for the (placeholder) input; the real buffer replaces it per compile.
static constexpr const char* kPlaceholderInput = "lcjit-input.cpp";
// Module flag telling the compile function which codegen level to use for this module.
static constexpr const char* kCodegenLevelFlag = "lcjit.codegen-level";

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

llvm::Error makeError(const llvm::Twine& msg) {
  return llvm::make_error<llvm::StringError>(msg, llvm::inconvertibleErrorCode());
}

// Collects errors (and the notes attached to them) as `FILE:LINE:COL: error: MESSAGE` lines.
// PresumedLoc honours `#line`, so errors point at the user's .l file.
class DiagCollector : public clang::DiagnosticConsumer {
public:
  void HandleDiagnostic(clang::DiagnosticsEngine::Level level, const clang::Diagnostic& info) override {
    clang::DiagnosticConsumer::HandleDiagnostic(level, info);
    const char* kind = nullptr;
    switch (level) {
    case clang::DiagnosticsEngine::Error:
    case clang::DiagnosticsEngine::Fatal:
      kind = "error";
      lastWasError_ = true;
      break;
    case clang::DiagnosticsEngine::Note:
      if (!lastWasError_)
        return;
      kind = "note";
      break;
    default:
      lastWasError_ = false;
      return;
    }
    unsigned id = info.getID();
    if ((id >= clang::diag::DIAG_START_SERIALIZATION && id < clang::diag::DIAG_START_LEX) ||
        id == clang::diag::err_fe_unable_to_load_pch)
      pchProblem = true;

    llvm::raw_string_ostream os(text);
    if (info.getLocation().isValid() && info.hasSourceManager()) {
      const clang::SourceManager& sm = info.getSourceManager();
      clang::PresumedLoc pl = sm.getPresumedLoc(sm.getFileLoc(info.getLocation()));
      if (pl.isValid())
        os << pl.getFilename() << ':' << pl.getLine() << ':' << pl.getColumn() << ": ";
    }
    llvm::SmallString<256> msg;
    info.FormatDiagnostic(msg);
    os << kind << ": " << msg << '\n';
  }

  std::string text;
  bool pchProblem = false;

private:
  bool lastWasError_ = false;
};

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
    return makeError(llvm::Twine("a ") + who + " threw an exception");
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

// The codegen level travels with each module so one LLJIT serves all opt levels.
class LevelledIRCompiler : public orc::IRCompileLayer::IRCompiler {
public:
  explicit LevelledIRCompiler(orc::JITTargetMachineBuilder jtmb)
      : IRCompiler(orc::irManglingOptionsFromTargetOptions(jtmb.getOptions())), jtmb_(std::move(jtmb)) {}

  llvm::Expected<std::unique_ptr<llvm::MemoryBuffer>> operator()(llvm::Module& m) override {
    unsigned idx = 0; // None: fast instruction selection, fast register allocation
    if (auto* c = llvm::mdconst::extract_or_null<llvm::ConstantInt>(m.getModuleFlag(kCodegenLevelFlag)))
      idx = c->getZExtValue() != 0 ? 1 : 0;
    std::lock_guard<std::mutex> lock(mutex_);
    auto& tm = tms_[idx];
    if (!tm) {
      orc::JITTargetMachineBuilder b = jtmb_;
      b.setCodeGenOptLevel(idx ? llvm::CodeGenOptLevel::Default : llvm::CodeGenOptLevel::None);
      auto t = b.createTargetMachine();
      if (!t)
        return t.takeError();
      tm = std::move(*t);
    }
    orc::SimpleCompiler compile(*tm);
    return compile(m);
  }

private:
  orc::JITTargetMachineBuilder jtmb_;
  std::mutex mutex_;
  std::array<std::unique_ptr<llvm::TargetMachine>, 2> tms_;
};

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
    // Inlined linkonce_odr helpers (most of the runtime header) would otherwise be codegen'd.
    mpm.addPass(llvm::GlobalDCEPass());
  }
  mpm.run(m, mam);
}

// Hash of everything a PCH depends on: the runtime header's directory tree (content), the
// compiler version, the full cc1 command line (opt level, -D, target CPU + features).
void hashHeaderTree(llvm::SHA256& h, const std::string& dir) {
  namespace fs = std::filesystem;
  std::vector<fs::path> files;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(dir, fs::directory_options::skip_permission_denied, ec), end;
       !ec && it != end; it.increment(ec)) {
    std::error_code ec2;
    if (it->is_regular_file(ec2))
      files.push_back(it->path());
  }
  std::sort(files.begin(), files.end());
  // A runtime header in a huge directory should not make every start slow; past this many
  // bytes, size + mtime stand in for content (clang's own PCH validation checks those too).
  uint64_t budget = 64ull << 20;
  for (const auto& f : files) {
    std::string p = f.string();
    h.update(p);
    h.update(llvm::StringRef("\0", 1));
    std::error_code ec2;
    auto size = fs::file_size(f, ec2);
    if (!ec2 && size <= budget) {
      if (auto buf = llvm::MemoryBuffer::getFile(p, /*IsText=*/false, /*RequiresNullTerminator=*/false)) {
        h.update((*buf)->getBuffer());
        budget -= size;
        continue;
      }
    }
    auto t = fs::last_write_time(f, ec2);
    std::string meta = std::to_string(ec2 ? 0 : size) + ":" +
                       std::to_string(ec2 ? 0 : t.time_since_epoch().count());
    h.update(meta);
  }
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

namespace detail {
// Everything ModelCode needs after the Compiler is gone: the LLJIT is destroyed only after the
// last ModelCode released its JITDylib (the reverse order is a use-after-free).
struct JitState {
  std::unique_ptr<orc::LLJIT> jit;
  orc::JITDylib* hostJD = nullptr;
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

  ~JitState() {
    failedDylibs.clear();
    jit.reset(); // before the mutexes the error reporter uses
  }

  std::string takeSessionErrors() {
    std::lock_guard<std::mutex> lock(errorMutex);
    return std::exchange(sessionErrors, {});
  }
};
} // namespace detail

// Per opt level: the driver-derived invocation (built once) and the PCH state.
struct LevelSetup {
  std::mutex mutex;
  std::shared_ptr<clang::CompilerInvocation> base;
  std::vector<std::string> cc1Args;
  std::string pchPath;
  bool pchReady = false;    // pchPath holds a PCH this process built or already used successfully
  bool pchFallback = false; // PCH unusable (unwritable cache...): include the header as text
};

struct Compiler::Impl {
  CompilerConfig config;
  std::string headerDir;
  std::string cacheDir;
  orc::JITTargetMachineBuilder jtmb{llvm::Triple()};
  std::shared_ptr<detail::JitState> state;
  std::array<LevelSetup, 3> levels;

  llvm::Error setupLevel(LevelSetup& L, int level);
  std::string pchKey(const LevelSetup& L, int level);
  // Makes sure L has a usable PCH (or falls back); reports whether one from disk was reused.
  void ensurePch(LevelSetup& L, int level, bool forceRebuild, CompileStats& st);
  bool buildPch(LevelSetup& L, const std::string& finalPath, std::string& diagnostics);

  struct FrontendResult {
    std::unique_ptr<llvm::Module> module;
    std::string diagnostics;
    bool pchProblem = false;
  };
  FrontendResult runFrontend(const LevelSetup& L, llvm::StringRef source, const std::string& bufferName,
                             llvm::LLVMContext& ctx);
};

llvm::Error Compiler::Impl::setupLevel(LevelSetup& L, int level) {
  if (L.base)
    return llvm::Error::success();
  std::vector<std::string> args = {kClangPath,
                                   "-std=c++20",
                                   "-w",
                                   "-O" + std::to_string(level),
                                   "-march=native",
                                   "-fpch-instantiate-templates",
                                   "-resource-dir",
                                   kResourceDir,
                                   "-I",
                                   headerDir};
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
    return makeError("lcjit: cannot set up the clang invocation:\n" + trimTrailingNewlines(dc.text));
  inv->getFrontendOpts().DisableFree = false; // createInvocation leaves it on: ~6 MB leak per compile
  inv->getLangOpts().PCHInstantiateTemplates = true;
  // IR passes run in runIRPipeline so that their time is measured and level 1 can differ.
  inv->getCodeGenOpts().DisableLLVMPasses = true;
  // Otherwise ExecuteAction prints "N errors generated." to stderr.
  inv->getDiagnosticOpts().ShowCarets = false;
  L.base = std::shared_ptr<clang::CompilerInvocation>(std::move(inv));
  return llvm::Error::success();
}

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
  hashHeaderTree(h, headerDir);
  auto digest = h.final();
  std::string hex = llvm::toHex(digest, /*LowerCase=*/true).substr(0, 24);
  std::string stem = llvm::sys::path::stem(config.runtimeHeader).str();
  return stem + "-O" + std::to_string(level) + "-" + hex + ".pch";
}

bool Compiler::Impl::buildPch(LevelSetup& L, const std::string& finalPath, std::string& diagnostics) {
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

  clang::CompilerInstance ci;
  ci.setInvocation(inv);
  DiagCollector dc;
  ci.createDiagnostics(&dc, false);
  clang::GeneratePCHAction action;
  bool ok = ci.ExecuteAction(action) && dc.getNumErrors() == 0;
  if (ok) {
    ec = llvm::sys::fs::rename(tmp, finalPath);
    if (ec) {
      dc.text += "cannot move the PCH into place: " + ec.message() + "\n";
      ok = false;
    }
  }
  if (!ok)
    llvm::sys::fs::remove(tmp);
  diagnostics = dc.text;
  return ok;
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
  std::string diags;
  if (buildPch(L, path, diags)) {
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

Compiler::Impl::FrontendResult Compiler::Impl::runFrontend(const LevelSetup& L, llvm::StringRef source,
                                                           const std::string& bufferName,
                                                           llvm::LLVMContext& ctx) {
  FrontendResult r;
  auto inv = std::make_shared<clang::CompilerInvocation>(*L.base);
  auto& fo = inv->getFrontendOpts();
  fo.Inputs.clear();
  fo.Inputs.emplace_back(bufferName, clang::InputKind(clang::Language::CXX));
  fo.OutputFile.clear();
  fo.DisableFree = false;
  auto& ppo = inv->getPreprocessorOpts();
  // SourceManager takes ownership (RetainRemappedFileBuffers is false).
  ppo.addRemappedFile(bufferName, llvm::MemoryBuffer::getMemBufferCopy(source, bufferName).release());
  if (L.pchFallback)
    ppo.Includes.push_back(config.runtimeHeader);
  else
    ppo.ImplicitPCHInclude = L.pchPath;
  inv->getCodeGenOpts().MainFileName = bufferName;

  clang::CompilerInstance ci;
  ci.setInvocation(inv);
  DiagCollector dc;
  ci.createDiagnostics(&dc, false);
  clang::EmitLLVMOnlyAction action(&ctx);
  bool ok = ci.ExecuteAction(action);
  r.pchProblem = dc.pchProblem;
  if (!ok || dc.getNumErrors() != 0) {
    r.diagnostics = dc.text.empty() ? std::string("error: compilation failed\n") : dc.text;
    return r;
  }
  r.module = action.takeModule();
  if (!r.module)
    r.diagnostics = "error: compilation produced no module\n";
  return r;
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
    return makeError("lcjit: runtimeHeader must be an absolute path, got '" + config.runtimeHeader + "'");
  if (!llvm::sys::fs::is_regular_file(config.runtimeHeader))
    return makeError("lcjit: runtime header '" + config.runtimeHeader + "' not found");

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
  impl->jtmb = *jtmb;

  auto state = std::make_shared<detail::JitState>();
  auto jit = orc::LLJITBuilder()
                 .setJITTargetMachineBuilder(*jtmb)
                 .setCompileFunctionCreator([](orc::JITTargetMachineBuilder b)
                                                -> llvm::Expected<std::unique_ptr<orc::IRCompileLayer::IRCompiler>> {
                   return std::make_unique<LevelledIRCompiler>(std::move(b));
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

llvm::Expected<std::unique_ptr<ModelCode>> Compiler::compile(llvm::StringRef cppSource,
                                                             const CompileOptions& options,
                                                             CompileStats* statsOut) {
  // Lets clang move deep recursion onto a bigger stack instead of overflowing ours.
  clang::noteBottomOfStack();
  CompileStats st;
  int level = options.optLevel;
  if (level < 0 || level > 2)
    return makeError("lcjit: optLevel must be 0, 1 or 2, got " + llvm::Twine(level));
  std::string bufferName = options.bufferName.empty() ? std::string("model.cpp") : options.bufferName;
  LevelSetup& L = impl_->levels[level];

  // Front end. The level lock only covers setup/PCH decisions; clang runs unlocked so that
  // compiles on several threads may overlap.
  auto ctx = std::make_unique<llvm::LLVMContext>();
  std::unique_ptr<llvm::Module> module;
  for (int attempt = 0;; ++attempt) {
    {
      std::lock_guard<std::mutex> lock(L.mutex);
      if (auto err = impl_->setupLevel(L, level))
        return std::move(err);
      impl_->ensurePch(L, level, attempt > 0, st);
    }
    auto t0 = Clock::now();
    // Snapshot the PCH decision; another thread may rebuild concurrently.
    LevelSetup snapshot;
    {
      std::lock_guard<std::mutex> lock(L.mutex);
      snapshot.base = L.base;
      snapshot.pchPath = L.pchPath;
      snapshot.pchFallback = L.pchFallback;
    }
    Impl::FrontendResult fr = impl_->runFrontend(snapshot, cppSource, bufferName, *ctx);
    st.frontendMs += msSince(t0);
    if (fr.module) {
      module = std::move(fr.module);
      break;
    }
    if (fr.pchProblem && attempt == 0 && !snapshot.pchFallback) {
      // Stale (header edited, mtime changed) or corrupt PCH: rebuild it and try once more.
      ctx = std::make_unique<llvm::LLVMContext>();
      continue;
    }
    if (statsOut)
      *statsOut = st;
    return makeError(trimTrailingNewlines(fr.diagnostics));
  }

  // IR optimization.
  auto t1 = Clock::now();
  {
    orc::JITTargetMachineBuilder b = impl_->jtmb;
    b.setCodeGenOptLevel(level >= 2 ? llvm::CodeGenOptLevel::Default : llvm::CodeGenOptLevel::None);
    auto tm = b.createTargetMachine();
    if (!tm)
      return tm.takeError();
    runIRPipeline(*module, level, tm->get());
  }
  module->addModuleFlag(llvm::Module::Warning, kCodegenLevelFlag, level >= 2 ? 1u : 0u);
  st.optimizeMs = msSince(t1);

  // Any external definition will do: materializing one materializes the whole module, so
  // codegen and link errors surface here instead of at the first call.
  std::string anchor;
  for (const llvm::GlobalValue& gv : module->global_values())
    if (!gv.isDeclaration() && !gv.hasLocalLinkage() && !gv.getName().starts_with("llvm.")) {
      anchor = gv.getName().str();
      break;
    }
  auto backendErrors = std::make_shared<std::string>();
  ctx->setDiagnosticHandler(std::make_unique<BackendDiagHandler>(backendErrors));

  // Load into a fresh JITDylib.
  auto t2 = Clock::now();
  auto& state = *impl_->state;
  std::lock_guard<std::mutex> lock(state.mutex);
  auto& J = *state.jit;
  auto& ES = J.getExecutionSession();
  std::string name = "lcjit.model." + std::to_string(++state.counter);
  auto jdOrErr = J.createJITDylib(name);
  if (!jdOrErr)
    return jdOrErr.takeError();
  orc::JITDylib& JD = *jdOrErr;
  orc::JITDylibSearchOrder order;
  // Host symbols first so explicit definitions win over same-named process symbols.
  order.push_back({state.hostJD, orc::JITDylibLookupFlags::MatchExportedSymbolsOnly});
  if (auto p = J.getPlatformJITDylib())
    order.push_back({p.get(), orc::JITDylibLookupFlags::MatchExportedSymbolsOnly});
  if (auto p = J.getProcessSymbolsJITDylib())
    order.push_back({p.get(), orc::JITDylibLookupFlags::MatchExportedSymbolsOnly});
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
    if (!backendErrors->empty())
      msg = trimTrailingNewlines(*backendErrors);
    else if (!cause.empty())
      msg = "error: " + what.str() + ": " + cause;
    else
      msg = "error: " + what.str() + ": " + msg;
    if (initAttempted) {
      // Destroy what the initializers managed to construct (registered atexit handlers).
      llvm::consumeError(runModelCode([&] { return callCatching([&] { return J.deinitialize(JD); }, "static destructor"); }));
    }
    state.failedDylibs.push_back(&JD);
    if (auto e = ES.removeJITDylib(JD))
      llvm::consumeError(std::move(e));
    state.takeSessionErrors();
    if (statsOut)
      *statsOut = st;
    return makeError(demangleMentions(msg));
  };

  state.takeSessionErrors();
  if (auto err = J.addIRModule(JD, orc::ThreadSafeModule(std::move(module), std::move(ctx))))
    return fail(std::move(err), "cannot add module");
  if (!anchor.empty()) {
    auto sym = ES.lookup(orc::makeJITDylibSearchOrder(&JD, orc::JITDylibLookupFlags::MatchAllSymbols),
                         J.mangleAndIntern(anchor));
    if (!sym)
      return fail(sym.takeError(), "JIT link failed");
  }
  if (!backendErrors->empty())
    return fail(makeError("code generation failed"), "code generation failed");
  st.codegenMs = msSince(t2);
  // Static constructors of the model. One that throws must not escape with the JITDylib half
  // set up (no ORC locks are held while initializers run, so catching here is safe).
  initAttempted = true;
  if (llvm::Error initErr = runModelCode([&] { return callCatching([&] { return J.initialize(JD); }, "static initializer"); }))
    return fail(std::move(initErr), "running static initializers failed");
  if (!backendErrors->empty())
    return fail(makeError("code generation failed"), "code generation failed");
  st.codegenMs = msSince(t2);
  if (statsOut)
    *statsOut = st;
  return std::unique_ptr<ModelCode>(new ModelCode(impl_->state, &JD, std::move(name), options.runModelCode));
}

ModelCode::ModelCode(std::shared_ptr<detail::JitState> state, void* jitDylib, std::string name,
                     std::function<llvm::Error(const std::function<llvm::Error()>&)> runModelCode)
    : state_(std::move(state)), jd_(jitDylib), name_(std::move(name)), runModelCode_(std::move(runModelCode)) {}

ModelCode::~ModelCode() {
  if (!state_)
    return;
  auto& JD = *static_cast<orc::JITDylib*>(jd_);
  std::lock_guard<std::mutex> lock(state_->mutex);
  auto& J = *state_->jit;
  // Static destructors / atexit handlers of this version only, then free its memory.
  auto deinitialize = [&]() -> llvm::Error { return callCatching([&] { return J.deinitialize(JD); }, "static destructor"); };
  if (llvm::Error err = runModelCode_ ? runModelCode_(deinitialize) : deinitialize())
    llvm::logAllUnhandledErrors(std::move(err), llvm::errs(), "lcjit: deinitializing " + name_ + ": ");
  if (auto err = J.getExecutionSession().removeJITDylib(JD))
    llvm::logAllUnhandledErrors(std::move(err), llvm::errs(), "lcjit: removing " + name_ + ": ");
  state_->takeSessionErrors();
}

llvm::Expected<void*> ModelCode::lookup(llvm::StringRef cName) {
  auto& JD = *static_cast<orc::JITDylib*>(jd_);
  auto addr = state_->jit->lookup(JD, cName);
  if (!addr) {
    state_->takeSessionErrors();
    return addr.takeError();
  }
  return addr->toPtr<void*>();
}

} // namespace lcjit::jit
