// The interactive mode (see Interactive.h). The derivation and interpretation run on a worker
// thread, so the window keeps redrawing (and rotating) while a model derives; the window shows
// each picture the worker finishes. While the worker runs, the model is the worker's: menu items
// that would touch it wait (they are greyed out).
#include "app/window/Interactive.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <future>
#include <optional>
#include <thread>

#include "app/common/Background.h"
#include "app/window/Editors.h"
#include "runtime/turtle/Drawing.h"
#include "runtime/Engine.h"
#include "app/common/Frame.h"
#include "app/common/FrameSequence.h"
#include "app/window/Parameters.h"
#include "app/common/ProfileReport.h"
#include "app/common/Progress.h"
#include "app/window/StringDebugger.h"
#include "app/common/PlainErrors.h"
#include "jit/Elapsed.h"
#include "runtime/WindowInput.h"
#include "viewer/Window.h"
#include "runtime/turtle/Camera.h"
#include "runtime/include/lcjit/modules.h"
#include "runtime/files/AnimationFile.h"
#include "runtime/files/ReplacingFile.h"
#include "runtime/files/TextLines.h"

namespace lcjit::app {
namespace {

using jit::Clock;

class InteractiveModel {
 public:
  InteractiveModel(Session& session, const ModelFiles& files, viewer::Window& window, const InteractiveOptions& o)
      : session_(session), files_(files), window_(window), options_(o) {
    // OutputFrame's files are written once their step is over (NamedFrames), on the worker.
    hooks_.outputFrame = [this](const char* path) { named_.name(path); };
    if (o.quiet) hooks_.print = [](const char*) {};
    // How far the worker has come, for the window's status line (poll); the module count may walk
    // the string, so it is taken (with its step) at most twice a second.
    hooks_.afterStep = [this, debug = o.debug](int step) {
      writeNamedFrames();
      if (debug || jit::msSince(progressCountedAt_) >= 500) {  // the step and its count, together
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
  }
  ~InteractiveModel() {
    if (work_.valid()) work_.wait();
    stopRecording();
  }

  bool busy() const { return work_.valid(); }

  // Derives the whole model (not animating) and shows it.
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

  // Called every frame: shows the worker's picture once it is ready, and keeps an animation going.
  void poll() {
    if (Action edit = editors_.takeAction(); edit != Action::None) apply(edit);  // waits while busy
    if (work_.valid() && work_.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
      Scene scene = work_.get();
      session_.engine().clearCancel();
      bool replaced = std::exchange(replacing_, false);
      if (!scene.error.empty() && replaced) {
        if (options_.verbose) std::fprintf(stderr, "lcjit: the running derivation stopped for the new version\n");
        return swapInWhenReady();
      }
      if (!scene.error.empty()) {
        // A fault in model code (docs/faults.md): said on stderr; the last picture stays.
        std::fprintf(stderr, "%s\n", scene.error.c_str());
        running_ = false;
        return;
      }
      shown_ = std::move(scene.main);
      if (const runtime::Profile* p = session_.engine().profile())
        profileRows_ = profileRows(*p, session_.engine().model());
      const runtime::DrawingFiles& d = session_.drawing();
      const RenderLook& look = look_.of(d);
      // Animation frames keep the first frame's framing unless the .a file says otherwise (§8.1).
      using Framing = viewer::Window::Framing;
      Framing framing = !animating_ || refit_ || animation_.scaleBetweenFrames ? Framing::Refit
                        : animation_.hcenterBetweenFrames                       ? Framing::HCenter
                                                                                : Framing::Keep;
      refit_ = false;
      if (animating_ && animation_.newViewBetweenFrames) window_.resetView();
      if (scene.panes.empty()) window_.setScene(shown_, d.view, look.palette, look.textures, framing);
      else window_.setViews(scene.panes, d.view, look.palette, look.textures);
      if (recordingWanted_) record();
      writePendingSaves();
      insertPending();  // against the picture just shown
      shownAt_ = Clock::now();
    }
    swapInWhenReady();
    showProgress();
    if (!busy()) applyPanelEdits();
    if (!busy()) {
      // RunSimulation/PauseSimulation from model code (§6.5; in animate mode only), also those
      // made outside a derivation step (Start, End).
      runtime::AnimationRequests r = session_.windowInput().animation.take();
      if (r.run) runRequested_ = true;
      if (r.pause) pauseRequested_ = true;
      if (runRequested_.exchange(false) && animating_) startRunning(runtime::AnimationSchedule::Mode::Run);
      if (pauseRequested_.exchange(false)) running_ = false;
    }
    if (running_ && !busy() && Clock::now() - shownAt_ >= std::chrono::milliseconds(animation_.swapIntervalMs()))
      advance(mode_);
  }

  // A derivation that has run half a second says how far it is in the window's status line.
  void showProgress() {
    if (!busy()) {
      if (statusShown_) window_.setStatus(""), statusShown_ = false;
      return;
    }
    if (jit::msSince(launchedAt_) < 500) return;
    window_.setStatus(progressStep_ < 0 ? "deriving..." : progressText(progressStep_, progressLength_, progressModules_));
    statusShown_ = true;
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
    if (!animating_) return run();
    int at = session_.engine().stepNo();
    launch([this, at] {
      session_.engine().begin(hooks_);
      deriveTo(at);
    });
  }
  void forgetUnsavedParameters() { parameters_.forgetUnsaved(); }

  void syncProfiling() {
    const bool wanted = window_.panelOpen(kProfileTitle);
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
  static constexpr const char* kProfileTitle = "Profile";
  viewer::Panel profilePanel() {
    if (!busy()) syncProfiling();
    viewer::Panel p;
    p.title = kProfileTitle;
    p.columns = {"rule", "where", "applied", "ms", "last step"};
    constexpr size_t kShown = 40;
    for (size_t i = 0; i < profileRows_.size() && i < kShown; ++i) {
      const ProfileRow& r = profileRows_[i];
      char ms[32], last[48];
      std::snprintf(ms, sizeof ms, "%.3f", r.ms);
      std::snprintf(last, sizeof last, "%llu (%.3f ms)", (unsigned long long)r.appliedLastStep, r.msLastStep);
      // "p A(n) < B": the kind's initial and the predecessor, cut short (the where column finds it).
      std::string rule = r.kind.substr(0, 1) + " " + r.rule;
      if (rule.size() > 34) rule = rule.substr(0, 31) + "...";
      p.rows.push_back({rule, r.where, std::to_string(r.applied), ms, last});
    }
    p.status = profileRows_.empty() ? "counting from the next run" : std::to_string(profileRows_.size()) + " rules ran";
    if (profileRows_.size() > kShown) p.status += " (the " + std::to_string(kShown) + " hottest shown)";
    p.buttons = {"Run again"};
    p.pressed = [this](size_t) {
      if (busy()) return;
      if (animating_) return rewind();
      run();
    };
    return p;
  }

  // ---- animate mode (§1.2.3)

  void enterAnimate() {
    readAnimationFile();
    animating_ = true;
    rewind();
  }
  void rewind() {
    running_ = false;
    refit_ = true;  // the first frame sets the animation's framing
    launch([this] {
      session_.engine().begin(hooks_);
      schedule_.emplace(animation_, session_.engine().derivationLength());
      deriveTo(schedule_->rewind());
    });
  }
  void advance(runtime::AnimationSchedule::Mode mode) {
    if (!schedule_) return;
    std::optional<int> next;
    if (animation_.displayOnRequest) {
      // The model says which frames to show (DisplayFrame): derive towards the last frame and
      // stop at the next request (deriveTo); Forever starts over after the last.
      int at = session_.engine().stepNo();
      if (at < schedule_->lastFrame()) next = schedule_->lastFrame();
      else if (mode == runtime::AnimationSchedule::Mode::Forever) next = schedule_->rewind();
    } else {
      next = schedule_->next(mode);
    }
    if (!next) {
      running_ = false;
      return;
    }
    int target = *next;
    launch([this, target] {
      if (target < session_.engine().stepNo()) session_.engine().begin(hooks_);  // Forever wrapped
      deriveTo(target);
    });
  }
  void startRunning(runtime::AnimationSchedule::Mode mode) {
    running_ = true;
    mode_ = mode;
  }
  void leaveAnimate() {
    running_ = false;
    stopRecording();
    animating_ = false;
    schedule_.reset();
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
      r.ms = jit::msSince(t0);
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
          running_ = false;
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
    ++installs_;
    parameters_.load(files_, session_.functions());
    window_.setMessage("");
    if (options_.verbose && recompiled)
      std::fprintf(stderr, "lcjit: reloaded %s in %.1f ms: preprocessed in %.1f ms, rewritten in %.1f ms, %s in %.1f ms\n",
                   files_.lsystem.c_str(), p.ms, p.times.preprocessMs, p.times.rewriteMs,
                   p.times.objectCached ? "code from the cache" : "compiled", p.times.compileMs);
    if (recompiled) startBetterTier();
    if (p.resetView) window_.resetView();
    refit_ = true;
    if (!p.rerun) return launch([] {});  // New view / New rendering: the same string, drawn anew
    if (animating_) return rewind();
    run();
  }

  // A change under -rmode continuous/triggered runs the §1.3 table's action.
  // The menu's New … items are the same actions.
  // While the worker has the model, a change that recompiles starts compiling at once (and
  // replaces the running version when ready, swapInWhenReady); the others wait for it.
  void apply(Action a) {
    if (a == Action::NewAnimate) return readAnimationFile();
    std::optional<ReloadParts> parts = reloadPartsFor(a);
    if (!parts) return;
    if (busy() && !parts->lsystem) {
      if (std::find(deferred_.begin(), deferred_.end(), a) == deferred_.end()) deferred_.push_back(a);
      return;
    }
    reload(*parts, rerunsSimulation(a), resetsView(a));
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

  // The menu as it stands: items that need the model are greyed out while the worker has it.
  viewer::MenuActions actions() {
    using Mode = runtime::AnimationSchedule::Mode;
    viewer::MenuActions a;
    a.saveName = stem() + ".png";
    a.exit = [this] { exit_ = true; };
    a.animating = animating_;
    a.stop = [this] {
      running_ = false;
      if (busy()) session_.engine().cancelStep();  // a long step in progress stops too
    };
    a.interrupt = [this] {
      running_ = false;
      if (busy()) session_.engine().interrupt();  // Esc: model code stuck in a loop too
    };
    a.clear = [this] {
      if (!busy()) launch([] {});
    };
    a.newAnimate = [this] { readAnimationFile(); };
    a.startRecording = [this] { recordingWanted_ = true; };
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
    if (busy()) return a;
    a.newModel = [this] { apply(Action::NewModel); };
    a.newLsystem = [this] { apply(Action::NewLsystem); };
    a.newRun = [this] { apply(Action::NewRun); };
    a.newView = [this] { apply(Action::NewView); };
    a.newRendering = [this] { apply(Action::NewRendering); };
    a.stringOutput = [this] { report(session_.engine().writeBinary(stem() + ".strb")); };
    a.stringInput = [this] {
      if (auto e = session_.engine().readBinary(stem() + ".strb")) return report(std::move(e));
      launch([] {});
    };
    a.animate = [this] { enterAnimate(); };
    a.step = [this] { advance(Mode::Step); };
    a.run = [this] { startRunning(Mode::Run); };
    a.forever = [this] { startRunning(Mode::Forever); };
    a.rewind = [this] { rewind(); };
    a.dontAnimate = [this] {
      leaveAnimate();
      run();
    };
    return a;
  }
  bool exitRequested() const { return exit_; }
  // How many loads were installed: what the file monitor must look at may have changed.
  int installs() const { return installs_; }

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
    return runtime::writeWholeFile(path, runtime::viewLine(v));
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

 private:
  // Runs `work` on the worker thread, then interprets the string there; poll() shows it.
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
      if (auto e = session_.engine().interpret(scene.main)) {
        scene.error = llvm::toString(std::move(e));
        return scene;
      }
      // Multi-view (§7.3): every view the model opened with UseView, drawn by its view group in
      // its `window:` rectangle.
      runtime::Bounds b = scene.main.framingBounds();
      if (!b.empty()) session_.windowInput().views.setBox(0, b.min, b.max);
      auto panes = interpretViews(session_.engine(), session_.drawing().view);
      if (!panes) {
        scene.error = llvm::toString(panes.takeError());
        return scene;
      }
      scene.panes = std::move(*panes);
      return scene;
    });
  }

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

  // Start recording: every frame shown from then on, to --record's video or numbered files, by
  // default lpfg's numbered pictures (MODELNNNN.png, lpfg's Save format) in the .a file's frame
  // dump folder. The numbers are the .a file's (frame count or step), from 0.
  void record() {
    if (!recording_) {
      std::string out = options_.record;
      if (out.empty()) out = (std::filesystem::path(animation_.frameDumpPath) / (stem() + "%04d.png")).string();
      auto opened = FrameSequence::open(out, options_.fps);
      if (!opened) {
        report(opened.takeError());
        recordingWanted_ = false;
        return;
      }
      recording_ = std::move(*opened);
    }
    int number = animation_.frameNumbers == runtime::AnimationSettings::FrameNumbers::StepNo ? session_.engine().stepNo()
                                                                                            : recorded_;
    FrameSource source;
    source.writeFile = [this](const std::string& path) { return window_.saveImage(path); };
    source.picture = [this] { return window_.grabImage(); };
    if (auto e = recording_->add(number, source)) {
      report(std::move(e));
      stopRecording();  // a video keeps the frames it got
      return;
    }
    ++recorded_;
  }
  // Leaving animate mode or closing the window ends a recording: a video is finished then.
  void stopRecording() {
    recordingWanted_ = false;
    if (recording_) report(recording_->finish());
    recording_.reset();
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
  bool statusShown_ = false;
  // What the worker hands the window: the main view's geometry and, with UseView, the panes.
  struct Scene {
    runtime::Geometry main;
    std::vector<viewer::ViewPane> panes;
    std::string error;  // a fault: nothing to show
  };
  std::future<Scene> work_;
  runtime::Geometry shown_;  // what the window shows, with its source modules
  bool exit_ = false;

  std::string animationFile_;
  runtime::AnimationSettings animation_;
  std::optional<runtime::AnimationSchedule> schedule_;
  bool animating_ = false, running_ = false;
  bool recordingWanted_ = false;                // Start recording was chosen (and not ended)
  std::unique_ptr<FrameSequence> recording_;    // where they go, opened at the first frame
  bool refit_ = false;  // the next picture frames itself (first frame, reloads)
  std::atomic<bool> runRequested_{false}, pauseRequested_{false};  // set on the worker thread
  runtime::AnimationSchedule::Mode mode_ = runtime::AnimationSchedule::Mode::Run;
  Clock::time_point shownAt_;
  int recorded_ = 0;
  int installs_ = 0;
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

int runInteractive(Session& session, const ModelFiles& files, const viewer::WindowOptions& windowOptions,
                   const InteractiveOptions& options) {
  auto window = viewer::Window::create(windowOptions);
  if (!window) {
    std::fprintf(stderr, "lcjit: cannot open a window: %s\n", llvm::toString(window.takeError()).c_str());
    return 1;
  }
  for (const std::string& title : options.panels) (*window)->showPanel(title, true);
  InteractiveModel model(session, files, **window, options);
  if (options.animate) model.enterAnimate();
  else model.run();
  model.startBetterTier();
  FileMonitor monitor;
  // Refresh mode > Triggered/Continuous turns monitoring on as the command line's mode would
  // (continuous when it said explicit); Explicit turns it off (lpfg's View::SetContinuousMode).
  RefreshMode refresh = options.refresh;
  bool watching = refresh != RefreshMode::Explicit;
  std::vector<std::string> watched = watchedFiles(files, session.drawing());
  int watchedAfter = model.installs();
  if (watching && !monitor.watch(watched) && !options.quiet)
    std::fprintf(stderr, "lcjit: file monitoring: %s\n", monitor.error().c_str());
  for (;;) {
    model.poll();
    model.feedMouse();
    model.feedCamera();
    viewer::MenuActions actions = model.actions();
    actions.monitoring = watching;
    actions.setRefreshMode = [&](bool on) {
      if (on == watching) return;
      watching = on;
      if (!on) return monitor.clear();
      if (refresh == RefreshMode::Explicit) refresh = RefreshMode::Continuous;
      watched = watchedFiles(files, session.drawing());
      if (!monitor.watch(watched) && !options.quiet)
        std::fprintf(stderr, "lcjit: file monitoring: %s\n", monitor.error().c_str());
    };
    if (model.exitRequested() || !(*window)->frame(actions)) break;
    // Redraw on input; while the worker runs, look for its picture often; files a few times a second.
    (*window)->waitEvents(model.busy() ? 0.01 : 0.1);
    if (watching) {
      std::vector<std::string> changed = monitor.poll(0);
      for (const std::string& f : changed)
        if (fileKindOf(f) == FileKind::Parameters || fileKindOf(f) == FileKind::Timeline) model.forgetUnsavedParameters();
      for (Action a : actionsForChanges(changed, refresh)) model.apply(a);
    }
    model.applyDeferred();
    if (watching && !model.busy()) {
      // A reload may have named other files (the view file's surfaces, meshes, textures).
      if (model.installs() != watchedAfter) {
        watchedAfter = model.installs();
        if (std::vector<std::string> now = watchedFiles(files, session.drawing()); now != watched) {
          watched = std::move(now);
          if (!monitor.watch(watched) && !options.quiet)
            std::fprintf(stderr, "lcjit: file monitoring: %s\n", monitor.error().c_str());
        }
      }
    }
  }
  return 0;
}

}  // namespace lcjit::app
