// One model, from files to a runnable engine: input files are sorted by extension (manual
// §1.1.2), the .l file is preprocessed, rewritten to C++ and compiled in-process, and the
// derivation engine is set up on the compiled model. Every phase is timed for --stats.
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "app/session/InputKinds.h"
#include "app/session/Languages.h"
#include "app/session/ReloadParts.h"
#include "frontend/lc/Preprocess.h"
#include "frontend/lc/Rewriter.h"
#include "runtime/environment/Builtin.h"
#include "runtime/Engine.h"
#include "runtime/ModelGuard.h"
#include "runtime/WindowInput.h"
#include <llvm/Support/Error.h>

struct __lc_Model;

namespace lcjit::jit {
class Compiler;
class ModelCode;
struct StaticData;
}  // namespace lcjit::jit
namespace lcjit::runtime {
class Engine;
class FunctionStore;
struct DrawingFiles;
}  // namespace lcjit::runtime

namespace lcjit::app {

struct PhaseTimes {
  double preprocessMs = 0, rewriteMs = 0, compileMs = 0, deriveMs = 0, interpretMs = 0, renderMs = 0;
  double frontendMs = 0, optimizeMs = 0, codegenMs = 0, loadMs = 0;  // the parts of compileMs
  bool pchCached = false;
  bool objectCached = false;  // the model's object code came from the cache: nothing compiled
  int productionsCompiled = -1;  // an incremental recompile compiled this many; -1: all of them
  bool frontendBegunAhead = false;  // the compile found its front end set up (live editing)
  int optLevel = -1;  // the level the load compiled at (a better tier may run later)
};

// A better-optimised build of the loaded model (Session::betterTierJob).
struct BetterTier {
  std::shared_ptr<jit::ModelCode> code;  // null when it failed
  std::string error;                     // why
  uint64_t generation = 0;  // which load it belongs to
  int optLevel = 0;
  double compileMs = 0;
  bool objectCached = false;
};

// The files a model run uses, recognised by extension.
struct ModelFiles {
  std::string lsystem;               // the model (a grammar language's file: Languages.h)
  const Language* language = nullptr;  // its language
  std::vector<std::string> functions;  // .func, in command-line order
  std::string functionSet, timeline, parameters;
  std::string view;                  // .v (lpfg also reads .dr)
  std::string colormap, materials;   // .map / .mat: the last one given wins
  std::vector<std::string> contours;  // .con and .cset, in command-line order
  std::vector<std::string> other;     // animation (.a), surfaces (.s): not used in batch mode
  std::string environment;            // .e: the environmental program (manual §5.10); the last one wins
  // The model's own C++ translation units (.cpp .cc .cxx), compiled beside it and linked with it,
  // as a research model's lpfg.mak builds them into lsys.so.
  std::vector<std::string> sources;
  // -I: searched for the model's headers (and its sources'), before lcjit's own.
  std::vector<std::string> includeDirs;
  // From the model folder's lpfg.mak (LpfgMak.h), as lpfg applies them: its -I folders and -D
  // flags to the sources only (lpfg preprocesses the model without them, and g++ does not
  // preprocess the translated model, lsys.ii, again), and its -std (empty: lcjit's).
  std::vector<std::string> sourceIncludeDirs;
  std::vector<std::pair<std::string, std::string>> defines;
  std::string languageStandard;
  // -D NAME=VALUE (a run of a sweep, docs/sweeps.md): the model's own `#define NAME` reads VALUE
  // (frontend::PreprocessOptions::overrides), and a .vset value NAME is VALUE.
  std::vector<std::pair<std::string, std::string>> overrides;
  // --run NAME: the rule method of an XL model each step applies (empty: its first).
  std::string run;
};

llvm::Expected<ModelFiles> classifyInputs(const std::vector<std::string>& paths);

// Compile diagnostics (`FILE:LINE:COL: error: …` lines) with, under each error, the source line
// it names and a caret under the column, as clang prints them: for the viewer's overlay and the
// watcher's log, where the user is looking at the picture rather than the editor.
std::string withSourceLines(const std::string& diagnostics);

// The files lpfg monitors (§1.3): every input file, and the surfaces, meshes and textures the
// view file names (as the loaded model resolved them).
std::vector<std::string> watchedFiles(const ModelFiles& files, const runtime::DrawingFiles& drawing);

// A load's result before it replaces the running model (Session::prepare).
struct PreparedModel {
  ReloadParts what;
  int optLevel = 0;
  std::unique_ptr<runtime::FunctionStore> functions;  // null: the running model's stay
  std::unique_ptr<runtime::DrawingFiles> drawing;
  std::vector<std::string> warnings;
  std::shared_ptr<jit::ModelCode> code;  // null without `what.lsystem`
  const __lc_Model* model = nullptr;     // owned by code
  std::string cpp, bufferName;
  std::string objectKey;  // the compile's object cache key (jit::CompileStats::objectKey)
  std::string lsystem;                     // the .l file
  std::string run;                         // ModelFiles::run
  std::vector<std::pair<std::string, int>> namedGroups;  // frontend::Rewritten::namedGroups
  frontend::PreprocessOptions preprocess;  // what it was preprocessed with
  // Columns of the preprocessed text as the user wrote them (errors and faults name those).
  std::shared_ptr<const frontend::OriginalColumns> columns;
  // The model's productions, and the rest of its C++, as an incremental recompile compares them
  // (see Session::prepare).
  std::vector<std::string> rules;
  std::string rest;
  // Only the productions whose code changed were compiled (`changedRules` of them): the others
  // are the running code's, and the running model's globals are reset when it is installed.
  bool incremental = false;
  int changedRules = 0;
  std::vector<std::shared_ptr<jit::ModelCode>> ruleCode;  // where the unchanged ones are, newest first
  std::vector<std::shared_ptr<jit::ModelCode>> sourceCode;  // ModelFiles::sources, compiled
  // With `what.lsystem`: the environmental program of the .e file, started (null: none). It
  // replaces the running one when installed, as lpfg restarts it on New L-system.
  std::unique_ptr<runtime::EnvironmentLink> environment;
  PreparedModel();
  PreparedModel(PreparedModel&&);
  PreparedModel& operator=(PreparedModel&&);
  ~PreparedModel();
};

class Session {
 public:
  // `cacheDir`: where compiled headers and object code are kept ("": the user's cache folder).
  // `languageStandard`: the C++ of model code (-std=), "" for lcjit's (jit::CompilerConfig).
  // `debugger`: model code for gdb and lldb (jit::CompilerConfig::debugger).
  static llvm::Expected<std::unique_ptr<Session>> create(const std::string& cacheDir = "",
                                                         const std::string& languageStandard = "",
                                                         bool debugger = false);
  ~Session();
  // lcjit ends: the environmental program is stopped, the compiler's work on other threads
  // finished (and a private cache folder removed); the rest — the model's code, its string —
  // is left for the process's end to take. A thread the model started and left running (as an
  // lpfg model may: its compiled library stays mapped until the process is gone) would otherwise
  // run code that the session's end had unmapped, and crash lcjit after a run that succeeded.
  static void leaveAtExit(std::unique_ptr<Session> session);
  // Why the cache folder asked for is not used (it is not the user's alone), or "": a warning
  // for the user (jit::Compiler::cacheWarning).
  const std::string& cacheWarning() const;

  // Reads input files, compiles the model; on error the previous model (if any) stays loaded.
  // With `what` less than all, only those files are re-read and the rest carries over: without
  // `lsystem` the compiled model is kept, and without `parameters` also the engine and its string
  // (New view / New rendering redraw, they do not re-run).
  llvm::Error load(const ModelFiles& files, int optLevel, PhaseTimes& times, ReloadParts what = ReloadParts::all());
  // load() in two halves, for a hot swap: prepare() reads the files and compiles, on any
  // thread, while the running model goes on deriving and drawing (it only reads the running
  // model's files and settings); install() replaces the running model with the result, on the
  // thread that owns the engine, when the engine is idle.
  // A recompile whose C++ differs from the running model's only inside some productions' bodies
  // compiles just those (the rest of the model still parsed, as their context) and links them
  // with the running code's other productions; install() then resets the model's globals, so
  // that the run starts as fresh as after a full load.
  llvm::Expected<PreparedModel> prepare(const ModelFiles& files, int optLevel, PhaseTimes& times,
                                        ReloadParts what = ReloadParts::all());
  llvm::Error prepareInto(PreparedModel& p, const ModelFiles& files, int optLevel, PhaseTimes& times, ReloadParts what);
  llvm::Error install(PreparedModel prepared);
  bool loaded() const { return engine_ != nullptr; }
  runtime::Engine& engine() { return *engine_; }
  // Optimisation level of the code running now.
  int optLevel() const { return optLevel_; }

  // Two tiers: after a load at a quick level, the job this returns compiles the same model at
  // `optLevel`; it may run on any thread (the running model goes on meanwhile). installTier
  // then swaps the result in, between derivation steps, without re-running: the new code uses
  // the running version's globals. False (and nothing changes) when another load came between.
  // `onlyFromCache`: the job only looks for the build in the object cache (an earlier run's):
  // no compile, a null code (and no error) when it is not there. A better tier built for a load
  // leaves a mark beside that load's object, and the job looks only where there is one: the
  // lookup itself (the level's compiler set-up, the key) cost a short run 2.5 ms.
  std::function<BetterTier()> betterTierJob(int optLevel, bool onlyFromCache = false) const;
  // The model is being edited live (its files watched): quick compiles of it set up the next
  // one's front end ahead (jit::CompileOptions::beginNextAhead).
  void setEditedLive(bool on) { editedLive_ = on; }
  // -O1 was lcjit's choice, not the user's: a model of more than kLargeModelProductions
  // productions is compiled at -O0 instead (optLevel() says which), where -O1's passes would
  // cost more than they save; a better tier takes over if the run is long.
  void setQuickLevelBySize(bool on) { quickLevelBySize_ = on; }
  static constexpr size_t kLargeModelProductions = 1000;
  bool installTier(BetterTier tier);
  // The loaded model's tables (modules, rules with their lines and groups); null before a load.
  const __lc_Model* model() const { return model_; }
  // The production groups of the loaded model a user applies by name (XL's rule methods: the
  // window's Rules menu), each with its group (runtime::Engine::stepWith).
  const std::vector<std::pair<std::string, int>>& namedGroups() const { return namedGroups_; }
  const runtime::FunctionStore& functions() const { return *functions_; }
  // Gives the loaded model's .vset parameter `name` a new value (val(NAME) reads it at run time,
  // so a re-run uses it without a recompile). Kept until the parameters are re-read by a load.
  llvm::Error setParameter(const std::string& name, float value);
  // Gives the loaded model's .tset timeline `name` a new range (what tfunc maps onto 0..1).
  llvm::Error setTimeline(const std::string& name, float start, float end);
  // C++ typed at the REPL, compiled against the loaded model (see docs/repl.md).
  llvm::Expected<std::string> evaluate(const std::string& input);
  // Environmental programs (manual §5.10): how they are started and waited for, -cleanEA20, and
  // whether to start them at all (not for -c or --emit-cpp, which run nothing).
  struct EnvironmentSettings {
    runtime::ChildProgramOptions program;
    bool cleanEA20 = false;
    bool start = true;
  };
  void setEnvironmentSettings(const EnvironmentSettings& settings) { environmentSettings_ = settings; }
  // The limits of every derivation (docs/faults.md): this model's and the next ones'. Static
  // constructors and destructors of the model run behind the same guard and time limit.
  void setLimits(const runtime::EngineLimits& limits);
  const runtime::EngineLimits& limits() const { return limits_; }
  // --seed N: every engine of this session runs as member N of an ensemble (Rand48::setMember).
  void setEnsembleMember(std::optional<uint64_t> n) {
    member_ = n;
    if (engine_) engine_->setEnsembleMember(n);
  }
  // A model without a .map or .mat drawn in lcjit's colours (runtime::Palette::lcjitDefault: the
  // window) rather than lpfg's white on black (the default: batch pictures, which are compared
  // with lpfg's). From the next load on.
  void setLcjitColours(bool on) { lcjitColours_ = on; }
  const runtime::DrawingFiles& drawing() const { return *drawing_; }
  // This session's window state (runtime/WindowInput.h): what its window, REPL or batch run sets
  // and its model code reads, kept across loads (tunable values are kept by name, as the user
  // menu's items are until the model clears them). Every engine of the session is given it.
  runtime::WindowInput& windowInput() { return windowInput_; }
  // Problems in the graphics files (view file lines, unreadable colormap...): reported, not
  // fatal, as in lpfg. Refilled by every load().
  const std::vector<std::string>& warnings() const { return warnings_; }
  std::string generatedCpp() const {
    std::lock_guard<std::mutex> lock(cppMutex_);
    return cpp_;
  }

 private:
  Session() = default;
  // `columns` (may be null) places faults' columns as written in the model's files.
  std::function<llvm::Error(const std::function<llvm::Error()>&)> guardedStatics(
      const std::string& file, std::shared_ptr<const frontend::OriginalColumns> columns) const;
  // Refuses code of `file` whose static data alone are more than --max-memory allows, before any
  // of it is allocated (CompileOptions::checkStaticData).
  std::function<llvm::Error(const jit::StaticData&)> staticDataCheck(const std::string& file) const;
  runtime::CodeLocator codeLocator(std::shared_ptr<const frontend::OriginalColumns> columns) const;
  static void splitRules(const frontend::Rewritten& cpp, std::vector<std::string>& rules, std::string& rest);
  std::optional<std::string> incrementalUnit(const frontend::Rewritten& cpp, PreparedModel& p);
  std::unique_ptr<jit::Compiler> compiler_;
  std::unique_ptr<runtime::FunctionStore> functions_;
  std::shared_ptr<jit::ModelCode> code_;  // shared with a tier job compiling against it
  // The loaded code that owns the model's globals: the first build, then the declarations typed
  // at the REPL (each in its own unit). Later compiles share them.
  std::vector<std::shared_ptr<jit::ModelCode>> stateOwners_;
  std::string lsystem_;                       // the running model's .l file
  std::string run_;                           // and the rule method its steps apply (--run)
  std::vector<std::pair<std::string, int>> namedGroups_;  // and its groups applied by name
  frontend::PreprocessOptions preprocess_;    // and how it was preprocessed
  std::shared_ptr<const frontend::OriginalColumns> columns_;  // and its columns as written
  std::vector<std::string> replDeclarations_;  // typed at the REPL since the last load
  int replInputs_ = 0;
  int optLevel_ = 0;
  std::string objectKey_;  // of the running code's load (PreparedModel::objectKey)
  bool quickLevelBySize_ = false;
  bool lcjitColours_ = false;
  std::atomic<bool> editedLive_{false};
  uint64_t generation_ = 0;  // counts loads that compiled
  const __lc_Model* model_ = nullptr;  // owned by code_
  std::unique_ptr<runtime::EnvironmentLink> environment_;  // outlives engine_, which calls it
  runtime::WindowInput windowInput_;                       // so does this
  EnvironmentSettings environmentSettings_;
  std::unique_ptr<runtime::Engine> engine_;
  std::unique_ptr<runtime::DrawingFiles> drawing_;
  mutable std::mutex cppMutex_;
  std::string cpp_;                       // the last C++ generated, compiled or not (prepare's thread)
  std::string runningCpp_, bufferName_;   // what the running code was compiled from
  // The running model's productions and the rest of its C++ (PreparedModel::rules/rest), and
  // the loaded code that has its productions, newest first (for incremental recompiles).
  std::vector<std::string> runningRules_;
  std::string runningRest_;
  std::vector<std::shared_ptr<jit::ModelCode>> ruleCode_;
  std::string languageStandard_;  // the compiler's -std=
  // The model's extra translation units: every compile of the model links against them.
  std::vector<std::shared_ptr<jit::ModelCode>> sourceCode_;
  std::vector<std::string> warnings_;
  runtime::EngineLimits limits_;
  std::optional<uint64_t> member_;
};

// An installed lcjit's data folder, PREFIX/share/lcjit beside PREFIX/bin/lcjit (`cmake --install`,
// app/CMakeLists.txt), when it holds the runtime headers; "" for a program in its build tree.
std::string installedDataDir();
// Where the model API header (lpfgall.h) lives: the installed data folder's include/, else the
// source tree the program was built from; overridable with LCJIT_RUNTIME_INCLUDE.
std::string runtimeIncludeDir();
// The folder of what the build or the install precompiled (jit::CompilerConfig::prebuiltDir),
// overridable with LCJIT_PREBUILT_DIR ("": none).
std::string prebuiltDir();
// The example models (the built-in example of the quick start among them).
std::string examplesDir();

}  // namespace lcjit::app
