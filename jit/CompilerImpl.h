// Compiler's private state (Compiler::Impl), for the files of jit/ that define its parts: each
// member says which. compile() and its stages are in Compiler.cpp; the design is in docs/jit.md.
#pragma once

#include "support/CacheFiles.h"
#include "jit/ClangFrontend.h"
#include "jit/Compiler.h"
#include "support/Elapsed.h"
#include "jit/ObjectCache.h"
#include "jit/OrcState.h"
#include "jit/StaticData.h"

#include <llvm/ExecutionEngine/Orc/JITTargetMachineBuilder.h>
#include <llvm/IR/Module.h>
#include <llvm/Support/Error.h>

#include <array>
#include <atomic>
#include <cstddef>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace lcjit::jit {

// Level 0 builds its PCH with clang's -fpch-codegen: the runtime header's inline functions and
// the templates the PCH instantiated are compiled once, into a support object loaded into its
// own JITDylib, and every model compiled against that PCH links to it instead of emitting its
// own copies. At -O0 nothing is inlined, so those copies were most of a small model's object
// (sunflower: 51 functions, 24 its own) and of its instruction selection time. Higher levels
// keep their own copies, which they inline.
inline bool pchCodegen(int level) { return level == 0; }

// A note for the user about a cache file that was deleted and made again.
inline std::string cacheNote(const std::string& file, const std::string& problem) {
  return "note: the cached compiled code " + file + " was not used: " + problem +
         "; it was deleted and the model compiled again (lcjit's cache folder may be deleted at any time)";
}

// Diagnostics end in a newline; an Error's message should not.
inline std::string trimTrailingNewlines(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r'))
    s.pop_back();
  return s;
}

struct Compiler::Impl {
  CompilerConfig config;
  std::string headerDir;
  std::string cacheDir;
  std::string cacheWarning;   // why the configured cache folder is not used
  bool privateCache = false;  // cacheDir is this process's own, removed with the Compiler
  orc::JITTargetMachineBuilder jtmb{llvm::Triple()};
  std::shared_ptr<detail::JitState> state;
  std::array<LevelSetup, 3> levels;

  // compile()'s stages, in order (Compiler.cpp). A Job is one compile: its inputs and what each
  // stage hands to the next.
  struct Job;
  llvm::Error setUp(Job& job);
  std::shared_ptr<const CachedObject> reusedObject(Job& job);
  llvm::Expected<Frontend::Result> parse(Job& job);
  llvm::Error optimize(Job& job, llvm::Module& module, CachedObject& fresh);
  llvm::Error generateCode(Job& job, Frontend::Result& ir, CachedObject& fresh);
  void cacheObject(Job& job);
  llvm::Expected<orc::JITDylib*> supportCode(Job& job);
  llvm::Expected<orc::JITDylib*> newDylib(const Job& job, orc::JITDylib* support);
  llvm::Expected<std::shared_ptr<detail::Dylib>> load(Job& job, orc::JITDylib& JD, const ObjectData& data,
                                                      support::Clock::time_point loadStart);

  // Instruction selection at `level`, with the level's kept TargetMachine (OrcState.cpp).
  llvm::Expected<std::string> emitObject(llvm::Module& m, int level);

  // Objects of recent compiles by key, newest last (a reload of unchanged source, a tier swap
  // back and forth); older ones come from the disk cache (ObjectCache.cpp).
  std::mutex objectsMutex;
  std::vector<std::pair<std::string, std::shared_ptr<const CachedObject>>> objects;
  static constexpr size_t kObjectsInMemory = 16;
  static constexpr size_t kObjectsOnDisk = 256;
  // `problem`: a disk entry that was there and damaged (deleted now), why.
  std::shared_ptr<const CachedObject> findObject(const std::string& key, bool& fromDisk, std::string& problem);
  // Forgets the entry in memory and on disk (it would not load).
  void dropObject(const std::string& key);
  // The object cache's folder: compiled objects by key (objectPath), ORC's own support objects
  // (OrcState.cpp) and the marks the program leaves beside an object.
  std::string objectsDir() const { return cacheDir + "/objects"; }
  std::string objectPath(const std::string& key) const { return objectsDir() + "/" + key + ".o"; }
  void keepObject(const std::string& key, std::shared_ptr<const CachedObject> object);
  // Writes the object to the disk cache (temporary file + rename, as for the PCH) and, every so
  // many stores (listing the folder is not free), keeps the cache to its newest kObjectsOnDisk
  // entries. Failures only cost a later compile.
  void storeObject(const std::string& key, const CachedObject& object);

  // The level's cc1 line (L.cc1Args), made once: kept in the cache folder from an earlier run, or
  // from Clang's driver, which also makes L.base (ClangFrontend.cpp). Enough for the keys.
  llvm::Error setupLevel(LevelSetup& L, int level);
  void noteLibraryDirs(const LevelSetup& L);
  std::string keptCc1Path(const std::vector<std::string>& driverArgs) const;
  // setupLevel, and the level's invocation (L.base) too: what parsing and PCH builds need.
  llvm::Error ensureBase(LevelSetup& L, int level);
  static void adjustInvocation(clang::CompilerInvocation& inv);

  // The PCH of each level (Pch.cpp).
  std::string pchKey(const LevelSetup& L, int level);
  // Makes sure L has a usable PCH (or falls back); reports whether one from disk was reused.
  void ensurePch(LevelSetup& L, int level, bool forceRebuild, CompileStats& st);
  // The level's PCH is made (or on the disk), without building it.
  bool pchExists(int level);
  // Where the PCH of this key is on the disk: the cache folder's, else config.prebuiltDir's, else
  // "" (then it is built into the cache folder).
  std::string existingPch(const std::string& key) const;
  // `writeFailed`: built, but the file could not be written (a full disk).
  bool buildPch(LevelSetup& L, int level, const std::string& finalPath, std::string& diagnostics, bool& writeFailed);
  std::atomic<bool> pchWriteWarned{false};  // the user was told once
  static constexpr size_t kPchsKept = 3;
  static void prunePchs(const std::string& built);

  // The JITDylib holding the support object of the -fpch-codegen PCH at pchPath: loaded from
  // the cache (pchPath + ".o") or compiled from the PCH and stored there first.
  // Building it takes ~0.4 s and loading it ~3 ms, so the first compile against a PCH starts
  // it on another thread (startSupport) and only waits for it (supportDylib) before linking
  // (SupportObjects.cpp).
  struct Support {
    std::shared_future<void> ready;
    orc::JITDylib* jd = nullptr;
    std::string error;
    std::string note;  // a damaged cache file it replaced, for the next compile to report
  };
  std::shared_ptr<Support> startSupport(const LevelSetup& L, const std::string& pchPath);
  // `notes`: gets the support's note, once.
  llvm::Expected<orc::JITDylib*> supportDylib(const LevelSetup& L, const std::string& pchPath,
                                              std::vector<std::string>* notes = nullptr);
  llvm::Expected<orc::JITDylib*> loadSupport(std::shared_ptr<clang::CompilerInvocation> base,
                                             const std::string& pchPath, unsigned number, std::string& note);
  static constexpr size_t kSupportPartSize = 32;
  std::mutex supportMutex;
  std::map<std::string, std::shared_ptr<Support>> supports;
  unsigned supportsStarted = 0;

  // The quick tiers' front end begun ahead (Frontend) if there is one that fits this compile;
  // a mismatched or failed one is dropped (ClangFrontend.cpp).
  std::unique_ptr<Frontend> takeAhead(LevelSetup& L, const LevelSetup& used, const std::string& bufferName,
                                      size_t size);
  // Begins the next front end of a quick tier on another thread, unless one is under way.
  void beginAhead(LevelSetup& L, const LevelSetup& used, const std::string& bufferName, size_t size);
  static constexpr size_t kAheadCapacity = 64 * 1024;

  // Waits for the work under way on other threads; removes a private cache folder.
  void settle() {
    for (auto& [path, support] : supports)
      support->ready.wait();
    for (auto& L : levels)
      if (L.ahead.valid())
        L.ahead.wait();
    if (privateCache)
      support::removeCacheFolder(cacheDir);
    privateCache = false;
  }
  ~Impl() { settle(); }
};

}  // namespace lcjit::jit
