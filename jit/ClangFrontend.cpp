// The Clang front end of ClangFrontend.h: each level's invocation from the driver's command line,
// the two-halved front-end run, and the quick tiers' next front end begun ahead.
#include "jit/ClangFrontend.h"
#include "support/CacheFiles.h"
#include "jit/CompilerImpl.h"
#include "support/InputFile.h"

#include <clang/Basic/DiagnosticOptions.h>
#include <clang/Basic/LangStandard.h>
#include <clang/Basic/Stack.h>
#include <clang/CodeGen/ModuleBuilder.h>
#include <clang/Frontend/Utils.h>
#include <clang/Lex/PreprocessorOptions.h>
#include <llvm/ADT/StringExtras.h>
#include <llvm/IR/DiagnosticHandler.h>
#include <llvm/IR/DiagnosticInfo.h>
#include <llvm/IR/DiagnosticPrinter.h>
#include <llvm/Support/FileSystem.h>
#include <llvm/Support/MemoryBuffer.h>
#include <llvm/Support/Path.h>
#include <llvm/Support/SHA256.h>
#include <llvm/Support/raw_ostream.h>

#include <algorithm>
#include <chrono>
#include <cstring>

namespace lcjit::jit {

namespace {

// The driver derives the resource dir and the GCC installation from argv[0]; Debian's clang 19
// lives here (packages clang-19 / libclang-common-19-dev), and the host toolchain must match.
constexpr const char* kClangPath = LCJIT_CLANG_EXECUTABLE;
constexpr const char* kResourceDir = LCJIT_CLANG_RESOURCE_DIR;
// Name given to the driver for the (placeholder) input; the real buffer replaces it per compile.
constexpr const char* kPlaceholderInput = "lcjit-input.cpp";

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

// Where each global variable of the module that `action` generated was declared, while its AST is
// there: "FILE:LINE:COL" of the declared name, the file and line as #line gives them.
std::map<std::string, std::string> declarationsOf(clang::CodeGenAction& action, const clang::SourceManager& sm) {
  std::map<std::string, std::string> places;
  clang::CodeGenerator* gen = action.getCodeGenerator();
  llvm::Module* module = gen ? gen->GetModule() : nullptr;
  if (!module)
    return places;
  for (const llvm::GlobalVariable& gv : module->globals()) {
    if (gv.isDeclaration() || !gv.hasName())
      continue;
    const clang::Decl* decl = gen->GetDeclForMangledName(gv.getName());
    if (!decl)
      continue;
    clang::PresumedLoc at = sm.getPresumedLoc(sm.getExpansionLoc(decl->getLocation()));
    if (at.isValid())
      places[gv.getName().str()] =
          std::string(at.getFilename()) + ":" + std::to_string(at.getLine()) + ":" + std::to_string(at.getColumn());
  }
  return places;
}

}  // namespace

bool executeClang(std::shared_ptr<clang::CompilerInvocation> inv, clang::FrontendAction& action,
                  frontend::DiagCollector& dc) {
  clang::CompilerInstance ci;
  ci.setInvocation(std::move(inv));
  ci.createDiagnostics(&dc, false);
  return ci.ExecuteAction(action) && dc.getNumErrors() == 0;
}

Frontend::Frontend(std::shared_ptr<clang::CompilerInvocation> base, std::string pchPath, bool pchFallback,
                   const std::string& runtimeHeader, std::string bufferName, size_t capacity)
    : pchPath(std::move(pchPath)), pchFallback(pchFallback), bufferName(std::move(bufferName)), capacity(capacity),
      base(std::move(base)), runtimeHeader(runtimeHeader) {}

Frontend::~Frontend() {
  if (begun)
    action->EndSourceFile();
}

bool Frontend::begin() {
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
  // The AST stays until EndSourceFile, for finish() to note where the module's variables are
  // declared (declarationsOf): clang would free it before its back end, which here only hands
  // the module over (the IR passes run later), so keeping it costs nothing.
  inv->getCodeGenOpts().ClearASTBeforeBackend = false;
  if (!lineTables)  // the level's line has -gline-tables-only, which a PCH made for it shares
    inv->getCodeGenOpts().setDebugInfo(llvm::codegenoptions::NoDebugInfo);
  else if (fullDebugInfo)  // code generation's choice: the PCH serves as it is
    inv->getCodeGenOpts().setDebugInfo(llvm::codegenoptions::FullDebugInfo);
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

Frontend::Result Frontend::finish(llvm::StringRef source) {
  Result r;
  r.backendErrors = backendErrors;
  if (begun && dc.getNumErrors() == 0) {
    std::memcpy(text.get(), source.data(), std::min(source.size(), capacity));
    if (llvm::Error err = action->Execute())
      dc.text += "error: " + llvm::toString(std::move(err)) + "\n";
    else
      r.declaredAt = declarationsOf(*action, ci->getSourceManager());
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

// A level's cc1 line kept in the cache folder (keptCc1Path): the folders the driver chose from
// stamped (stampLines), then this marker, then the arguments, each ending in a NUL.
constexpr llvm::StringLiteral kCc1Follows = "// lcjit-cc1 1\n";

// Where the cc1 line of the driver arguments `args` is kept. The name hashes everything else the
// driver reads: lcjit's build (the driver is in it), the host CPU (-march=native), the working
// folder and the variables that add include folders.
std::string Compiler::Impl::keptCc1Path(const std::vector<std::string>& args) const {
  llvm::SHA256 h;
  static constexpr const char* kBuild = __DATE__ " " __TIME__;
  const std::string features = jtmb.getFeatures().getString();
  for (llvm::StringRef part : {llvm::StringRef(kBuild), llvm::StringRef(jtmb.getCPU()), llvm::StringRef(features)}) {
    h.update(part);
    h.update(llvm::StringRef("\0", 1));
  }
  llvm::SmallString<256> cwd;
  llvm::sys::fs::current_path(cwd);
  h.update(cwd);
  for (const auto& a : args) {
    h.update(llvm::StringRef("\0", 1));
    h.update(a);
  }
  for (const char* var : {"CPATH", "C_INCLUDE_PATH", "CPLUS_INCLUDE_PATH", "CCC_OVERRIDE_OPTIONS", "COMPILER_PATH"}) {
    const char* value = std::getenv(var);
    h.update(llvm::StringRef("\0", 1));
    h.update(value ? value : "");
  }
  return cacheDir + "/levels/" + llvm::toHex(h.final(), /*LowerCase=*/true).substr(0, 32);
}

llvm::Error Compiler::Impl::setupLevel(LevelSetup& L, int level) {
  if (!L.cc1Args.empty())
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
                                   // Line tables (no types or variables): a fault names the
                                   // statement it happened in (CodeMap.h). They change no code.
                                   "-gline-tables-only",
                                   // Relative names in them (a model given as `m.l`) stay
                                   // relative, to the folder of the run that reads them: the
                                   // object cache serves an object to runs in other folders.
                                   "-fdebug-compilation-dir=.",
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

  // The driver's cc1 line from an earlier run: the driver was a tenth of a run whose model came
  // from the object cache, which needs the line for the cache's keys and no invocation at all.
  const std::string kept = keptCc1Path(args);
  if (auto file = support::readInputFile(kept, /*nullTerminated=*/false)) {
    llvm::StringRef rest;
    if (support::stampsHold((*file)->getBuffer(), kCc1Follows, &rest) && rest.starts_with("-cc1") &&
        rest.ends_with(llvm::StringRef("\0", 1))) {
      llvm::SmallVector<llvm::StringRef, 64> parts;
      rest.drop_back().split(parts, '\0', /*MaxSplit=*/-1, /*KeepEmpty=*/true);
      for (llvm::StringRef arg : parts)
        L.cc1Args.push_back(arg.str());
      noteLibraryDirs(L);
      return llvm::Error::success();
    }
  }

  std::vector<const char*> argv;
  for (const auto& a : args)
    argv.push_back(a.c_str());
  frontend::DiagCollector dc;
  clang::CreateInvocationOptions opts;
  opts.Diags = clang::CompilerInstance::createDiagnostics(new clang::DiagnosticOptions, &dc, false);
  opts.CC1Args = &L.cc1Args;
  std::unique_ptr<clang::CompilerInvocation> inv = clang::createInvocation(argv, std::move(opts));
  if (!inv) {
    L.cc1Args.clear();
    return llvm::createStringError("lcjit: cannot set up the clang invocation:\n" + trimTrailingNewlines(dc.text));
  }
  adjustInvocation(*inv);
  L.base = std::shared_ptr<clang::CompilerInvocation>(std::move(inv));
  noteLibraryDirs(L);

  // The folders the driver searched: the include folders it chose and their parents up to the
  // GCC installation's (installing or removing a GCC changes one of them).
  std::vector<std::string> searched;
  for (size_t i = 0; i + 1 < L.cc1Args.size(); ++i) {
    llvm::StringRef opt = L.cc1Args[i];
    if (opt != "-internal-isystem" && opt != "-internal-externc-isystem")
      continue;
    llvm::SmallString<256> dir(L.cc1Args[i + 1]);
    llvm::sys::path::remove_dots(dir, /*remove_dot_dot=*/true);
    for (int up = 0; up < 3 && !dir.empty() && dir != "/"; ++up, llvm::sys::path::remove_filename(dir))
      if (llvm::sys::fs::is_directory(dir) &&
          std::find(searched.begin(), searched.end(), dir.str()) == searched.end())
        searched.push_back(dir.str().str());
  }
  if (auto stamps = support::stampLines(searched)) {
    std::string text = *stamps + kCc1Follows.str();
    for (const auto& a : L.cc1Args)
      text += a + '\0';
    std::error_code ec = llvm::sys::fs::create_directories(cacheDir + "/levels");
    if (!ec)
      support::writeCacheFile(kept, text);
  }
  return llvm::Error::success();
}

// The folders whose headers are not the model's (CodeMap::addLibraryDirs): lcjit's runtime
// header's and those the driver added for the system's and the compiler's own headers.
void Compiler::Impl::noteLibraryDirs(const LevelSetup& L) {
  std::vector<std::string> dirs{headerDir};
  for (size_t i = 0; i + 1 < L.cc1Args.size(); ++i) {
    llvm::StringRef opt = L.cc1Args[i];
    if (opt == "-internal-isystem" || opt == "-internal-externc-isystem" || opt == "-isystem" || opt == "-resource-dir")
      dirs.push_back(L.cc1Args[i + 1]);
  }
  state->codeMap->addLibraryDirs(dirs);
}

void Compiler::Impl::adjustInvocation(clang::CompilerInvocation& inv) {
  inv.getFrontendOpts().DisableFree = false; // createInvocation leaves it on: ~6 MB leak per compile
  inv.getCodeGenOpts().DisableFree = false;  // and this one: clang's back end buried a TargetMachine (~28 KB) per compile
  inv.getLangOpts().PCHInstantiateTemplates = true;
  // IR passes run in runIRPipeline so that their time is measured and level 1 can differ.
  inv.getCodeGenOpts().DisableLLVMPasses = true;
  // Otherwise ExecuteAction prints "N errors generated." to stderr.
  inv.getDiagnosticOpts().ShowCarets = false;
}

llvm::Error Compiler::Impl::ensureBase(LevelSetup& L, int level) {
  if (auto err = setupLevel(L, level))
    return err;
  if (L.base)
    return llvm::Error::success();
  // From the kept cc1 line, as createInvocation makes it from the driver's.
  std::vector<const char*> argv;
  for (const auto& a : L.cc1Args)
    argv.push_back(a.c_str());
  frontend::DiagCollector dc;
  auto diags = clang::CompilerInstance::createDiagnostics(new clang::DiagnosticOptions, &dc, false);
  auto inv = std::make_shared<clang::CompilerInvocation>();
  if (!clang::CompilerInvocation::CreateFromArgs(*inv, argv, *diags, kClangPath))
    return llvm::createStringError("lcjit: cannot set up the clang invocation:\n" + trimTrailingNewlines(dc.text));
  adjustInvocation(*inv);
  L.base = std::move(inv);
  return llvm::Error::success();
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

}  // namespace lcjit::jit
