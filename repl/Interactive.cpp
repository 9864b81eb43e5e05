// The interactive mode (see Interactive.h).
#include "Interactive.h"

#include <cstdio>
#include <filesystem>

#include "Drawing.h"
#include "Engine.h"
#include "Frame.h"
#include "Window.h"

namespace lcjit {
namespace {

class InteractiveModel {
 public:
  InteractiveModel(Session& session, const ModelFiles& files, viewer::Window& window, const InteractiveOptions& o)
      : session_(session), files_(files), window_(window), options_(o) {
    hooks_.outputFrame = [this](const char* path) { report(frames_.write(path, session_.engine(), session_.drawing())); };
    if (o.quiet) hooks_.print = [](const char*) {};
  }

  // Derives the loaded model and shows it.
  void run() {
    for (const std::string& w : session_.warnings())
      if (!options_.quiet) std::fprintf(stderr, "%s\n", w.c_str());
    report(session_.engine().run(hooks_));
    show();
  }

  void show() {
    runtime::Geometry geometry;
    session_.engine().interpret(geometry);
    const runtime::DrawingFiles& d = session_.drawing();
    window_.setScene(geometry, d.view, viewer::RenderPalette::fromPalette(d.palette), textureImages(d));
  }

  // One of the New … menu items: re-read `what`, then re-run or only redraw.
  void reload(ReloadParts what, bool rerun, bool resetView) {
    PhaseTimes times;
    if (auto e = session_.load(files_, options_.optLevel, times, what)) {
      report(std::move(e));  // the last good model stays on screen
      return;
    }
    if (resetView) window_.resetView();
    if (rerun) run();
    else show();
  }

  // The files lpfg monitors (§1.3): every input file, and the surfaces and textures the view
  // file names.
  std::vector<std::string> inputFiles() const {
    std::vector<std::string> f{files_.lsystem};
    for (const std::string* one : {&files_.view, &files_.colormap, &files_.materials, &files_.functionSet,
                                   &files_.timeline, &files_.parameters})
      if (!one->empty()) f.push_back(*one);
    f.insert(f.end(), files_.functions.begin(), files_.functions.end());
    f.insert(f.end(), files_.contours.begin(), files_.contours.end());
    f.insert(f.end(), files_.other.begin(), files_.other.end());
    const runtime::DrawingFiles& d = session_.drawing();
    f.insert(f.end(), d.textureFiles.begin(), d.textureFiles.end());
    std::filesystem::path dir = std::filesystem::path(files_.view).parent_path();
    for (const auto& s : d.view.surfaces) f.push_back((dir / s.file).string());
    return f;
  }

  // A change under -rmode continuous/triggered runs the §1.3 table's action.
  void apply(Action a) {
    switch (a) {
      case Action::NewModel: reload(ReloadParts::all(), true, true); break;
      case Action::NewLsystem: reload(ReloadParts::newLsystem(), true, false); break;
      case Action::NewRun: reload(ReloadParts::newRun(), true, false); break;
      case Action::NewView: reload(ReloadParts::newView(), false, true); break;
      case Action::NewRendering: reload(ReloadParts::newView(), false, false); break;
      default: break;  // NewAnimate: the animation file is the animate mode's (not here yet)
    }
  }

  viewer::MenuActions actions() {
    viewer::MenuActions a;
    a.newModel = [this] { reload(ReloadParts::all(), true, true); };
    a.newLsystem = [this] { reload(ReloadParts::newLsystem(), true, false); };
    a.newRun = [this] { reload(ReloadParts::newRun(), true, false); };
    a.newView = [this] { reload(ReloadParts::newView(), false, true); };
    a.newRendering = [this] { reload(ReloadParts::newView(), false, false); };
    a.saveAs = [this](const std::string& path) { report(frames_.write(path, session_.engine(), session_.drawing())); };
    a.saveName = std::filesystem::path(files_.lsystem).stem().string() + ".png";
    a.exit = [this] { exit_ = true; };
    return a;
  }
  bool exitRequested() const { return exit_; }

 private:
  void report(llvm::Error e) {
    if (e) std::fprintf(stderr, "%s\n", llvm::toString(std::move(e)).c_str());
  }

  Session& session_;
  const ModelFiles& files_;
  viewer::Window& window_;
  InteractiveOptions options_;
  runtime::EngineHooks hooks_;
  FrameWriter frames_;
  bool exit_ = false;
};

}  // namespace

int runInteractive(Session& session, const ModelFiles& files, const viewer::WindowOptions& windowOptions,
                   const InteractiveOptions& options) {
  auto window = viewer::Window::create(windowOptions);
  if (!window) {
    std::fprintf(stderr, "lcjit: cannot open a window: %s\n", llvm::toString(window.takeError()).c_str());
    return 1;
  }
  InteractiveModel model(session, files, **window, options);
  model.run();
  viewer::MenuActions actions = model.actions();
  FileMonitor monitor;
  bool watching = options.refresh != RefreshMode::Explicit;
  if (watching && !monitor.watch(model.inputFiles()) && !options.quiet)
    std::fprintf(stderr, "lcjit: file monitoring: %s\n", monitor.error().c_str());
  while (!model.exitRequested() && (*window)->frame(actions)) {
    // Redraw on input, and look at the files a few times a second.
    (*window)->waitEvents(0.1);
    if (!watching) continue;
    for (Action a : actionsForChanges(monitor.poll(0), options.refresh)) model.apply(a);
  }
  return 0;
}

}  // namespace lcjit
