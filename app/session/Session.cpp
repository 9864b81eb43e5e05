// Loading a model (see Session.h).
#include "app/session/Session.h"
#include "app/session/LpfgMak.h"

#include <cctype>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <fstream>
#include <map>
#include <sstream>
#include <mutex>

#include "runtime/turtle/Drawing.h"
#include "runtime/Engine.h"
#include "runtime/Functions.h"
#include "runtime/HostFunctions.h"
#include "runtime/files/TextLines.h"
#include "frontend/lc/Preprocess.h"
#include "frontend/lc/Rewriter.h"
#include "jit/Compiler.h"
#include "support/Elapsed.h"

namespace lcjit::app {
namespace {

// The model's language (Languages.h), whose rewriter is the L-system engine's front end: the
// one given, else its extension's; a file of no language is read as L+C.
const Language& lsystemLanguage(const Language* given, const std::string& path) {
  const Language* language = given ? given : languageOf(path);
  return language ? *language : *languageNamed("L+C");
}

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
                                                       const runtime::DrawingFiles* current, const std::string& cacheDir,
                                                       bool lcjitColours, std::vector<std::string>& warnings) {
  // What is not re-read is carried over from the model as it is.
  auto d = current ? std::make_unique<runtime::DrawingFiles>(*current) : std::make_unique<runtime::DrawingFiles>();
  // A drawing file that cannot be read is left out and the run goes on (as lpfg does), so its
  // reader's error is said as a warning: an "error:" with exit status 0 reads as a contradiction.
  auto warn = [&](llvm::Error e) {
    if (!e) return;
    std::string text = llvm::toString(std::move(e));
    if (size_t at = text.find(": error: "); at != std::string::npos) text.replace(at, 9, ": warning: ");
    warnings.push_back(text + " (lcjit goes on without it)");
  };
  if (what.view) d->view = runtime::ViewSettings();
  if (what.view && !files.view.empty()) {
    frontend::PreprocessOptions pp;
    pp.runtimeIncludeDir = runtimeIncludeDir();
    pp.prebuiltDir = prebuiltDir();
    pp.cacheDir = cacheDir;
    auto text = frontend::preprocess(files.view, pp);
    if (!text) {
      // Nothing of it is used, and the model still runs: its messages are warnings.
      std::string why = llvm::toString(text.takeError());
      for (size_t at = why.find(": error: "); at != std::string::npos; at = why.find(": error: ", at))
        why.replace(at, 9, ": warning: ");
      warnings.push_back(why);
      warnings.push_back(files.view + ": warning: the view file could not be read; the model is drawn with the default view");
    } else {
      std::vector<runtime::ViewFileWarning> w;
      d->view = runtime::parseViewFile(*text, files.view, w);
      for (auto& x : w) warnings.push_back(x.file + ":" + std::to_string(x.line) + ":" + std::to_string(x.column) + ": warning: " + x.message);
    }
  }
  if (what.view) {
    // lpfg builds its terrain as it reads the `terrain:` line: a new one with each view file.
    d->terrain.reset();
    if (const auto& t = d->view.terrain) {
      auto terrain = runtime::Terrain::load(*t, besideView(files.view, t->file),
                                            d->view.renderMode == runtime::RenderMode::Wireframe);
      if (terrain) d->terrain = std::move(*terrain);
      else warn(terrain.takeError());
    }
  }
  if (what.parameters) {
    d->contours = runtime::ContourStore();
    warn(d->contours.loadFiles(files.contours));
  }
  if (!what.rendering) return d;
  const bool colourFile = !files.colormap.empty() || !files.materials.empty();
  // Without a colour file: the language's own colours (XL's are GroIMP's), else lcjit's in the
  // window, else lpfg's.
  const Language& language = lsystemLanguage(files.language, files.lsystem);
  if (colourFile) d->palette = runtime::Palette();
  else if (language.colours) d->palette = language.colours();
  else d->palette = lcjitColours ? runtime::Palette::lcjitDefault() : runtime::Palette();
  if (!files.colormap.empty()) warn(d->palette.loadColormap(files.colormap, &warnings));
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
  for (auto& b : d->view.bsurfaces) {
    d->shapeFiles.push_back(besideView(files.view, b.file));
    std::vector<std::string> notes;
    runtime::BSplineFile f = runtime::loadBSpline(d->shapeFiles.back(), notes);
    warnings.insert(warnings.end(), notes.begin(), notes.end());
    d->shapes.bsplines.push_back({std::move(f.net), b.sdiv, b.tdiv, b.texture});
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

// The length of line `line` of `file` as it is on the disk (none when it cannot be read).
std::optional<unsigned> lineLength(const std::string& file, unsigned line) {
  std::ifstream in(file);
  std::string text;
  for (unsigned i = 0; i < line && std::getline(in, text); ++i)
    if (i + 1 == line) return unsigned(text.size() - (!text.empty() && text.back() == '\r'));
  return std::nullopt;
}

// A compile's errors, each naming the file it is about: those with no place of their own (the
// link's, the back end's) name `file`, the unit that was compiled.
std::string namingFile(const std::string& file, llvm::StringRef errors) {
  std::string out;
  for (llvm::StringRef rest = errors; !rest.empty();) {
    auto [line, next] = rest.split('\n');
    if (line.starts_with("error: ")) out += file + ": ";
    out += line;
    if (next.data() != nullptr && line.size() < rest.size()) out += '\n';
    rest = next;
  }
  return out;
}

}  // namespace

std::string installedDataDir() {
  static const std::string dir = [] {
    std::error_code ec;
    std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (ec) return std::string();
    std::filesystem::path share = exe.parent_path().parent_path() / "share" / "lcjit";
    return std::filesystem::is_regular_file(share / "include" / "lpfgall.h", ec) ? share.string() : std::string();
  }();
  return dir;
}

std::string runtimeIncludeDir() {
  if (const char* e = std::getenv("LCJIT_RUNTIME_INCLUDE")) return e;
  if (std::string installed = installedDataDir(); !installed.empty()) return installed + "/include";
  return LCJIT_RUNTIME_INCLUDE_DIR;
}

std::string prebuiltDir() {
  // Made by the build (app/CMakeLists.txt) or the install; LCJIT_PREBUILT_DIR="" goes without
  // (tests of the cache).
  if (const char* e = std::getenv("LCJIT_PREBUILT_DIR")) return e;
  if (std::string installed = installedDataDir(); !installed.empty()) return installed + "/prebuilt";
  return LCJIT_PREBUILT_DIR;
}

std::string examplesDir() {
  if (std::string installed = installedDataDir(); !installed.empty()) return installed + "/examples";
  return LCJIT_EXAMPLES_DIR;
}

llvm::Expected<ModelFiles> classifyInputs(const std::vector<std::string>& paths) {
  ModelFiles f;
  for (const auto& p : paths) {
    if (!std::filesystem::exists(p)) return llvm::createStringError(p + ": error: no such file");
    const InputExtension* in = inputExtensionOf(p);
    switch (in && in->commandLine ? in->kind : FileKind::Other) {
      case FileKind::Model: {
        const Language* language = languageOf(p);
        if (!f.lsystem.empty())
          return llvm::createStringError(p + ": error: more than one " +
                                         (language == f.language ? std::string(language->model) : "model") + " file (" +
                                         f.lsystem + " and " + p + ")");
        f.lsystem = p;
        f.language = language;
        break;
      }
      case FileKind::Function:
        if (in->set)
          f.functionSet = p;  // lpfg: the last one on the command line wins
        else
          f.functions.push_back(p);
        break;
      case FileKind::Timeline: f.timeline = p; break;
      case FileKind::Parameters: f.parameters = p; break;
      case FileKind::View: f.view = p; break;
      case FileKind::Colormap: f.colormap = p; break;
      case FileKind::Material: f.materials = p; break;
      case FileKind::Contour: f.contours.push_back(p); break;
      case FileKind::Environment: f.environment = p; break;
      case FileKind::Animation:
      case FileKind::Surface: f.other.push_back(p); break;
      case FileKind::Texture:
      case FileKind::Other:
        if (isCppSource(p)) {
          f.sources.push_back(p);
          break;
        }
        return llvm::createStringError(p + ": error: unknown input file type '" +
                                       std::filesystem::path(p).extension().string() + "' (expected " +
                                       commandLineExtensions() + ", or C++ sources .cpp .cc .cxx .C .c++)");
    }
  }
  if (f.lsystem.empty()) return llvm::createStringError("error: " + noModelGiven());
  // lpfg builds a model whose folder has an lpfg.mak with it: its sources, flags and -std.
  auto mak = readLpfgMak(std::filesystem::path(f.lsystem).parent_path().string());
  if (!mak) return mak.takeError();
  if (*mak) {
    for (auto& s : (*mak)->sources)
      if (std::find(f.sources.begin(), f.sources.end(), s) == f.sources.end()) f.sources.push_back(s);
    f.sourceIncludeDirs = (*mak)->includeDirs;
    f.defines = (*mak)->defines;
    f.languageStandard = (*mak)->languageStandard;
  }
  return f;
}

std::string withSourceLines(const std::string& diagnostics) {
  std::string out;
  std::map<std::string, std::vector<std::string>> files;  // read once each
  std::istringstream in(diagnostics);
  for (std::string line; std::getline(in, line);) {
    out += line + "\n";
    // FILE:LINE:COL: error: — the file name itself may contain ':'; the numbers come last.
    size_t at = line.find(": error: ");
    if (at == std::string::npos) continue;
    size_t c = line.rfind(':', at - 1), l = c == std::string::npos || c == 0 ? std::string::npos : line.rfind(':', c - 1);
    if (l == std::string::npos) continue;
    std::string file = line.substr(0, l);
    int row = std::atoi(line.c_str() + l + 1), column = std::atoi(line.c_str() + c + 1);
    if (row <= 0 || column <= 0 || file.empty() || file[0] == '<') continue;  // <lcjit: generated ...>
    auto [it, fresh] = files.try_emplace(file);
    if (fresh)
      if (auto text = support::readInputFile(file, /*nullTerminated=*/false))
        for (std::string_view s : runtime::textfile::splitLines((*text)->getBuffer())) it->second.emplace_back(s);
    if (row > (int)it->second.size()) continue;
    std::string source = it->second[row - 1];
    std::string caret;
    for (int i = 0; i + 1 < column && i < (int)source.size(); ++i) caret += source[i] == '\t' ? '\t' : ' ';
    char number[16];
    std::snprintf(number, sizeof number, "%5d | ", row);
    out += number + source + "\n      | " + caret + "^\n";
  }
  if (!out.empty() && diagnostics.back() != '\n') out.pop_back();
  return out;
}

std::vector<std::string> watchedFiles(const ModelFiles& files, const runtime::DrawingFiles& drawing) {
  std::vector<std::string> f{files.lsystem};
  for (const std::string* one :
       {&files.view, &files.colormap, &files.materials, &files.functionSet, &files.timeline, &files.parameters})
    if (!one->empty()) f.push_back(*one);
  f.insert(f.end(), files.functions.begin(), files.functions.end());
  f.insert(f.end(), files.contours.begin(), files.contours.end());
  f.insert(f.end(), files.other.begin(), files.other.end());
  if (!files.environment.empty()) f.push_back(files.environment);
  f.insert(f.end(), drawing.textureFiles.begin(), drawing.textureFiles.end());
  f.insert(f.end(), drawing.shapeFiles.begin(), drawing.shapeFiles.end());
  return f;
}

llvm::Expected<std::unique_ptr<Session>> Session::create(const std::string& cacheDir,
                                                         const std::string& languageStandard, bool debugger) {
  std::unique_ptr<Session> s(new Session());
  jit::CompilerConfig config;
  config.runtimeHeader = runtimeIncludeDir() + "/lpfgall.h";
  config.cacheDir = cacheDir;
  config.prebuiltDir = prebuiltDir();
  if (!languageStandard.empty()) config.languageStandard = languageStandard;
  config.debugger = debugger;
  s->languageStandard_ = config.languageStandard;
  for (auto& [name, addr] : runtime::hostFunctions()) config.hostSymbols.push_back({name, addr});
  auto compiler = jit::Compiler::create(std::move(config));
  if (!compiler) return compiler.takeError();
  s->compiler_ = std::move(*compiler);
  s->setLimits(runtime::EngineLimits());  // the default limits guard static constructors too
  return s;
}

const std::string& Session::cacheWarning() const { return compiler_->cacheWarning(); }

void Session::setLimits(const runtime::EngineLimits& limits) {
  limits_ = limits;
  if (engine_) engine_->setLimits(limits);
}

// The model's static constructors and destructors are model code: behind a guard (one per call:
// they run on the thread that compiles or drops a version, possibly beside another's).
std::function<llvm::Error(const std::function<llvm::Error()>&)> Session::guardedStatics(
    const std::string& file, std::shared_ptr<const frontend::OriginalColumns> columns) const {
  return [limits = runtime::GuardLimits{limits_.timeLimit, limits_.maxMemory}, file,
          locate = codeLocator(std::move(columns))](const std::function<llvm::Error()>& run) -> llvm::Error {
    runtime::ModelGuard guard;
    guard.setLimits(limits);
    std::optional<llvm::Error> result;
    runtime::Fault fault = guard.run([&] { result.emplace(run()); });
    if (!fault) return std::move(*result);
    if (result) llvm::consumeError(std::move(*result));
    const char* verb = fault.kind == runtime::FaultKind::Exception ? "threw an exception"
                       : fault.kind == runtime::FaultKind::Crash || fault.kind == runtime::FaultKind::Abort
                           ? "crashed"
                           : "was stopped";
    auto place = runtime::faultPlace(fault, locate);
    return llvm::createStringError((place ? runtime::placeText(*place, {file}) : file) + ": a static constructor or destructor " +
                                   verb + ": " + fault.what);
  };
}

// The guard watches the memory only while model code runs, and a model's arrays are allocated when
// it is linked, before: an array larger than the limit is refused then, at its declaration,
// rather than run until the model touches it (docs/faults.md).
std::function<llvm::Error(const jit::StaticData&)> Session::staticDataCheck(const std::string& file) const {
  return [limit = limits_.maxMemory, file](const jit::StaticData& d) -> llvm::Error {
    if (!limit || d.bytes <= limit) return llvm::Error::success();
    std::string largest = d.largest.empty() ? "" : "; '" + d.largest + "' alone takes " + runtime::sizeInWords(d.largestBytes);
    return llvm::createStringError((d.declaredAt.empty() ? file : d.declaredAt) + ": error: the model's static data take " +
                                   runtime::sizeInWords(d.bytes) + ", more than the memory limit (--max-memory " +
                                   runtime::sizeInWords(limit) + ")" + largest);
  };
}

// The statement at a model code address, in the model's own files (the JIT's line tables): the
// innermost place whose column is on its line as written. One past the line's end is code lcjit
// generated and placed on the user's line, never a statement the user wrote: the place it was
// inlined at is named instead, or the model's call that led there (the guard's next frame).
runtime::CodeLocator Session::codeLocator(std::shared_ptr<const frontend::OriginalColumns> columns) const {
  return [compiler = compiler_.get(), columns = std::move(columns)](uintptr_t address,
                                                                    bool returnAddress) -> std::optional<runtime::CodePlace> {
    for (const jit::SourcePlace& p : compiler->sourceAt(address, returnAddress)) {
      const unsigned column = columns ? columns->column(p.file, p.line, p.column) : p.column;
      const std::optional<unsigned> length = lineLength(p.file, p.line);
      if (column == 0 || !length || column <= *length) return runtime::CodePlace{p.file, p.line, column};
    }
    return std::nullopt;
  };
}

// Out of line: the header only forward-declares what these members are.
PreparedModel::PreparedModel() = default;
PreparedModel::PreparedModel(PreparedModel&&) = default;
PreparedModel& PreparedModel::operator=(PreparedModel&&) = default;
PreparedModel::~PreparedModel() = default;

Session::~Session() {
  // The engine refers to the model's tables; the model's code must go after it.
  engine_.reset();
  environment_.reset();
  drawing_.reset();
  code_.reset();
  functions_.reset();
}

void Session::leaveAtExit(std::unique_ptr<Session> session) {
  if (!session) return;
  session->environment_.reset();
  session->compiler_->settleAtExit();
  (void)session.release();
}

llvm::Expected<PreparedModel> Session::prepare(const ModelFiles& files, int optLevel, PhaseTimes& times,
                                               ReloadParts what) {
  if (!engine_) what = ReloadParts::all();  // nothing to carry over yet
  PreparedModel p;
  if (auto e = prepareInto(p, files, optLevel, times, what)) {
    if (p.warnings.empty()) return std::move(e);
    // The input files' warnings come first: they often explain the error (a surface file that did
    // not load leaves the model's 'leaf' undeclared).
    std::string text;
    for (const std::string& w : p.warnings) text += w + "\n";
    return llvm::createStringError(text + llvm::toString(std::move(e)));
  }
  return p;
}

llvm::Error Session::prepareInto(PreparedModel& p, const ModelFiles& files, int optLevel, PhaseTimes& times,
                                 ReloadParts what) {
  p.what = what;
  p.optLevel = optLevel;
  // Function files first: their names become macros of the model, as in lpfg. lpfg's order:
  // the .fset, the .tset, the .vset, then .func files.
  // Not re-read: a recompile still needs the store (its names are macros), nothing else does.
  if (what.parameters) p.functions = std::make_unique<runtime::FunctionStore>();
  else if (what.lsystem) p.functions = std::make_unique<runtime::FunctionStore>(*functions_);
  runtime::FunctionStore* functions = p.functions.get();
  if (what.parameters) {
    if (!files.functionSet.empty())
      if (auto e = functions->loadFunctionSet(files.functionSet)) return e;
    if (!files.timeline.empty())
      if (auto e = functions->loadTimeline(files.timeline)) return e;
    if (!files.parameters.empty())
      if (auto e = functions->loadParameters(files.parameters)) return e;
    for (auto& f : files.functions)
      if (auto e = functions->loadFunction(f)) return e;
    // -D of a .vset value (a number) or of a .tset timeline (START:END, the range tfunc maps onto
    // 0..1); the others are #defines (preprocess, below).
    const auto timelines = functions->timelines();
    for (const auto& [name, value] : files.overrides) {
      const bool timeline = std::any_of(timelines.begin(), timelines.end(), [&](const auto& t) { return t.name == name; });
      int id = functions->idOf(name);
      const bool parameter = functions->isParameter(id) && functions->nameOf(id) == name;
      if (!timeline && !parameter) continue;
      char* end = nullptr;
      float v = std::strtof(value.c_str(), &end);
      if (parameter) {
        if (value.empty() || *end)
          return llvm::createStringError("error: -D " + name + "=" + value + ": the .vset value " + name + " is a number");
        functions->setParameter(name, v);
      } else {
        char* rest = nullptr;
        float to = *end == ':' ? std::strtof(end + 1, &rest) : 0;
        if (value.empty() || end == value.c_str() || *end != ':' || rest == end + 1 || *rest)
          return llvm::createStringError("error: -D " + name + "=" + value + ": the .tset timeline " + name +
                                         " takes START:END");
        functions->setTimeline(name, v, to);
      }
    }
  }

  p.drawing = loadDrawingFiles(files, what, drawing_.get(), compiler_->cacheDir(), lcjitColours_, p.warnings);
  // New run: the compiled model stays and a new engine re-runs it. New view / New rendering:
  // the string stays too; only what it is drawn with changes.
  if (!what.lsystem) return llvm::Error::success();

  const runtime::DrawingFiles* drawing = p.drawing.get();
  auto t0 = std::chrono::steady_clock::now();
  frontend::PreprocessOptions pp;
  pp.runtimeIncludeDir = runtimeIncludeDir();
  pp.prebuiltDir = prebuiltDir();
  pp.cacheDir = compiler_->cacheDir();
  pp.includeDirs = files.includeDirs;
  pp.languageStandard = languageStandard_;
  pp.overrides = files.overrides;
  for (int id = 1; id <= functions->size(); ++id)
    if (functions->isParameter(id)) pp.overridableElsewhere.emplace_back(functions->nameOf(id));
  for (const auto& t : functions->timelines()) pp.overridableElsewhere.push_back(t.name);
  if (!files.languageStandard.empty() && files.languageStandard != languageStandard_)
    return llvm::createStringError(files.lsystem + ": error: the model's lpfg.mak asks for -std=" + files.languageStandard +
                 ", and this session compiles " + languageStandard_ + ": start lcjit again for it");
  // The model's own C++ units first: the model links against them. Preprocessed as the model is
  // (their quoted headers become part of the text the object cache keys on), without its macros.
  // Counted as compile time.
  const auto unitsStart = std::chrono::steady_clock::now();
  for (const std::string& source : files.sources) {
    frontend::PreprocessOptions spp = pp;
    spp.overrides.clear();  // the model's #defines; its units are preprocessed without its macros
    spp.plainMarkers = true;
    spp.includeDirs.insert(spp.includeDirs.end(), files.sourceIncludeDirs.begin(), files.sourceIncludeDirs.end());
    spp.defines = files.defines;
    auto text = frontend::preprocess(source, spp);
    if (!text) return text.takeError();
    jit::CompileOptions so;
    so.optLevel = optLevel;
    so.plainUnit = true;
    so.bufferName = source;
    auto unitColumns = std::make_shared<frontend::OriginalColumns>(*text);
    so.runModelCode = guardedStatics(source, unitColumns);
    so.checkStaticData = staticDataCheck(source);
    jit::CompileStats unitStats;
    auto unit = compiler_->compile(*text, so, &unitStats);
    for (const std::string& n : unitStats.notes) p.warnings.push_back("lcjit: " + n);
    if (!unit) return llvm::createStringError(namingFile(source, unitColumns->diagnostics(llvm::toString(unit.takeError()))));
    p.sourceCode.push_back(std::move(*unit));
  }
  const double unitsMs = support::msSince(unitsStart);
  t0 = std::chrono::steady_clock::now();
  // lpfg defines the names of functions, parameters, contours and surfaces as their ids, for the
  // model to use; a name that is not an identifier cannot be one (it would fail as a macro on
  // '<command line>').
  auto defineId = [&](const std::string& name, size_t id) {
    bool ok = !name.empty() && !std::isdigit((unsigned char)name[0]);
    for (char c : name) ok = ok && (std::isalnum((unsigned char)c) || c == '_');
    if (ok) pp.defines.push_back({name, std::to_string(id)});
    return ok;
  };
  for (int id = 1; id <= functions->size(); ++id) {
    std::string name(functions->nameOf(id));
    if (!name.empty() && !defineId(name, id))
      p.warnings.push_back("lcjit: warning: the function or parameter '" + name +
                           "' (.func, .fset, .tset or .vset) is not named as an identifier; the model cannot use its name");
  }
  for (int id = 0; id < drawing->contours.size(); ++id) defineId(drawing->contours.nameOf(id), id);
  for (size_t id = 0; id < drawing->shapes.surfaces.size(); ++id) defineId(drawing->shapes.surfaces[id].surface.name, id);
  // Multi-view (§7.3): each `window:` name is its view id, for UseView and `vgroup`.
  for (size_t id = 0; id < drawing->view.windows.size(); ++id) defineId(drawing->view.windows[id].name, id);
  // A model of a language on another engine (a Context Free design given to the REPL) is an
  // error, before anything reads it as an L-system.
  const Language& language = lsystemLanguage(files.language, files.lsystem);
  if (!language.rewrite)
    return llvm::createStringError(files.lsystem + ": error: a " + std::string(language.model) +
                                   " is not an L-system, and this mode runs L-systems (lcjit " + files.lsystem +
                                   " draws it)");
  auto text = frontend::preprocess(files.lsystem, pp);
  if (!text) return text.takeError();
  p.preprocess = pp;
  p.lsystem = files.lsystem;
  p.run = files.run;
  times.preprocessMs = support::msSince(t0);

  t0 = std::chrono::steady_clock::now();
  auto cpp = language.rewrite(*text, files.lsystem, files.run);
  p.columns = std::make_shared<frontend::OriginalColumns>(std::move(*text));
  // The rewriter's and the compile's errors count columns in the preprocessed text.
  auto asWritten = [&](llvm::Error e) {
    return llvm::createStringError(namingFile(files.lsystem, p.columns->diagnostics(llvm::toString(std::move(e)))));
  };
  if (!cpp) return asWritten(cpp.takeError());
  times.rewriteMs = support::msSince(t0);
  {
    std::lock_guard<std::mutex> lock(cppMutex_);
    cpp_ = cpp->cpp;
  }

  t0 = std::chrono::steady_clock::now();
  jit::CompileOptions co;
  co.optLevel = optLevel;
  co.bufferName = files.lsystem + ".cpp";
  co.runModelCode = guardedStatics(files.lsystem, p.columns);
  co.checkStaticData = staticDataCheck(files.lsystem);
  co.beginNextAhead = editedLive_;
  for (const auto& c : p.sourceCode) co.linkAgainst.push_back(c.get());
  jit::CompileStats stats;
  splitRules(*cpp, p.rules, p.rest);
  // A model of thousands of productions (generated by a script) spends longer in
  // -O1's passes than they save: its quick tier is -O0 (20,000 productions: 5.4 -> 3.2 s), and
  // without line tables, a third of its compile (a fault names the rule's line, not the
  // statement's; the better tier has them).
  if (quickLevelBySize_ && optLevel == 1 && p.rules.size() > kLargeModelProductions) {
    co.optLevel = p.optLevel = 0;
    co.lineTables = false;
  }
  llvm::Expected<std::unique_ptr<jit::ModelCode>> code = nullptr;
  if (std::optional<std::string> unit = incrementalUnit(*cpp, p)) {
    jit::CompileOptions uo = co;
    {
      std::lock_guard<std::mutex> lock(cppMutex_);
      uo.shareStateWith = {stateOwners_[0].get()};
      p.ruleCode = ruleCode_;
    }
    uo.linkAgainst.clear();  // the kept productions' code (no units of the model's own here)
    for (const auto& c : p.ruleCode) uo.linkAgainst.push_back(c.get());
    code = compiler_->compile(*unit, uo, &stats);
    if (code) {
      p.incremental = true;
    } else {
      // A compile error is the user's, and a full compile would say the same; anything else
      // (the old code not there to link with) is lcjit's problem: compile it all instead.
      std::string message = llvm::toString(code.takeError());
      if (message.find("JIT link failed") == std::string::npos) return asWritten(llvm::createStringError(message));
      p.changedRules = 0;
      p.ruleCode.clear();
    }
  }
  if (!p.incremental) code = compiler_->compile(cpp->cpp, co, &stats);
  for (const std::string& n : stats.notes) p.warnings.push_back("lcjit: " + n);
  if (!code) return asWritten(code.takeError());
  auto entry = (*code)->lookup(frontend::kModelEntry);
  if (!entry) return entry.takeError();
  auto describe = reinterpret_cast<const __lc_Model* (*)()>(*entry);
  p.model = describe();
  times.compileMs = support::msSince(t0) + unitsMs;
  times.pchCached = stats.pchCached;
  times.objectCached = stats.object != jit::CompileStats::ObjectFrom::Compiled;
  times.productionsCompiled = p.incremental ? p.changedRules : -1;
  times.frontendMs = stats.frontendMs;
  times.frontendBegunAhead = stats.frontendBegunAhead;
  times.optimizeMs = stats.optimizeMs;
  times.codegenMs = stats.codegenMs;
  times.loadMs = stats.loadMs;
  times.optLevel = p.optLevel;
  if (p.model->abiVersion != __lc_AbiVersion) return llvm::createStringError("internal error: model ABI version mismatch");
  p.code = std::move(*code);
  p.objectKey = stats.objectKey;
  p.cpp = std::move(cpp->cpp);
  p.namedGroups = std::move(cpp->namedGroups);
  p.bufferName = co.bufferName;
  // lpfg starts the environmental program once the model has compiled.
  if (!files.environment.empty() && environmentSettings_.start) {
    std::vector<runtime::ViewFileWarning> warnings;
    auto spec = runtime::loadCommSpec(files.environment, warnings);
    for (auto& w : warnings)
      p.warnings.push_back(w.file + ":" + std::to_string(w.line) + ":" + std::to_string(w.column) + ": warning: " + w.message);
    if (!spec) return spec.takeError();
    auto link = runtime::startEnvironment(*spec, environmentSettings_.program);
    if (!link) return link.takeError();
    p.environment = std::move(*link);
  }
  return llvm::Error::success();
}

llvm::Error Session::install(PreparedModel p) {
  llvm::Error reset = llvm::Error::success();
  if (p.what.lsystem) {
    engine_.reset();  // it refers to the old model's tables
    std::lock_guard<std::mutex> lock(cppMutex_);
    code_ = std::move(p.code);
    model_ = p.model;
    optLevel_ = p.optLevel;
    objectKey_ = std::move(p.objectKey);
    ++generation_;
    runningCpp_ = std::move(p.cpp);
    bufferName_ = std::move(p.bufferName);
    runningRules_ = std::move(p.rules);
    runningRest_ = std::move(p.rest);
    if (p.incremental) {
      // The globals are the first build's, used by all the productions' code: as after a load.
      ruleCode_ = std::move(p.ruleCode);
      ruleCode_.insert(ruleCode_.begin(), code_);
      reset = stateOwners_[0]->resetState();
    } else {
      stateOwners_ = {code_};
      ruleCode_ = {code_};
    }
    preprocess_ = std::move(p.preprocess);
    columns_ = std::move(p.columns);
    lsystem_ = std::move(p.lsystem);
    run_ = std::move(p.run);
    namedGroups_ = std::move(p.namedGroups);
    sourceCode_ = std::move(p.sourceCode);
    replDeclarations_.clear();  // a reload replaces them
  }
  if (p.what.lsystem || p.what.parameters) {
    engine_ = std::make_unique<runtime::Engine>(*model_, p.functions.get());
    engine_->showNames(lsystemLanguage(nullptr, lsystem_).shownName);
    engine_->useWords(lsystemLanguage(nullptr, lsystem_).words);
    engine_->setLimits(limits_);
    engine_->setEnsembleMember(member_);
    engine_->setCodeLocator(codeLocator(columns_));
    functions_ = std::move(p.functions);  // the old engine, which used the old ones, is gone
  }
  if (p.what.lsystem) environment_ = std::move(p.environment);  // the old program is stopped
  engine_->setEnvironment(environment_.get());
  engine_->setWindowInput(&windowInput_);
  engine_->setCleanEA20(environmentSettings_.cleanEA20);
  drawing_ = std::move(p.drawing);
  warnings_ = std::move(p.warnings);
  engine_->setTurtleSetup(drawing_->turtleSetup());
  engine_->setCurves(&drawing_->contours);
  return reset;
}

llvm::Error Session::load(const ModelFiles& files, int optLevel, PhaseTimes& times, ReloadParts what) {
  auto p = prepare(files, optLevel, times, what);
  if (!p) return p.takeError();
  return install(std::move(*p));
}

namespace {
// C++ as an incremental recompile compares it: without #line directives and with every run of
// white space one space (a production that grew by a line moves the ones after it).
std::string normalized(std::string_view text) {
  std::string out;
  bool space = false, lineStart = true;
  for (size_t i = 0; i < text.size(); ++i) {
    if (lineStart && text.substr(i, 5) == "#line") {
      i = std::min(text.find('\n', i), text.size()) - 1;
      continue;
    }
    char c = text[i];
    lineStart = c == '\n';
    if (std::isspace((unsigned char)c)) {
      space = true;
      continue;
    }
    if (space && !out.empty()) out += ' ';
    space = false;
    out += c;
  }
  return out;
}
}  // namespace

void Session::splitRules(const frontend::Rewritten& cpp, std::vector<std::string>& rules, std::string& rest) {
  std::string_view all(cpp.cpp);
  size_t at = 0;
  std::string outside;
  for (auto [begin, end] : cpp.ruleSpans) {
    outside += all.substr(at, begin - at);
    outside += '\n';
    rules.push_back(normalized(all.substr(begin, end - begin)));
    at = end;
  }
  outside += all.substr(at, cpp.tablesAt - at);  // the tables are always compiled anew
  rest = normalized(outside);
}

// The C++ to compile when only some productions changed: the model's C++ with the unchanged
// productions' functions reduced to declarations (their #line directives and line breaks kept,
// so that diagnostics in the changed ones point where they should). Nothing when a full compile
// is due: the first load, another text outside the productions, other productions, REPL
// declarations in the running code, or more than half of the productions changed.
std::optional<std::string> Session::incrementalUnit(const frontend::Rewritten& cpp, PreparedModel& p) {
  std::lock_guard<std::mutex> lock(cppMutex_);
  // The model's own C++ units are compiled afresh for each version (their globals start over, as
  // a new lpfg library's do): productions kept from the last version would call its copies.
  if (!p.sourceCode.empty()) return std::nullopt;
  if (!engine_ || !replDeclarations_.empty() || ruleCode_.empty() || p.rest != runningRest_ ||
      p.rules.size() != runningRules_.size())
    return std::nullopt;
  std::vector<bool> changed(p.rules.size());
  for (size_t i = 0; i < p.rules.size(); ++i) changed[i] = p.rules[i] != runningRules_[i];
  p.changedRules = (int)std::count(changed.begin(), changed.end(), true);
  if (p.changedRules == 0 || p.changedRules * 2 > (int)p.rules.size()) return std::nullopt;
  std::string unit;
  size_t at = 0;
  for (size_t i = 0; i < cpp.ruleSpans.size(); ++i) {
    auto [begin, end] = cpp.ruleSpans[i];
    if (changed[i]) continue;
    unit.append(cpp.cpp, at, begin - at);
    std::string declaration = "static void __lc_rule_" + std::to_string(i) + "(__lc_Ctx*, const char* const*);";
    std::string_view body(cpp.cpp.data() + begin, end - begin);
    for (size_t line = 0; line < body.size();) {
      size_t next = std::min(body.find('\n', line), body.size());
      std::string_view text = body.substr(line, next - line);
      if (text.substr(0, 5) == "#line") unit += text;
      else if (!declaration.empty() && !text.empty()) unit += std::exchange(declaration, std::string());
      if (next < body.size()) unit += '\n';
      line = next + 1;
    }
    at = end;
  }
  unit.append(cpp.cpp, at, std::string::npos);
  return unit;
}

std::function<BetterTier()> Session::betterTierJob(int optLevel, bool onlyFromCache) const {
  return [compiler = compiler_.get(), owners = stateOwners_, sources = sourceCode_, cpp = runningCpp_, name = bufferName_,
          generation = generation_, optLevel, onlyFromCache, statics = guardedStatics(lsystem_, columns_),
          mark = objectKey_.empty() ? std::string()
                                    : compiler_->objectsDir() + "/" + objectKey_ + ".better-O" + std::to_string(optLevel)]()
             -> BetterTier {
    if (onlyFromCache && (mark.empty() || !std::filesystem::exists(mark))) return {};
    auto t0 = std::chrono::steady_clock::now();
    jit::CompileOptions co;
    co.optLevel = optLevel;
    co.bufferName = name;
    co.runModelCode = statics;
    co.onlyFromCache = onlyFromCache;
    for (const auto& owner : owners) co.shareStateWith.push_back(owner.get());  // alive until the job ends
    for (const auto& source : sources) co.linkAgainst.push_back(source.get());
    jit::CompileStats stats;
    auto code = compiler->compile(cpp, co, &stats);
    BetterTier t;
    if (!code) {
      t.error = llvm::toString(code.takeError());
      return t;
    }
    t.code = std::move(*code);
    if (t.code && !mark.empty() && !onlyFromCache) std::ofstream{mark};  // for the next run's lookup
    t.generation = generation;
    t.optLevel = optLevel;
    t.compileMs = support::msSince(t0);
    t.objectCached = stats.object != jit::CompileStats::ObjectFrom::Compiled;
    return t;
  };
}

bool Session::installTier(BetterTier tier) {
  if (!engine_ || !tier.code || tier.generation != generation_) return false;
  auto entry = tier.code->lookup(frontend::kModelEntry);
  if (!entry) {
    llvm::consumeError(entry.takeError());
    return false;
  }
  const __lc_Model* model = reinterpret_cast<const __lc_Model* (*)()>(*entry)();
  engine_->swapModel(*model);
  model_ = model;
  code_ = std::move(tier.code);  // the previous version stays loaded: it holds the state
  optLevel_ = tier.optLevel;
  std::lock_guard<std::mutex> lock(cppMutex_);
  ruleCode_ = {code_};  // all the productions are in it
  return true;
}

// What declarations typed at the REPL follow, whatever section or group the model's file ended
// in: a rule typed there is a production of the main group (lpfg's default), unless the input
// names its section or group itself (`interpretation:`, `group 2:`).
static const std::string kReplSection = "\nendgroup\nendvgroup\nproduction:\n";

// The input followed by `closing`, generated code that ends what the input is put in. On a line
// of its own, so that nothing at the end of the input takes it in (a `//` comment, an
// unterminated literal), but numbered as the input's last line and indented to stand just after
// it: an error about the input ending too soon ("expected expression") points just after what was
// typed, and no error points at a line or a bracket the user did not type.
static std::string withClosing(const std::string& input, const std::string& closing) {
  size_t lastLine = input.rfind('\n');
  size_t column = lastLine == std::string::npos ? input.size() : input.size() - lastLine - 1;
  long line = 1 + std::count(input.begin(), input.end(), '\n');
  return input + "\n#line " + std::to_string(line) + " \"<repl>\"\n" + std::string(column, ' ') + closing;
}

// C++ at the REPL. The input is compiled as the last part of the model: the .l file (included,
// so its macros, modules and functions are there), the declarations typed so far, then the input
// as a declaration (file scope), as statements, or as an expression whose value is printed (in a
// function run once). That unit shares every global with the running code, so statements change
// the model's state. A declaration's unit becomes the running code: new productions take part in
// the next step and new globals live there.

llvm::Expected<std::string> Session::evaluate(const std::string& input) {
  if (!engine_) return llvm::createStringError("error: no model is loaded");
  std::string text = input;
  while (!text.empty() && std::isspace((unsigned char)text.back())) text.pop_back();
  size_t start = text.find_first_not_of(" \t\r\n");
  if (start == std::string::npos) return std::string();
  enum class Form { Expression, Statements, Declarations };
  char last = text.back();
  const bool ended = last == ';' || last == '}';
  // Without its ';', a declaration (`int count = 0`) is one still, as at cling's prompt: tried
  // before the statements, which would take it as a local variable, dropped when they return.
  std::vector<Form> tries = ended ? std::vector{Form::Declarations, Form::Statements}
                                  : std::vector{Form::Expression, Form::Declarations, Form::Statements};
  std::vector<std::string> errors;
  for (Form form : tries) {
    int n = ++replInputs_;
    std::string entry = "__lc_repl_input_" + std::to_string(n);
    std::string declared = ended ? text : withClosing(text, ";");
    const std::string atInput = "#line 1 \"<repl>\"\n";
    std::string wrapped;
    switch (form) {
      case Form::Declarations: wrapped = kReplSection + atInput + declared + "\n"; break;
      case Form::Statements: wrapped = "extern \"C\" void " + entry + "() {\n" + atInput + text + "\n;}\n"; break;
      case Form::Expression:
        wrapped = "extern \"C\" void " + entry + "() { __lc_repl::print([&]() -> decltype(auto) { return (\n" + atInput +
                  withClosing(text, " ); }); }") + "\n";
        break;
    }
    std::string source = "#include \"" + lsystem_ + "\"\n";
    for (const std::string& d : replDeclarations_) source += kReplSection + atInput + d + "\n";
    source += wrapped;

    frontend::PreprocessOptions pp = preprocess_;
    pp.mainText = source;
    std::string unitName = (std::filesystem::path(lsystem_).parent_path() / "<repl>").string();
    auto preprocessed = frontend::preprocess(unitName, pp);
    if (!preprocessed) {
      errors.push_back(llvm::toString(preprocessed.takeError()));
      continue;
    }
    // The running model's language, which its load checked.
    auto cpp = lsystemLanguage(nullptr, lsystem_).rewrite(*preprocessed, unitName, run_);
    auto columns = std::make_shared<frontend::OriginalColumns>(std::move(*preprocessed));
    if (!cpp) {
      errors.push_back(columns->diagnostics(llvm::toString(cpp.takeError())));
      continue;
    }
    jit::CompileOptions co;
    co.optLevel = 0;
    co.bufferName = "<repl>";
    // Once its static initializers have begun (a global typed here), the input has run as this
    // form: a fault or an interrupt there is its outcome, and no other form runs it again.
    // (Shared: the unit keeps runModelCode for its static destructors.)
    auto ran = std::make_shared<bool>(false);
    co.runModelCode = [ran, statics = guardedStatics("<repl>", columns)](const std::function<llvm::Error()>& run) {
      *ran = true;
      return statics(run);
    };
    co.checkStaticData = staticDataCheck("<repl>");
    for (const auto& owner : stateOwners_) co.shareStateWith.push_back(owner.get());
    for (const auto& source : sourceCode_) co.linkAgainst.push_back(source.get());
    auto code = compiler_->compile(cpp->cpp, co);
    if (!code) {
      errors.push_back(columns->diagnostics(llvm::toString(code.takeError())));
      if (*ran) return llvm::createStringError(errors.back());
      continue;
    }
    std::shared_ptr<jit::ModelCode> unit = std::move(*code);
    if (form == Form::Declarations) {
      auto entryPoint = unit->lookup(frontend::kModelEntry);
      if (!entryPoint) return entryPoint.takeError();
      const __lc_Model* model = reinterpret_cast<const __lc_Model* (*)()>(*entryPoint)();
      engine_->swapModel(*model);
      model_ = model;
      code_ = unit;
      stateOwners_.push_back(unit);
      replDeclarations_.push_back(declared);
      runningCpp_ = cpp->cpp;  // a better tier now compiles the model with them
      bufferName_ = co.bufferName;
      ++generation_;
      return std::string();
    }
    auto fn = unit->lookup(entry);
    if (!fn) return fn.takeError();
    runtime::takeReplOutput();
    auto run = reinterpret_cast<void (*)()>(*fn);
    runtime::Fault fault = engine_->runModelCode([&] { run(); });  // model code too: Ctrl-C stops it
    std::string printed = runtime::takeReplOutput();
    if (fault) return llvm::createStringError("<repl>: error: " + fault.what);
    return printed;
  }
  // The form the input looks most like decides which diagnostics are shown: a definition that
  // is no statement (a function, a production) gets the declaration's.
  const std::string& shown = tries[0] == Form::Declarations && errors.size() == 2 &&
                                     errors[1].find("not allowed here") == std::string::npos
                                 ? errors[1]
                                 : errors[0];  // unended input: the expression's
  return llvm::createStringError(shown);
}

llvm::Error Session::setTimeline(const std::string& name, float start, float end) {
  if (!functions_ || !functions_->setTimeline(name, start, end))
    return llvm::createStringError("error: no .tset timeline '" + name + "'");
  return llvm::Error::success();
}

llvm::Error Session::setParameter(const std::string& name, float value) {
  if (!functions_ || !functions_->setParameter(name, value)) return llvm::createStringError("error: no .vset parameter '" + name + "'");
  return llvm::Error::success();
}

}  // namespace lcjit::app
