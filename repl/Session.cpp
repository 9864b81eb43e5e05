// Loading a model (see Session.h).
#include "Session.h"

#include <chrono>
#include <cstdlib>
#include <filesystem>

#include "Engine.h"
#include "Functions.h"
#include "HostFunctions.h"
#include "frontend/Preprocess.h"
#include "frontend/Rewriter.h"
#include "jit/Compiler.h"

namespace lcjit {
namespace {

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

llvm::Error error(const std::string& msg) { return llvm::createStringError(llvm::inconvertibleErrorCode(), "%s", msg.c_str()); }

}  // namespace

std::string runtimeIncludeDir() {
  if (const char* e = std::getenv("LCJIT_RUNTIME_INCLUDE")) return e;
  return LCJIT_RUNTIME_INCLUDE_DIR;
}

llvm::Expected<ModelFiles> classifyInputs(const std::vector<std::string>& paths) {
  ModelFiles f;
  for (const auto& p : paths) {
    std::string ext = std::filesystem::path(p).extension().string();
    if (!std::filesystem::exists(p)) return error(p + ": error: no such file");
    if (ext == ".l") {
      if (!f.lsystem.empty()) return error(p + ": error: more than one L-system file (" + f.lsystem + " and " + p + ")");
      f.lsystem = p;
    } else if (ext == ".func") {
      f.functions.push_back(p);
    } else if (ext == ".fset") {
      f.functionSet = p;  // lpfg: the last one on the command line wins
    } else if (ext == ".tset") {
      f.timeline = p;
    } else if (ext == ".vset") {
      f.parameters = p;
    } else if (ext == ".a" || ext == ".v" || ext == ".map" || ext == ".mat" || ext == ".con" || ext == ".cset" ||
               ext == ".e" || ext == ".s") {
      f.other.push_back(p);
    } else {
      return error(p + ": error: unknown input file type '" + ext +
                   "' (expected .l, .a, .v, .map, .mat, .con, .cset, .e, .func, .fset, .tset or .vset)");
    }
  }
  if (f.lsystem.empty()) return error("error: no L-system file (.l) given");
  return f;
}

llvm::Expected<std::unique_ptr<Session>> Session::create() {
  std::unique_ptr<Session> s(new Session());
  jit::CompilerConfig config;
  config.runtimeHeader = runtimeIncludeDir() + "/lpfgall.h";
  for (auto& [name, addr] : runtime::hostFunctions()) config.hostSymbols.push_back({name, addr});
  auto compiler = jit::Compiler::create(std::move(config));
  if (!compiler) return compiler.takeError();
  s->compiler_ = std::move(*compiler);
  return s;
}

Session::~Session() {
  // The engine refers to the model's tables; the model's code must go after it.
  engine_.reset();
  code_.reset();
  functions_.reset();
}

llvm::Error Session::load(const ModelFiles& files, int optLevel, PhaseTimes& times) {
  // Function files first: their names become macros of the model, as in lpfg. lpfg's order:
  // the .fset, the .tset, the .vset, then .func files.
  auto functions = std::make_unique<runtime::FunctionStore>();
  if (!files.functionSet.empty())
    if (auto e = functions->loadFunctionSet(files.functionSet)) return e;
  if (!files.timeline.empty())
    if (auto e = functions->loadTimeline(files.timeline)) return e;
  if (!files.parameters.empty())
    if (auto e = functions->loadParameters(files.parameters)) return e;
  for (auto& f : files.functions)
    if (auto e = functions->loadFunction(f)) return e;

  auto t0 = std::chrono::steady_clock::now();
  frontend::PreprocessOptions pp;
  for (int id = 1; id <= functions->size(); ++id) {
    std::string name(functions->nameOf(id));
    if (!name.empty()) pp.defines.push_back({name, std::to_string(id)});
  }
  auto text = frontend::preprocess(files.lsystem, pp);
  if (!text) return text.takeError();
  times.preprocessMs = msSince(t0);

  t0 = std::chrono::steady_clock::now();
  auto cpp = frontend::rewrite(*text, files.lsystem);
  if (!cpp) return cpp.takeError();
  times.rewriteMs = msSince(t0);
  cpp_ = cpp->cpp;

  t0 = std::chrono::steady_clock::now();
  jit::CompileOptions co;
  co.optLevel = optLevel;
  co.bufferName = files.lsystem + ".cpp";
  jit::CompileStats stats;
  auto code = compiler_->compile(cpp->cpp, co, &stats);
  if (!code) return code.takeError();
  auto entry = (*code)->lookup(frontend::kModelEntry);
  if (!entry) return entry.takeError();
  auto describe = reinterpret_cast<const __lc_Model* (*)()>(*entry);
  const __lc_Model* model = describe();
  times.compileMs = msSince(t0);
  times.pchCached = stats.pchCached;
  if (model->abiVersion != __lc_AbiVersion) return error("internal error: model ABI version mismatch");

  // Swap in the new model only now that everything succeeded.
  engine_.reset();
  code_ = std::move(*code);
  functions_ = std::move(functions);
  engine_ = std::make_unique<runtime::Engine>(*model, functions_.get());
  return llvm::Error::success();
}

}  // namespace lcjit
