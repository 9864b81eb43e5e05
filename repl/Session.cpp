// Loading a model (see Session.h).
#include "Session.h"

#include <cctype>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <optional>

#include "Drawing.h"
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

// A file named in the view file: relative to the view file's folder, else as given (lpfg runs in
// the object's folder).
std::string besideView(const std::string& viewFile, const std::string& name) {
  std::filesystem::path p(name);
  if (p.is_absolute()) return name;
  std::filesystem::path beside = std::filesystem::path(viewFile).parent_path() / p;
  return std::filesystem::exists(beside) ? beside.string() : name;
}

// Loads the graphics inputs. Nothing here is fatal: lpfg reports a bad view file line or an
// unreadable colormap and goes on drawing with what it has.
std::unique_ptr<runtime::DrawingFiles> loadDrawingFiles(const ModelFiles& files, const ReloadParts& what,
                                                       const runtime::DrawingFiles* current,
                                                       std::vector<std::string>& warnings) {
  // What is not re-read is carried over from the model as it is.
  auto d = current ? std::make_unique<runtime::DrawingFiles>(*current) : std::make_unique<runtime::DrawingFiles>();
  auto warn = [&](llvm::Error e) {
    if (e) warnings.push_back(llvm::toString(std::move(e)));
  };
  if (what.view) d->view = runtime::ViewSettings();
  if (what.view && !files.view.empty()) {
    auto text = frontend::preprocess(files.view, {});
    if (!text) {
      warn(text.takeError());
    } else {
      std::vector<runtime::ViewFileWarning> w;
      d->view = runtime::parseViewFile(*text, files.view, w);
      for (auto& x : w) warnings.push_back(x.file + ":" + std::to_string(x.line) + ":" + std::to_string(x.column) + ": warning: " + x.message);
    }
  }
  if (what.parameters) {
    d->contours = runtime::ContourStore();
    warn(d->contours.loadFiles(files.contours));
  }
  if (!what.rendering) return d;
  d->palette = runtime::Palette();
  if (!files.colormap.empty()) warn(d->palette.loadColormap(files.colormap));
  if (!files.materials.empty()) warn(d->palette.loadMaterials(files.materials));
  d->shapes = runtime::ShapeLibrary();
  d->textures.clear();
  d->textureFiles.clear();
  d->shapeFiles.clear();
  for (auto& s : d->view.surfaces) {
    d->shapeFiles.push_back(besideView(files.view, s.file));
    auto surface = runtime::loadSurface(d->shapeFiles.back());
    if (!surface) {
      warn(surface.takeError());  // lpfg skips it: later ids shift down
      continue;
    }
    d->shapes.surfaces.push_back({std::move(*surface), s.scale, s.sdiv, s.tdiv, s.texture});
  }
  for (auto& m : d->view.meshes) {
    runtime::MeshLoadOptions o;
    o.scale = m.scale;
    o.contact = m.contact;
    d->shapeFiles.push_back(besideView(files.view, m.file));
    auto mesh = runtime::loadMesh(d->shapeFiles.back(), o);
    if (!mesh) {
      warn(mesh.takeError());
      continue;
    }
    d->shapes.meshes.push_back({std::move(*mesh), m.texture});
  }
  for (auto& t : d->view.textures) {
    std::string path = besideView(files.view, t);
    auto image = runtime::loadImage(path);
    if (!image) {
      warn(image.takeError());
      image = runtime::Image();  // keep the ids of later textures
    }
    d->textures.push_back(std::move(*image));
    d->textureFiles.push_back(path);
  }
  return d;
}

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
    } else if (ext == ".v" || ext == ".dr") {
      f.view = p;
    } else if (ext == ".map") {
      f.colormap = p;
    } else if (ext == ".mat") {
      f.materials = p;
    } else if (ext == ".con" || ext == ".cset") {
      f.contours.push_back(p);
    } else if (ext == ".a" || ext == ".e" || ext == ".s") {
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
  s->setLimits(runtime::EngineLimits());  // the default limits guard static constructors too
  return s;
}

void Session::setLimits(const runtime::EngineLimits& limits) {
  limits_ = limits;
  staticGuard_.setLimits({limits.timeLimit, limits.maxMemory});
  if (engine_) engine_->setLimits(limits);
}

Session::~Session() {
  // The engine refers to the model's tables; the model's code must go after it.
  engine_.reset();
  drawing_.reset();
  code_.reset();
  functions_.reset();
}

llvm::Error Session::load(const ModelFiles& files, int optLevel, PhaseTimes& times, ReloadParts what) {
  if (!engine_) what = ReloadParts::all();  // nothing to carry over yet
  // Function files first: their names become macros of the model, as in lpfg. lpfg's order:
  // the .fset, the .tset, the .vset, then .func files.
  // Not re-read: a recompile still needs the store (its names are macros), nothing else does.
  std::unique_ptr<runtime::FunctionStore> functions;
  if (what.parameters) functions = std::make_unique<runtime::FunctionStore>();
  else if (what.lsystem) functions = std::make_unique<runtime::FunctionStore>(*functions_);
  if (what.parameters) {
    if (!files.functionSet.empty())
      if (auto e = functions->loadFunctionSet(files.functionSet)) return e;
    if (!files.timeline.empty())
      if (auto e = functions->loadTimeline(files.timeline)) return e;
    if (!files.parameters.empty())
      if (auto e = functions->loadParameters(files.parameters)) return e;
    for (auto& f : files.functions)
      if (auto e = functions->loadFunction(f)) return e;
  }

  std::vector<std::string> warnings;
  auto drawing = loadDrawingFiles(files, what, drawing_.get(), warnings);
  if (!what.lsystem) {
    // New run: the compiled model stays and a new engine re-runs it. New view / New rendering:
    // the string stays too; only what it is drawn with changes.
    if (what.parameters) {
      engine_ = std::make_unique<runtime::Engine>(*model_, functions.get());
      engine_->setLimits(limits_);
      functions_ = std::move(functions);  // the old engine, which used the old ones, is gone
    }
    drawing_ = std::move(drawing);
    warnings_ = std::move(warnings);
    engine_->setTurtleSetup(drawing_->turtleSetup());
    engine_->setCurves(&drawing_->contours);
    return llvm::Error::success();
  }

  auto t0 = std::chrono::steady_clock::now();
  frontend::PreprocessOptions pp;
  for (int id = 1; id <= functions->size(); ++id) {
    std::string name(functions->nameOf(id));
    if (!name.empty()) pp.defines.push_back({name, std::to_string(id)});
  }
  // lpfg defines contour and surface names as their ids (names that are identifiers).
  auto defineId = [&](const std::string& name, size_t id) {
    bool ok = !name.empty() && !std::isdigit((unsigned char)name[0]);
    for (char c : name) ok = ok && (std::isalnum((unsigned char)c) || c == '_');
    if (ok) pp.defines.push_back({name, std::to_string(id)});
  };
  for (int id = 0; id < drawing->contours.size(); ++id) defineId(drawing->contours.nameOf(id), id);
  for (size_t id = 0; id < drawing->shapes.surfaces.size(); ++id) defineId(drawing->shapes.surfaces[id].surface.name, id);
  // Multi-view (§7.3): each `window:` name is its view id, for UseView and `vgroup`.
  for (size_t id = 0; id < drawing->view.windows.size(); ++id) defineId(drawing->view.windows[id].name, id);
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
  co.runModelCode = [this, file = files.lsystem](const std::function<llvm::Error()>& run) -> llvm::Error {
    std::optional<llvm::Error> result;
    runtime::Fault fault = staticGuard_.run([&] { result.emplace(run()); });
    if (!fault) return std::move(*result);
    if (result) llvm::consumeError(std::move(*result));
    const char* verb = fault.kind == runtime::FaultKind::Exception ? "threw an exception"
                       : fault.kind == runtime::FaultKind::Crash || fault.kind == runtime::FaultKind::Abort
                           ? "crashed"
                           : "was stopped";
    return error(file + ": a static constructor or destructor " + verb + ": " + fault.what);
  };
  jit::CompileStats stats;
  auto code = compiler_->compile(cpp->cpp, co, &stats);
  if (!code) return code.takeError();
  auto entry = (*code)->lookup(frontend::kModelEntry);
  if (!entry) return entry.takeError();
  auto describe = reinterpret_cast<const __lc_Model* (*)()>(*entry);
  const __lc_Model* model = describe();
  times.compileMs = msSince(t0);
  times.pchCached = stats.pchCached;
  times.frontendMs = stats.frontendMs;
  times.optimizeMs = stats.optimizeMs;
  times.codegenMs = stats.codegenMs;
  if (model->abiVersion != __lc_AbiVersion) return error("internal error: model ABI version mismatch");

  // Swap in the new model only now that everything succeeded.
  engine_.reset();
  code_ = std::move(*code);
  functions_ = std::move(functions);
  model_ = model;
  engine_ = std::make_unique<runtime::Engine>(*model, functions_.get());
  engine_->setLimits(limits_);
  drawing_ = std::move(drawing);
  warnings_ = std::move(warnings);
  engine_->setTurtleSetup(drawing_->turtleSetup());
  engine_->setCurves(&drawing_->contours);
  return llvm::Error::success();
}

}  // namespace lcjit
