// The precompiled runtime header, one per opt level: its key, building it into the disk cache,
// pruning old ones, and making sure a compile has one (or falls back to the header as text).
#include "support/CacheFiles.h"
#include "jit/CompilerImpl.h"

#include <sys/stat.h>
#include "support/Elapsed.h"
#include "support/ReplacingFile.h"

#include <clang/Basic/Version.h>
#include <clang/Frontend/CompilerInstance.h>
#include <clang/Frontend/FrontendActions.h>
#include <clang/Frontend/MultiplexConsumer.h>
#include <clang/Lex/PreprocessorOptions.h>
#include <clang/Serialization/ASTWriter.h>
#include <llvm/ADT/SmallString.h>
#include <llvm/ADT/StringExtras.h>
#include <llvm/Config/llvm-config.h>
#include <llvm/Support/FileSystem.h>
#include <llvm/Support/Path.h>
#include <llvm/Support/SHA256.h>
#include <llvm/Support/raw_ostream.h>
#include <llvm/TargetParser/Host.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <utility>
#include <unistd.h>

namespace lcjit::jit {

namespace {

// GeneratePCHAction with the PCH written to memory instead of the output file: clang's output
// streams end the process (report_fatal_error) when a write fails, and a full disk must only
// cost the cache. The caller writes the bytes with its own checks.
class PchToMemoryAction : public clang::GeneratePCHAction {
public:
  explicit PchToMemoryAction(llvm::SmallVectorImpl<char>& bytes) : bytes_(bytes) {}

protected:
  std::unique_ptr<clang::ASTConsumer> CreateASTConsumer(clang::CompilerInstance& CI, llvm::StringRef inFile) override {
    std::string sysroot;
    if (!ComputeASTConsumerArguments(CI, sysroot))
      return nullptr;
    const clang::FrontendOptions& fo = CI.getFrontendOpts();
    if (!fo.RelocatablePCH)
      sysroot.clear();
    // The name the PCH records as its own: where the bytes will be written.
    const std::string outputFile = fo.OutputFile;
    auto buffer = std::make_shared<clang::PCHBuffer>();
    std::vector<std::unique_ptr<clang::ASTConsumer>> consumers;
    consumers.push_back(std::make_unique<clang::PCHGenerator>(
        CI.getPreprocessor(), CI.getModuleCache(), outputFile, sysroot, buffer, fo.ModuleFileExtensions,
        CI.getPreprocessorOpts().AllowPCHWithCompilerErrors, fo.IncludeTimestamps, fo.BuildingImplicitModule,
        +CI.getLangOpts().CacheGeneratedPCH));
    consumers.push_back(CI.getPCHContainerWriter().CreatePCHContainerGenerator(
        CI, inFile.str(), outputFile, std::make_unique<llvm::raw_svector_ostream>(bytes_), buffer));
    return std::make_unique<clang::MultiplexConsumer>(std::move(consumers));
  }

private:
  llvm::SmallVectorImpl<char>& bytes_;
};

}  // namespace

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
  support::hashDirectoryTree(h, headerDir);
  auto digest = h.final();
  std::string hex = llvm::toHex(digest, /*LowerCase=*/true).substr(0, 24);
  std::string stem = llvm::sys::path::stem(config.runtimeHeader).str();
  return stem + "-O" + std::to_string(level) + "-" + hex + ".pch";
}

bool Compiler::Impl::buildPch(LevelSetup& L, int level, const std::string& finalPath, std::string& diagnostics,
                              bool& writeFailed) {
  std::error_code ec = llvm::sys::fs::create_directories(cacheDir);
  if (ec) {
    diagnostics = "cannot create cache directory '" + cacheDir + "': " + ec.message();
    return false;
  }
  if (llvm::Error err = ensureBase(L, level)) {
    diagnostics = llvm::toString(std::move(err));
    return false;
  }
  auto inv = std::make_shared<clang::CompilerInvocation>(*L.base);
  auto& fo = inv->getFrontendOpts();
  fo.Inputs.clear();
  fo.Inputs.emplace_back(config.runtimeHeader,
                         clang::InputKind(clang::Language::CXX, clang::InputKind::Source, false,
                                          clang::InputKind::HeaderUnit_None, /*HD=*/true));
  fo.OutputFile = finalPath;
  fo.ProgramAction = clang::frontend::GeneratePCH;
  fo.DisableFree = false;
  if (pchCodegen(level))
    inv->getLangOpts().ModulesCodegen = true;

  frontend::DiagCollector dc;
  llvm::SmallVector<char, 0> bytes;
  PchToMemoryAction action(bytes);
  bool ok = executeClang(inv, action, dc) && !bytes.empty();
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
    // Through a temporary file and a rename: readers never see a partial file even when several
    // processes (ctest -j) build the same PCH at once. A failed write (a full disk) leaves nothing.
    if (!support::writeCacheFile(finalPath, llvm::StringRef(bytes.data(), bytes.size()))) {
      dc.text += "cannot write the PCH to '" + finalPath + "' (is the disk full?)\n";
      writeFailed = true;
      ok = false;
    }
  }
  if (ok)
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
    if (other.rfind(prefix, 0) == 0 && it->path().extension() == ".pch" && !support::ReplacingFile::isUnfinished(other))
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

bool Compiler::Impl::pchExists(int level) {
  LevelSetup& L = levels[level];
  std::lock_guard<std::mutex> lock(L.mutex);
  if (llvm::Error err = setupLevel(L, level)) {
    llvm::consumeError(std::move(err));  // the compile that needs the level reports it
    return false;
  }
  return L.pchReady || (!L.pchFallback && !existingPch(pchKey(L, level)).empty());
}

std::string Compiler::Impl::existingPch(const std::string& key) const {
  std::string own = cacheDir + "/" + key;
  if (llvm::sys::fs::exists(own))
    return own;
  // The prebuilt folder's code is loaded and run (the support object) as the binary's own is:
  // not from a folder anyone else can write to.
  struct stat st {};
  if (config.prebuiltDir.empty() || ::stat(config.prebuiltDir.c_str(), &st) != 0 || (st.st_mode & (S_IWGRP | S_IWOTH)))
    return "";
  std::string prebuilt = config.prebuiltDir + "/" + key;
  return llvm::sys::fs::exists(prebuilt) ? prebuilt : "";
}

void Compiler::Impl::ensurePch(LevelSetup& L, int level, bool forceRebuild, CompileStats& st) {
  if (L.pchFallback)
    return;
  if (L.pchReady && !forceRebuild) {
    st.pchCached = true;
    return;
  }
  auto t0 = support::Clock::now();
  // Recomputed here (not cached) so that a runtime header edited while we run gets a new key.
  const std::string key = pchKey(L, level);
  std::string path = cacheDir + "/" + key;
  if (!forceRebuild)
    if (std::string found = existingPch(key); !found.empty())
      path = found;
  L.pchPath = path;
  if (!forceRebuild && llvm::sys::fs::exists(path)) {
    // Validity is checked by the compile that uses it; a stale or corrupt file comes back here
    // with forceRebuild.
    L.pchReady = true;
    st.pchCached = true;
    st.pchBuildMs += support::msSince(t0);
    return;
  }
  if (L.ahead.valid())
    L.ahead.get();  // begun on the PCH being replaced
  std::string diags;
  bool writeFailed = false;
  if (buildPch(L, level, path, diags, writeFailed)) {
    L.pchReady = true;
    st.pchCached = false;
  } else {
    // Still compile, just slower; if the header itself is broken the model compile reports it.
    L.pchFallback = true;
    L.pchReady = false;
    if (writeFailed && !pchWriteWarned.exchange(true))
      st.notes.push_back("warning: the precompiled runtime header cannot be written to the cache folder " + cacheDir +
                         " (is the disk full?): compiling without it, which is slower");
    if (std::getenv("LCJIT_VERBOSE"))
      llvm::errs() << "lcjit: PCH build failed, including the runtime header as text:\n" << diags;
  }
  st.pchBuildMs += support::msSince(t0);
}

}  // namespace lcjit::jit
