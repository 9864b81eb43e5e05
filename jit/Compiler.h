// In-process C++ -> native code compiler for generated model code: Clang 19 as a library
// (with a cached precompiled runtime header) feeding one long-lived LLVM ORC LLJIT.
// How it works, and the measurements behind it: docs/jit.md.
#pragma once

#include <llvm/ADT/StringRef.h>
#include <llvm/Support/Error.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "frontend/ModelCpp.h"
#include "jit/CodeMap.h"          // SourcePlace

namespace lcjit::jit {

// A C-linkage host function (or variable) the model code may reference by name.
struct HostSymbol {
  std::string name;
  void* address;
};

struct CompilerConfig {
  // Absolute path of the model API header (lpfgall.h). It is precompiled once per opt level
  // and implicitly included in every compile.
  std::string runtimeHeader;
  // Extra -I directories for model compiles (the runtime header's directory is added first).
  std::vector<std::string> includeDirs;
  // PCH cache directory. Empty: $LCJIT_CACHE_DIR, else $XDG_CACHE_HOME/lcjit, else ~/.cache/lcjit,
  // else /tmp/lcjit-cache-UID. Used only when it is the user's alone; else a private folder of
  // this process's (cacheWarning() says why).
  std::string cacheDir;
  // PCHs (and the -O0 PCH's support object) made when lcjit was built or installed, used read
  // only: a PCH the cache folder lacks is taken from here when its key is the same (same header,
  // compiler, options and CPU), so that a new user's first compile builds none (≈0.25 s each).
  // Empty, or a folder others may write to: not used.
  std::string prebuiltDir;
  // Defined explicitly in the JIT so the host binary needs no -rdynamic.
  std::vector<HostSymbol> hostSymbols;
  // The C++ of model code (-std=): frontend::kDefaultLanguageStandard unless a model's lpfg.mak
  // asks for another.
  std::string languageStandard = frontend::kDefaultLanguageStandard;
  // For gdb and lldb (lcjit --debugger, docs/faults.md): model code gets full debug information
  // (-g: variables and types, not only line tables) and every object is registered through the
  // GDB JIT interface, so a debugger stops at `break m.l:7`, shows locals and backtraces in the
  // .l file. Costs bigger objects and slower compiles; no front end is begun ahead. The object
  // cache keeps such objects apart.
  bool debugger = false;
};

class ModelCode;

// The data a compiled model puts in memory when it is loaded: its variables of static storage,
// zero-filled or not, and its constants (everything of its object but the code).
struct StaticData {
  uint64_t bytes = 0;
  // The largest variable: its name as the source spells it ("grid", "Model::cells"), its size,
  // and where it is declared ("FILE:LINE:COL", presumed through #line; "" when not known).
  std::string largest;
  uint64_t largestBytes = 0;
  std::string declaredAt;
};

struct CompileOptions {
  // 0: -O0 IR, fast instruction selection. 1: light IR pipeline (SROA, early-CSE, instcombine,
  // simplifycfg, inliner) + fast instruction selection. 2: standard O2 pipeline + default codegen.
  int optLevel = 1;
  // Name the main file gets in diagnostics unless `#line` directives say otherwise.
  std::string bufferName = "model.cpp";
  // Loaded code whose mutable globals this compile uses instead of defining its own (by name),
  // without running their constructors again: a better-optimised tier of the same source keeps
  // the running simulation's state, and C++ typed at the REPL sees the model's. Globals none of
  // them defines are this compile's own. The other code stays loaded while this one lives.
  std::vector<const ModelCode*> shareStateWith;
  // Loaded code whose functions this compile may call without defining them (an incremental
  // recompile declares the productions it did not change; their code is there), newest first.
  std::vector<const ModelCode*> linkAgainst;
  // DWARF line tables in the object (-gline-tables-only: no types or variables), so that a fault
  // names the statement it happened in (Compiler::sourceAt). They change no code. Cost, measured
  // on the quick tier: a few per cent of a small model's compile (birch.l 7.7 -> 8.1 ms, gcplant.l
  // 9.0 -> 10.0 ms), a third of a huge one's (20,000 productions: 5.9 -> 8.1 s, 438 -> 623 MB).
  // Without them, a fault names the rule's first line.
  bool lineTables = true;
  // Reuse the object code of an identical earlier compile (same source, options, compiler and
  // runtime header), from memory or from the disk cache, instead of compiling again.
  bool useObjectCache = true;
  // Wants only the object code of an identical earlier compile (from memory or the disk cache):
  // nothing is parsed or compiled and no PCH is built; compile() returns null (not an error)
  // when there is none, or when it would not load. Costs hashing the source and a file lookup:
  // how a run takes a better tier an earlier run compiled, for free.
  bool onlyFromCache = false;
  // Calls the model's static constructors (at load, and by resetState()) and destructors (when
  // the ModelCode goes): they are model code, so lcjit runs them behind its fault guard, and one
  // that crashes fails the compile (or is reported) instead of ending the process. Empty:
  // called directly.
  std::function<llvm::Error(const std::function<llvm::Error()>& run)> runModelCode;
  // Asked before the object is linked, before any of its memory is allocated: an error refuses
  // the model with it (a memory limit that its static data alone would pass). Empty: none.
  std::function<llvm::Error(const StaticData& data)> checkStaticData;
  // A C++ translation unit of the model's own (an extra .cpp on the command line), compiled as
  // g++ compiles it for lpfg: without the runtime header (no PCH, nothing included implicitly),
  // so its names cannot clash with lpfgall.h's. Slower to parse than model code; the object
  // cache keeps it. Models reach its functions through linkAgainst.
  bool plainUnit = false;
  // At a quick level (0, 1): once this compile is over, set up the next compile's front end on
  // another thread (the PCH loaded, the builtins registered: a third of a small compile), for
  // the next edit of the same unit (same bufferName) to find ready. For live editing; the
  // Compiler must then be destroyed before the process exits (it waits for that thread).
  bool beginNextAhead = false;
};

struct CompileStats {
  double frontendMs = 0;  // parse + IR generation
  double optimizeMs = 0;  // IR pipeline
  double codegenMs = 0;   // instruction selection into an object file
  double loadMs = 0;      // JIT link of the object and the model's static constructors
  double pchBuildMs = 0;  // building (or validating) the PCH, when this compile had to
  bool pchCached = false; // an existing PCH from the disk cache was reused
  bool frontendBegunAhead = false;  // the front end was set up before the source came (quick tiers)
  // The object code came from the cache (no front end, optimisation or instruction selection).
  enum class ObjectFrom { Compiled, Memory, Disk } object = ObjectFrom::Compiled;
  // For the user: cache files that were damaged or would not load, deleted and compiled again.
  std::vector<std::string> notes;
  // The object cache's key of this compile ("" without the cache): a name for what it made.
  std::string objectKey;
};

namespace detail {
struct JitState;
struct Dylib;
}

// One compiled model version, living in its own JITDylib. Destroying it runs the model's static
// destructors and removes its code from the JIT (unless a version sharing its state still runs);
// it may outlive the Compiler that made it.
class ModelCode {
public:
  ~ModelCode();
  ModelCode(const ModelCode&) = delete;
  ModelCode& operator=(const ModelCode&) = delete;

  // Address of an extern "C" symbol defined by the model.
  llvm::Expected<void*> lookup(llvm::StringRef cName);

  // Unique name of the JITDylib holding this version (for logs).
  const std::string& name() const;

  // Puts the globals this version owns back as they were when it was loaded: runs their
  // destructors, restores their initial bytes, runs their constructors again. Code that shares
  // them (later tiers, incremental recompiles) then starts from a fresh model, as a new load
  // would. The caller makes sure no model code runs meanwhile.
  llvm::Error resetState();

private:
  friend class Compiler;
  explicit ModelCode(std::shared_ptr<detail::Dylib> dylib);
  std::shared_ptr<detail::Dylib> dylib_;
};

// One per process. compile() may run on a background thread while older ModelCode runs.
class Compiler {
public:
  static llvm::Expected<std::unique_ptr<Compiler>> create(CompilerConfig config);
  ~Compiler();
  // The process is ending and keeps model code mapped (app::Session::leaveAtExit): the work under
  // way on other threads is finished, and a private cache folder removed, as ~Compiler would.
  void settleAtExit();
  Compiler(const Compiler&) = delete;
  Compiler& operator=(const Compiler&) = delete;

  // Compile a C++ translation unit (the runtime header is implicitly included via the PCH) and
  // load it. Errors carry the diagnostics, one per line: `FILE:LINE:COL: error: MESSAGE`.
  llvm::Expected<std::unique_ptr<ModelCode>> compile(llvm::StringRef cppSource,
                                                     const CompileOptions& options,
                                                     CompileStats* stats = nullptr);

  // The model source of the code at `address` (CodeMap.h), innermost inlined call first and
  // only the model's own files: not lcjit's runtime header, system headers or the generated
  // tables. Empty when the address is not in loaded model code. `returnAddress`: the address is
  // one a call returns to (a frame of a stack walk). Costs a lookup under a lock, and parsing the
  // object's line table the first time one of its addresses is asked about.
  std::vector<SourcePlace> sourceAt(uintptr_t address, bool returnAddress = false) const;

  // The resolved cache directory.
  const std::string& cacheDir() const;
  // Its folder of object code (the object cache's), where a caller may leave marks beside an
  // object (CompileStats::objectKey names it).
  std::string objectsDir() const;
  // Why the configured (or default) cache folder is not used, when it is not: it is not the
  // user's alone (support::useAsCacheFolder). Empty when it is used.
  const std::string& cacheWarning() const;

  struct Impl;

private:
  explicit Compiler(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

} // namespace lcjit::jit
