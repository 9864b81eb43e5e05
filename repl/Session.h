// One model, from files to a runnable engine: input files are sorted by extension (manual
// §1.1.2), the .l file is preprocessed, rewritten to C++ and compiled in-process, and the
// derivation engine is set up on the compiled model. Every phase is timed for --stats.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "Engine.h"
#include "ModelGuard.h"
#include "llvm/Support/Error.h"

struct __lc_Model;

namespace lcjit::jit {
class Compiler;
class ModelCode;
}  // namespace lcjit::jit
namespace lcjit::runtime {
class Engine;
class FunctionStore;
struct DrawingFiles;
}  // namespace lcjit::runtime

namespace lcjit {

struct PhaseTimes {
  double preprocessMs = 0, rewriteMs = 0, compileMs = 0, deriveMs = 0, interpretMs = 0, renderMs = 0;
  double frontendMs = 0, optimizeMs = 0, codegenMs = 0;  // the parts of compileMs
  bool pchCached = false;
};

// The files a model run uses, recognised by extension.
struct ModelFiles {
  std::string lsystem;
  std::vector<std::string> functions;  // .func, in command-line order
  std::string functionSet, timeline, parameters;
  std::string view;                  // .v (lpfg also reads .dr)
  std::string colormap, materials;   // .map / .mat: the last one given wins
  std::vector<std::string> contours;  // .con and .cset, in command-line order
  std::vector<std::string> other;     // animation (.a), environment (.e): not used in batch mode
};

llvm::Expected<ModelFiles> classifyInputs(const std::vector<std::string>& paths);

// Which input files a load re-reads (manual §1.2.2's table of the New … menu items); the rest is
// carried over from the loaded model.
struct ReloadParts {
  bool lsystem = true;     // re-read and recompile the .l file (and re-run)
  bool view = true;        // the view file
  bool rendering = true;   // colormap/materials, surfaces, meshes, textures
  bool parameters = true;  // functions, contours, timeline, parameters
  static ReloadParts all() { return {}; }
  static ReloadParts newLsystem() { return {true, false, true, true}; }
  static ReloadParts newRun() { return {false, false, true, true}; }
  static ReloadParts newView() { return {false, true, true, false}; }  // New rendering reads the same
};

class Session {
 public:
  static llvm::Expected<std::unique_ptr<Session>> create();
  ~Session();

  // Reads input files, compiles the model; on error the previous model (if any) stays loaded.
  // With `what` less than all, only those files are re-read and the rest carries over: without
  // `lsystem` the compiled model is kept, and without `parameters` also the engine and its string
  // (New view / New rendering redraw, they do not re-run).
  llvm::Error load(const ModelFiles& files, int optLevel, PhaseTimes& times, ReloadParts what = ReloadParts::all());
  runtime::Engine& engine() { return *engine_; }
  // The limits of every derivation (docs/faults.md): this model's and the next ones'. Static
  // constructors and destructors of the model run behind the same guard and time limit.
  void setLimits(const runtime::EngineLimits& limits);
  const runtime::EngineLimits& limits() const { return limits_; }
  const runtime::DrawingFiles& drawing() const { return *drawing_; }
  // Problems in the graphics files (view file lines, unreadable colormap...): reported, not
  // fatal, as in lpfg. Refilled by every load().
  const std::vector<std::string>& warnings() const { return warnings_; }
  const std::string& generatedCpp() const { return cpp_; }

 private:
  Session() = default;
  std::unique_ptr<jit::Compiler> compiler_;
  std::unique_ptr<runtime::FunctionStore> functions_;
  std::unique_ptr<jit::ModelCode> code_;
  const __lc_Model* model_ = nullptr;  // owned by code_
  std::unique_ptr<runtime::Engine> engine_;
  std::unique_ptr<runtime::DrawingFiles> drawing_;
  std::string cpp_;
  std::vector<std::string> warnings_;
  runtime::EngineLimits limits_;
  runtime::ModelGuard staticGuard_;  // the model's static constructors and destructors
};

// Where the model API header (lpfgall.h) lives: next to the binary's source tree at build time,
// overridable with LCJIT_RUNTIME_INCLUDE.
std::string runtimeIncludeDir();

}  // namespace lcjit
