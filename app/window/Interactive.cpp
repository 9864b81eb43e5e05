// The interactive mode (see Interactive.h): the model host (ModelHost.h) of the session in this
// process, which the window's controller (WindowController.h) drives. The derivation and
// interpretation run on a worker thread, so the window keeps redrawing (and rotating) while a
// model derives; the window shows each picture the worker finishes. While the worker runs, the
// model is the worker's: menu items that would touch it wait (they are greyed out).
#include "app/window/Interactive.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <future>
#include <optional>
#include <thread>

#include "app/common/Background.h"
#include "app/window/Editors.h"
#include "runtime/turtle/Drawing.h"
#include "runtime/Engine.h"
#include "app/common/Frame.h"
#include "app/window/ModelHost.h"
#include "app/window/Parameters.h"
#include "app/window/ProfilePanel.h"
#include "app/common/ProfileReport.h"
#include "app/common/Progress.h"
#include "app/window/StringDebugger.h"
#include "app/window/WindowController.h"
#include "app/common/PlainErrors.h"
#include "support/Elapsed.h"
#include "runtime/WindowInput.h"
#include "viewer/Window.h"
#include "runtime/turtle/Camera.h"
#include "runtime/include/lcjit/modules.h"
#include "runtime/files/AnimationFile.h"
#include "support/ReplacingFile.h"

namespace lcjit::app {
namespace {

using support::Clock;

class SessionHost final : public ModelHost {
 public:
  SessionHost(Session& session, const ModelFiles& files, viewer::Window& window, const InteractiveOptions& o)
      : session_(session), files_(files), window_(window), options_(o) {
    // OutputFrame's files are written once their step is over (NamedFrames), on the worker.
    hooks_.outputFrame = [this](const char* path) { named_.name(path); };
    if (o.quiet) hooks_.print = [](const char*) {};
    // How far the worker has come, for the window's status line (progress); the module count may
    // walk the string, so it is taken (with its step) at most twice a second.
    hooks_.afterStep = [this, debug = o.debug](int step) {
      writeNamedFrames();
      if (debug || support::msSince(progressCountedAt_) >= 500) {  // the step and its count, together
        progressCountedAt_ = Clock::now();
        progressModules_ = session_.engine().moduleCount();
        progressLength_ = session_.engine().derivationLength();
        progressStep_ = step;
      }
      if (!debug) return;
      std::printf("lcjit: step %d: %zu modules\n", step, size_t(progressModules_));
      std::fflush(stdout);
    };
    for (const std::string& f : files.other)
      if (fileKindOf(f) == FileKind::Animation) animationFile_ = f;
    parameters_.load(files_, session_.functions());
    startBetterTier();
  }
  ~SessionHost() override {
    if (work_.valid()) work_.wait();
  }

  // ---- runs

  void derive(RunTarget target) override {
    switch (target.kind) {
      case RunTarget::Kind::Whole: return run();
      case RunTarget::Kind::FirstFrame:
        return launch([this] {
          runtime::Engine& e = session_.engine();
          e.begin(hooks_);
          deriveTo(runtime::AnimationSchedule(animation_, e.derivationLength()).firstFrame());
        });
      case RunTarget::Kind::Step:
        return launch([this, target] {
          runtime::Engine& e = session_.engine();
          if (target.fromAxiom || target.step < e.stepNo() || e.ended()) e.begin(hooks_);
          deriveTo(target.step);
        });
    }
  }
  void redraw() override { launch([] {}); }  // the same string, interpreted again
  bool busy() const override { return work_.valid(); }
  bool itemsWaitWhileBusy() const override { return true; }
  void stop() override {
    if (busy()) session_.engine().cancelStep();
  }
  void interrupt() override {
    if (busy()) session_.engine().interrupt();
  }

  // Shows the worker's picture once it is ready (waiting up to `waitMs` for it), installs a
  // finished recompile, applies the panels' edits.
  HostNews poll(int waitMs) override {
    applyDeferred();
    if (Action edit = editors_.takeAction(); edit != Action::None) apply(edit);  // waits while busy
    if (work_.valid() && work_.wait_for(std::chrono::milliseconds(waitMs)) == std::future_status::ready) {
      Scene scene = work_.get();
      session_.engine().clearCancel();
      bool replaced = std::exchange(replacing_, false);
      if (!scene.error.empty() && replaced) {
        if (options_.verbose) std::fprintf(stderr, "lcjit: the running derivation stopped for the new version\n");
      } else if (!scene.error.empty()) {
        // A fault in model code (docs/faults.md): said on stderr; the last picture stays.
        std::fprintf(stderr, "%s\n", scene.error.c_str());
        news_.run.emplace().failed = true;
      } else {
        shownPicture(std::move(scene));
      }
    }
    swapInWhenReady();
    if (!busy()) applyPanelEdits();
    if (!busy()) {
      // RunSimulation/PauseSimulation from model code (§6.5; in animate mode only), also those
      // made outside a derivation step (Start, End).
      runtime::AnimationRequests r = session_.windowInput().animation.take();
      if (runRequested_.exchange(false) || r.run) news_.runAnimation = true;
      if (pauseRequested_.exchange(false) || r.pause) news_.pauseAnimation = true;
    }
    return std::exchange(news_, {});
  }

  // What waited for the worker's picture, now that the window shows it.
  void shown() override {
    writePendingSaves();
    insertPending();  // against the picture just shown
  }

  // A derivation that has run half a second says how far it is.
  std::string progress() const override {
    if (support::msSince(launchedAt_) < 500) return "";
    return progressStep_ < 0 ? "deriving..." : progressText(progressStep_, progressLength_, progressModules_);
  }

  // ---- files

  // A change under -rmode continuous/triggered runs the §1.3 table's action.
  // The menu's New … items are the same actions.
  // While the worker has the model, a change that recompiles starts compiling at once (and
  // replaces the running version when ready, swapInWhenReady); the others wait for it.
  void apply(Action a) override {
    if (a == Action::NewAnimate) return readAnimationFile();
    std::optional<ReloadParts> parts = reloadPartsFor(a);
    if (!parts) return;
    if (busy() && !parts->lsystem) {
      if (std::find(deferred_.begin(), deferred_.end(), a) == deferred_.end()) deferred_.push_back(a);
      return;
    }
    reload(*parts, rerunsSimulation(a), resetsView(a));
  }
  // The .vset changed on disk: its values win over those moved in the panel and not saved.
  void filesChanged(const std::vector<std::string>& changed) override {
    for (const std::string& f : changed)
      if (fileKindOf(f) == FileKind::Parameters || fileKindOf(f) == FileKind::Timeline) parameters_.forgetUnsaved();
  }
  std::vector<std::string> watchedFiles() const override { return app::watchedFiles(files_, session_.drawing()); }

  // ---- the window's input and menu

  void takeInput() override {
    feedMouse();
    feedCamera();
  }

  void addToMenu(viewer::MenuActions& a) override {
    a.newAnimate = [this] { readAnimationFile(); };
    // Save as… a model format while the worker has the model: written from the picture it
    // brings (the name typed is not lost to a greyed-out action).
    a.saveAs = [this](const std::string& path) {
      pendingSaves_.push_back(path);
      if (!busy()) writePendingSaves();
    };
    a.userMenu = session_.windowInput().menu.items();
    a.userChoice = [this](int code) { session_.windowInput().menu.choose(code); };
    if (!parameters_.empty()) a.panels.push_back(parameters_.panel());
    a.panels.push_back(profilePanel());
    a.panels.push_back(stringPanel());
    for (viewer::Panel& p : editors_.panels()) a.panels.push_back(std::move(p));
    a.namedGroups = session_.namedGroups();
    if (busy()) return;
    // A rule method (GroIMP's button): one step of its rules, from the string shown.
    a.applyGroup = [this](int group) { launch([this, group] { session_.engine().stepWith(group, hooks_); }); };
    a.stringOutput = [this] { report(session_.engine().writeBinary(stem() + ".strb")); };
    a.stringInput = [this] {
      if (auto e = session_.engine().readBinary(stem() + ".strb")) return report(std::move(e));
      launch([] {});
    };
  }
  bool records() const override { return true; }

 private:
  // What the worker hands the window: the main view's geometry and, with UseView, the panes.
  struct Scene {
    runtime::Geometry main;
    std::vector<viewer::ViewPane> panes;
    std::string error;  // a fault: nothing to show
  };

  // Derives the whole model (not animating).
  void run() {
    for (const std::string& w : session_.warnings())
      if (!options_.quiet) std::fprintf(stderr, "%s\n", w.c_str());
    launch([this] {
      runtime::Engine& e = session_.engine();
      e.begin(hooks_);
      while (e.step())
        if (e.takeBreak()) return;  // the String panel's "stop when": End waits for the rest
      e.finish();
    });
  }

  // The String panel's Step, Step back and Run: to step `target` (from the axiom when behind),
  // stopping early where its "stop when" production applies.
  void debugDeriveTo(int target) {
    launch([this, target] {
      runtime::Engine& e = session_.engine();
      if (target < e.stepNo() || e.ended()) e.begin(hooks_);
      while (e.stepNo() < target && e.step())
        if (e.takeBreak()) return;
      if (e.stepNo() >= e.derivationLength()) e.finish();
    });
  }

  // The worker's picture, for the controller to show; what waited for the worker meanwhile.
  void shownPicture(Scene scene) {
    shown_ = std::move(scene.main);
    shownPanes_ = std::move(scene.panes);
    runtime::Engine& e = session_.engine();
    if (const runtime::Profile* p = e.profile()) profileRows_ = profileRows(*p, e.ruleSources());
    const runtime::DrawingFiles& d = session_.drawing();
    const RenderLook& look = look_.of(d);
    RunEnd& r = news_.run.emplace();
    r.picture = HostPicture{&shown_, &shownPanes_, &d.view, &look.palette, &look.textures};
    r.step = e.stepNo();
    r.derivationLength = e.derivationLength();
    r.ended = e.ended() || e.stepNo() >= e.derivationLength();
    r.animation = animation_;
  }

  // The Parameters panel's edits, once the worker has let go of the model: .vset values are set
  // and the model re-runs (to the step shown, when animating); a file a panel item rewrote is
  // re-read as its change would be under -rmode cont (an included header recompiles the L-system).
  void applyPanelEdits() {
    std::map<std::string, float> values = parameters_.takeParameters();
    for (const auto& [name, value] : values) report(session_.setParameter(name, value));
    std::map<std::string, std::pair<float, float>> timelines = parameters_.takeTimelines();
    for (const auto& [name, range] : timelines) report(session_.setTimeline(name, range.first, range.second));
    std::map<std::string, float> tunables = parameters_.takeTunables();
    for (const auto& [name, value] : tunables) session_.windowInput().tunables.move(name, value);
    for (const std::string& f : parameters_.takeChangedFiles()) {
      FileKind kind = fileKindOf(f);
      Action a = kind == FileKind::Other ? Action::NewLsystem : actionForChange(kind, RefreshMode::Continuous);
      if (a != Action::None) apply(a);
    }
    if ((values.empty() && timelines.empty() && tunables.empty()) || busy()) return;
    news_.rerunShown = true;
  }

  void syncProfiling() {
    const bool wanted = window_.panelOpen(kProfilePanelTitle);
    if (wanted == (session_.engine().profile() != nullptr)) return;
    session_.engine().setProfiling(wanted);
    profileRows_.clear();
  }

  // The String panel (StringDebugger.h); provenance is tracked while it is open.
  viewer::Panel stringPanel() {
    if (!window_.panelOpen(StringDebugger::kTitle)) {
      if (!busy()) session_.engine().setProvenance(false);
      viewer::Panel closed;
      closed.title = StringDebugger::kTitle;
      return closed;
    }
    return debugger_.panel(session_.engine(), busy(), {[this](int step) { debugDeriveTo(step); }});
  }

  // The Profile panel: the rules by time, from the last picture's run. Counting is on while the
  // panel is open (it costs two clock readings per rule body); opening it counts from the next run.
  viewer::Panel profilePanel() {
    if (!busy()) syncProfiling();
    // Run again: the whole derivation, or the animation from its first frame.
    return app::profilePanel(profileRows_, ProfiledRules::LSystem, "", [this] {
      if (!busy()) news_.rerun = true;
    });
  }

  // ---- the New … items (§1.2.2): re-read `what`, then re-run or only redraw.
  // A recompile (New model, New L-system, an edited .l file) runs on another thread while the
  // running model goes on deriving and drawing; poll() swaps the new one in when it is ready.
  void reload(ReloadParts what, bool rerun, bool resetView) {
    auto job = [this, what, rerun, resetView, files = editors_.files(files_)] {
      Prepared r;
      r.rerun = rerun;
      r.resetView = resetView;
      auto t0 = Clock::now();
      auto p = session_.prepare(files, options_.optLevel, r.times, what);
      if (p) r.model = std::move(*p);
      else r.error = llvm::toString(p.takeError());
      r.ms = support::msSince(t0);
      return r;
    };
    if (what.lsystem) return compile_.start(job);
    if (busy()) return;  // the worker has the model (the menu greys these items meanwhile)
    installPrepared(job());
  }

  void startBetterTier() {
    if (options_.betterTier > session_.optLevel()) tier_.start(session_.betterTierJob(options_.betterTier));
  }

  // poll(): a finished recompile or better tier replaces the running model between pictures.
  void swapInWhenReady() {
    if (busy()) {
      // A saved version compiled while the worker still runs the old one (a long derivation,
      // or model code stuck in a loop): stop it, as Esc does, and install the new one once
      // the worker has let go. A failed compile only shows its diagnostics.
      if (!waiting_) {
        if (std::optional<Prepared> p = compile_.take()) {
          if (!p->model) return installPrepared(std::move(*p));
          waiting_ = std::move(*p);
          replacing_ = true;
          news_.pauseAnimation = true;  // an animation stops, as with Esc
        }
      }
      // Again at every poll: it stops model code only while some is running.
      if (waiting_) session_.engine().interrupt();
      return;
    }
    if (waiting_) {
      Prepared p = std::move(*waiting_);
      waiting_.reset();
      installPrepared(std::move(p));
    }
    if (std::optional<Prepared> p = compile_.take()) installPrepared(std::move(*p));
    if (std::optional<BetterTier> t = tier_.take()) {
      if (!t->error.empty()) {
        report(t->error);  // the quick tier goes on running
      } else {
        double ms = t->compileMs;
        if (session_.installTier(std::move(*t)) && options_.verbose)
          std::fprintf(stderr, "lcjit: -O%d code swapped in (%.1f ms in the background)\n", session_.optLevel(), ms);
      }
    }
  }

  struct Prepared {
    std::optional<PreparedModel> model;
    std::string error;
    PhaseTimes times;
    double ms = 0;
    bool rerun = false, resetView = false;
  };

  void installPrepared(Prepared p) {
    if (!p.model) {
      // The last good model stays on screen, with the diagnostics over it.
      std::string shown = withSourceLines(p.error);
      if (options_.plainErrors) shown = inPlainLanguage(shown);
      report(shown);
      window_.setMessage(shown + "\n(the last good model is shown; save a fix to reload)");
      return;
    }
    bool recompiled = p.model->what.lsystem;
    if (auto e = session_.install(std::move(*p.model))) report(std::move(e));  // the model's constructors threw
    parameters_.load(files_, session_.functions());
    window_.setMessage("");
    if (options_.verbose && recompiled)
      std::fprintf(stderr, "lcjit: reloaded %s in %.1f ms: preprocessed in %.1f ms, rewritten in %.1f ms, %s in %.1f ms\n",
                   files_.lsystem.c_str(), p.ms, p.times.preprocessMs, p.times.rewriteMs,
                   p.times.objectCached ? "code from the cache" : "compiled", p.times.compileMs);
    if (recompiled) startBetterTier();
    news_.resetView = news_.resetView || p.resetView;
    // Re-run, or (New view / New rendering) the same string drawn anew.
    (p.rerun ? news_.rerun : news_.redraw) = true;
  }

  void writeNamedFrames() {
    if (!named_.empty()) report(named_.writeAll(frames_, session_.engine(), session_.drawing()));
  }
  void writePendingSaves() {
    for (const std::string& path : std::exchange(pendingSaves_, {})) {
      if (fileKindOf(path) == FileKind::View) report(saveViewParameters(path));
      else report(frames_.write(path, session_.engine(), session_.drawing()));
    }
  }
  void applyDeferred() {
    if (!busy()) writePendingSaves();
    if (busy() || deferred_.empty()) return;
    std::vector<Action> now = std::move(deferred_);
    deferred_.clear();
    for (Action a : now) apply(a);
  }

  // Save as… "view parameters" (a .v name): the window's current view as a `view:` line that a
  // view file reads back (direction, up, pan from the box centre, scale with the zoom).
  llvm::Error saveViewParameters(const std::string& path) {
    const runtime::CameraMatrices& c = window_.camera();
    runtime::ViewDefinition v;
    v.dir = V3f(c.viewDirection.x, c.viewDirection.y, c.viewDirection.z);
    v.up = V3f(c.up.x, c.up.y, c.up.z);
    V3f centre = c.bounds.empty() ? V3f() : c.bounds.center();
    v.pan = V3f(c.lookAt.x, c.lookAt.y, c.lookAt.z) - centre;
    v.scale = session_.drawing().view.scale * window_.adjustment().zoom;
    return support::writeWholeFile(path, runtime::viewLine(v));
  }

  // The window's camera for GetCameraPosition() and vvScale() (§6.4), view 0.
  void feedCamera() {
    const runtime::CameraMatrices& c = window_.camera();
    auto v3 = [](glm::vec3 v) { return V3f(v.x, v.y, v.z); };
    const float scale = window_.adjustment().zoom / runtime::projectionScale(session_.drawing().view, 0);
    session_.windowInput().views.setCamera(0, runtime::cameraPosition(v3(c.eye), v3(c.lookAt), v3(c.viewDirection), v3(c.up), scale));
  }

  // The window's pointer for GetMouseStatus() (§7.4).
  void feedMouse() {
    viewer::Window::Pointer p = window_.takePointer();
    MouseStatus s{};
    s.viewX = p.x;
    s.viewY = p.y;
    s.atFront = V3d(p.front[0], p.front[1], p.front[2]);
    s.atRear = V3d(p.rear[0], p.rear[1], p.rear[2]);
    s.atMiddle = V3d(p.middle[0], p.middle[1], p.middle[2]);
    s.lbDown = p.down;
    s.lbPushed = p.pushed;
    s.lbReleased = p.released;
    session_.windowInput().mouse.update(s);
    // A Shift+Ctrl click while the worker has the string waits for it (a click is not lost).
    if (p.insert) pendingInserts_.push_back({p.insert, p.fbX, p.fbY, s});
    insertPending();
    if (p.clicked && !busy() && window_.panelOpen(StringDebugger::kTitle))
      if (std::optional<uint32_t> source = runtime::pickSource(shown_, window_.camera(), p.clickFbX, p.clickFbY))
        debugger_.select(session_.engine(), *source);
  }

  // Shift+Ctrl clicks, in order, once the worker has let go of the string (each insertion
  // re-interprets it, so the next waits again).
  struct PendingInsert {
    int kind;
    float x, y;
    MouseStatus status;
  };
  void insertPending() {
    while (!busy() && !pendingInserts_.empty()) {
      PendingInsert i = pendingInserts_.front();
      pendingInserts_.erase(pendingInserts_.begin());
      insertAtPointer(i.kind, i.x, i.y, i.status);
    }
  }
  // §5.9: MouseIns (1) or MouseInsPos(status) (2) goes into the string before the module whose
  // drawing is under the pointer; nothing when the click hits the background.
  void insertAtPointer(int kind, float x, float y, const MouseStatus& status) {
    std::optional<uint32_t> source = runtime::pickSource(shown_, window_.camera(), x, y);
    if (!source) return;
    if (kind == 1) {
      __lc_R_MouseIns r;
      std::memset(&r, 0, sizeof r);
      r.id = r.id2 = __lc_id_MouseIns;
      session_.engine().insertBefore(*source, reinterpret_cast<const char*>(&r));
    } else {
      __lc_R_MouseInsPos r;
      std::memset(&r, 0, sizeof r);
      r.id = r.id2 = __lc_id_MouseInsPos;
      r.p0 = status;
      session_.engine().insertBefore(*source, reinterpret_cast<const char*>(&r));
    }
    launch([] {});  // redraw: the geometry's sources now point behind the insertion
  }

  // Runs `work` on the worker thread, then interprets the string there; poll() hands it over.
  void launch(std::function<void()> work) {
    if (busy()) return;
    syncProfiling();
    launchedAt_ = Clock::now();
    progressStep_ = -1;  // none counted yet: the first step counts
    progressCountedAt_ = {};
    work_ = std::async(std::launch::async, [this, work = std::move(work)] {
      work();
      writeNamedFrames();  // named by Start or End
      Scene scene;
      if (auto e = session_.engine().takeFault()) {
        scene.error = llvm::toString(std::move(e));
        return scene;
      }
      scene.main.trackSources = true;  // for MouseIns picking
      if (auto e = interpretWindowPicture(session_.engine(), session_.drawing().view, scene.main, scene.panes))
        scene.error = llvm::toString(std::move(e));
      return scene;
    });
  }

  // To step `target`, stopping early at a DisplayFrame() with `display on request: on`.
  void deriveTo(int target) {
    runtime::Engine& e = session_.engine();
    while (e.stepNo() < target && e.step()) {
      runtime::AnimationRequests r = session_.windowInput().animation.take();
      if (r.run) runRequested_ = true;
      if (r.pause) pauseRequested_ = true;
      if (animation_.displayOnRequest && r.display) break;  // DisplayFrame: show this step
    }
  }

  void readAnimationFile() {
    animation_ = runtime::AnimationSettings();
    if (animationFile_.empty()) return;
    std::vector<std::string> warnings;
    animation_ = runtime::loadAnimationFile(animationFile_, warnings);
    for (const std::string& w : warnings)
      if (!options_.quiet) std::fprintf(stderr, "%s\n", w.c_str());
  }

  std::string stem() const { return std::filesystem::path(files_.lsystem).stem().string(); }

  void report(llvm::Error e) {
    if (e) report(llvm::toString(std::move(e)));
  }
  void report(const std::string& message) { std::fprintf(stderr, "%s\n", message.c_str()); }

  Session& session_;
  const ModelFiles& files_;
  viewer::Window& window_;
  InteractiveOptions options_;
  runtime::EngineHooks hooks_;
  FrameWriter frames_;
  NamedFrames named_;  // OutputFrame's, on the worker thread
  RenderLook look_;
  ParameterPanel parameters_{session_.windowInput().tunables};
  std::vector<ProfileRow> profileRows_;  // of the run the window shows
  StringDebugger debugger_;
  // Progress of the worker's derivation (set on the worker, shown by the main thread).
  std::atomic<int> progressStep_{0}, progressLength_{0};
  std::atomic<size_t> progressModules_{0};
  Clock::time_point progressCountedAt_{}, launchedAt_{};  // the first: the worker's own
  std::future<Scene> work_;
  runtime::Geometry shown_;  // what the window shows, with its source modules
  std::vector<viewer::ViewPane> shownPanes_;
  HostNews news_;  // for the next poll

  std::string animationFile_;
  runtime::AnimationSettings animation_;
  std::atomic<bool> runRequested_{false}, pauseRequested_{false};  // set on the worker thread
  std::optional<Prepared> waiting_;  // compiled while the worker ran the old version
  bool replacing_ = false;           // the worker was interrupted for waiting_
  std::vector<Action> deferred_;     // changes that wait for the worker
  std::vector<std::string> pendingSaves_;  // Save as… names that wait for the worker
  std::vector<PendingInsert> pendingInserts_;  // Shift+Ctrl clicks (MouseIns) that wait for it
  Editors editors_{files_, runtime::Palette::lcjitDefault()};  // the Panels submenu's file editors
  // Declared last: destroyed first, they wait for their jobs, which use the members above.
  Background<Prepared> compile_;
  Background<BetterTier> tier_;
};

}  // namespace

int runInteractive(Session& session, const ModelFiles& files, const viewer::WindowOptions& window,
                   const InteractiveOptions& options) {
  return runWindow(window, options, files.lsystem, [&](viewer::Window& w) -> std::unique_ptr<ModelHost> {
    return std::make_unique<SessionHost>(session, files, w, options);
  });
}

}  // namespace lcjit::app
