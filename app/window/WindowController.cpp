// The window over a model host (see WindowController.h). Everything here runs on the main
// thread, with GLFW: the host runs the model wherever it does (a worker thread, a child process)
// and reports what its runs brought when polled, once a frame.
#include "app/window/WindowController.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <utility>

#include "app/common/FrameSequence.h"
#include "runtime/files/AnimationFile.h"
#include "viewer/Window.h"

namespace lcjit::app {
namespace {

using Clock = std::chrono::steady_clock;
using Mode = runtime::AnimationSchedule::Mode;

class WindowController {
 public:
  WindowController(ModelHost& host, viewer::Window& window, const std::string& model, const InteractiveOptions& o)
      : host_(host), window_(window), options_(o), stem_(std::filesystem::path(model).stem().string()) {}
  ~WindowController() { stopRecording(); }

  // The loop, until the window closes.
  int run() {
    if (options_.animate) enterAnimate();
    else host_.derive(RunTarget::whole());
    FileMonitor monitor;
    // Refresh mode > Triggered/Continuous turns monitoring on as the command line's mode would
    // (continuous when it said explicit); Explicit turns it off (lpfg's View::SetContinuousMode).
    RefreshMode refresh = options_.refresh;
    bool watching = refresh != RefreshMode::Explicit;
    std::vector<std::string> watched = host_.watchedFiles();
    auto watch = [&] {
      if (!monitor.watch(watched) && !options_.quiet)
        std::fprintf(stderr, "lcjit: file monitoring: %s\n", monitor.error().c_str());
    };
    if (watching) watch();
    for (;;) {
      poll();
      host_.takeInput();
      viewer::MenuActions actions = this->actions();
      actions.monitoring = watching;
      actions.setRefreshMode = [&](bool on) {
        if (on == watching) return;
        watching = on;
        if (!on) return monitor.clear();
        if (refresh == RefreshMode::Explicit) refresh = RefreshMode::Continuous;
        watched = host_.watchedFiles();
        watch();
      };
      if (exit_ || !window_.frame(actions)) break;
      // Redraw on input; while a run is on, the host waits for it (poll) rather than the window.
      window_.waitEvents(host_.busy() ? 0 : 0.05);
      if (watching) {
        std::vector<std::string> changed = monitor.poll(0);
        host_.filesChanged(changed);
        for (Action a : actionsForChanges(changed, refresh)) host_.apply(a);
      }
      // A reload or a run may have named other files (the view file's surfaces, meshes,
      // textures; a sandboxed run's reads).
      if (watching && !host_.busy() && std::exchange(filesMayHaveChanged_, false))
        if (std::vector<std::string> now = host_.watchedFiles(); now != watched) {
          watched = std::move(now);
          watch();
        }
    }
    return 0;
  }

 private:
  // Once a frame: what the host brought, then the animation's next frame when it is due.
  void poll() {
    HostNews n = host_.poll(host_.busy() ? 10 : 0);
    if (n.run) show(*n.run);
    if (n.run || n.rerun || n.redraw) filesMayHaveChanged_ = true;
    if (n.resetView) window_.resetView();
    if (n.rerun || n.redraw) refit_ = true;  // a reload frames itself anew
    if (n.rerun) rerun();
    else if (n.rerunShown) derive(!animating_ ? RunTarget::whole() : shown_ ? RunTarget::at(shown_->step, true) : RunTarget::firstFrame());
    else if (n.redraw) host_.redraw();
    if (n.runAnimation && animating_) startRunning(Mode::Run);
    if (n.pauseAnimation) running_ = false;
    if (running_ && !host_.busy() && shown_ &&
        Clock::now() - shownAt_ >= std::chrono::milliseconds(shown_->animation.swapIntervalMs()))
      advance(mode_);
    showProgress();
  }

  void show(const RunEnd& r) {
    if (r.failed) running_ = false;  // the last picture stays; the host has said why
    if (!r.picture) return;
    shown_ = Shown{r.step, r.derivationLength, r.ended, r.animation};
    const runtime::AnimationSettings& a = r.animation;
    // Animation frames keep the first frame's framing unless the .a file says otherwise (§8.1).
    using Framing = viewer::Window::Framing;
    Framing framing = !animating_ || refit_ || a.scaleBetweenFrames ? Framing::Refit
                      : a.hcenterBetweenFrames                       ? Framing::HCenter
                                                                     : Framing::Keep;
    refit_ = false;
    if (animating_ && a.newViewBetweenFrames) window_.resetView();
    const HostPicture& p = *r.picture;
    if (p.panes->empty()) window_.setScene(*p.main, *p.view, *p.palette, *p.textures, framing);
    else window_.setViews(*p.panes, *p.view, *p.palette, *p.textures);
    if (recordingWanted_) record();
    host_.shown();
    shownAt_ = Clock::now();
  }

  void derive(RunTarget t) { host_.derive(t); }
  // After a reload: the whole derivation again, or, animating, the first frame.
  void rerun() {
    if (animating_) return rewind();
    derive(RunTarget::whole());
  }

  // A run that has gone on half a second says how far it is in the window's status line.
  void showProgress() {
    std::string text = host_.busy() ? host_.progress() : "";
    if (text != status_) window_.setStatus(status_ = text);
  }

  // ---- animate mode (§1.2.3)

  void enterAnimate() {
    host_.apply(Action::NewAnimate);  // the animation file, read again
    animating_ = true;
    rewind();
  }
  void rewind() {
    running_ = false;
    refit_ = true;  // the first frame sets the animation's framing
    derive(RunTarget::firstFrame());
  }
  // The animation file's next frame after the one shown (AnimationSchedule: every `step:` steps
  // from the first frame, and the last frame; with `display on request`, the last frame, the
  // host stopping at each DisplayFrame() on the way); Forever starts over after the last.
  void advance(Mode mode) {
    if (!shown_) return;
    std::optional<RunTarget> next;
    if (shown_->ended) {
      if (mode == Mode::Forever) next = RunTarget::firstFrame();
    } else {
      runtime::AnimationSchedule schedule(shown_->animation, shown_->derivationLength);
      schedule.setCurrent(shown_->step);
      bool wraps = schedule.atEnd();
      if (std::optional<int> step = schedule.next(mode)) next = wraps ? RunTarget::firstFrame() : RunTarget::at(*step);
    }
    if (!next) {
      running_ = false;
      return;
    }
    derive(*next);
  }
  void startRunning(Mode mode) {
    running_ = true;
    mode_ = mode;
  }
  void leaveAnimate() {
    running_ = false;
    stopRecording();
    animating_ = false;
  }

  // The menu as it stands: where the host's items wait for its run (the session's engine is the
  // worker's), those that need the model are greyed out meanwhile.
  viewer::MenuActions actions() {
    viewer::MenuActions a;
    a.saveName = stem_ + ".png";
    a.exit = [this] { exit_ = true; };
    a.animating = animating_;
    a.stop = [this] {
      running_ = false;
      host_.stop();  // a long step in progress stops too
    };
    a.interrupt = [this] {
      running_ = false;
      host_.interrupt();  // Esc: model code stuck in a loop too
    };
    a.clear = [this] { host_.redraw(); };
    if (host_.records()) a.startRecording = [this] { recordingWanted_ = true; };
    host_.addToMenu(a);
    if (host_.busy() && host_.itemsWaitWhileBusy()) return a;
    a.newModel = [this] { host_.apply(Action::NewModel); };
    a.newLsystem = [this] { host_.apply(Action::NewLsystem); };
    a.newRun = [this] { host_.apply(Action::NewRun); };
    a.newView = [this] { host_.apply(Action::NewView); };
    a.newRendering = [this] { host_.apply(Action::NewRendering); };
    a.animate = [this] { enterAnimate(); };
    a.step = [this] {
      running_ = false;  // as lpfg's Step stops a Run
      if (!host_.busy()) advance(Mode::Step);
    };
    a.run = [this] { startRunning(Mode::Run); };
    a.forever = [this] { startRunning(Mode::Forever); };
    a.rewind = [this] { rewind(); };
    a.dontAnimate = [this] {
      leaveAnimate();
      derive(RunTarget::whole());
    };
    return a;
  }

  // Start recording: every frame shown from then on, to --record's video or numbered files, by
  // default lpfg's numbered pictures (MODELNNNN.png, lpfg's Save format) in the .a file's frame
  // dump folder. The numbers are the .a file's (frame count or step), from 0.
  void record() {
    const runtime::AnimationSettings& animation = shown_->animation;
    if (!recording_) {
      std::string out = options_.record;
      if (out.empty()) out = (std::filesystem::path(animation.frameDumpPath) / (stem_ + "%04d.png")).string();
      auto opened = FrameSequence::open(out, options_.fps);
      if (!opened) {
        report(opened.takeError());
        recordingWanted_ = false;
        return;
      }
      recording_ = std::move(*opened);
    }
    int number = animation.frameNumbers == runtime::AnimationSettings::FrameNumbers::StepNo ? shown_->step : recorded_;
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

  void report(llvm::Error e) {
    if (e) std::fprintf(stderr, "%s\n", llvm::toString(std::move(e)).c_str());
  }

  ModelHost& host_;
  viewer::Window& window_;
  InteractiveOptions options_;
  std::string stem_;
  bool exit_ = false;
  std::string status_;  // the status line shown
  // The last picture shown: where its run left the derivation, and the animation file it used.
  struct Shown {
    int step = 0, derivationLength = 0;
    bool ended = false;
    runtime::AnimationSettings animation;
  };
  std::optional<Shown> shown_;
  Clock::time_point shownAt_;
  bool filesMayHaveChanged_ = false;  // a reload or a run since the watched files were last asked for
  bool animating_ = false, running_ = false;
  Mode mode_ = Mode::Run;
  bool refit_ = true;                          // the next picture frames itself (first frame, reloads)
  bool recordingWanted_ = false;               // Start recording was chosen (and not ended)
  std::unique_ptr<FrameSequence> recording_;   // where they go, opened at the first frame
  int recorded_ = 0;
};

}  // namespace

int runWindow(const viewer::WindowOptions& windowOptions, const InteractiveOptions& options, const std::string& model,
              const std::function<std::unique_ptr<ModelHost>(viewer::Window&)>& makeHost) {
  auto window = viewer::Window::create(windowOptions);
  if (!window) {
    std::fprintf(stderr, "lcjit: cannot open a window: %s\n", llvm::toString(window.takeError()).c_str());
    return 1;
  }
  for (const std::string& title : options.panels) (*window)->showPanel(title, true);
  std::unique_ptr<ModelHost> host = makeHost(**window);
  return WindowController(*host, **window, model, options).run();
}

}  // namespace lcjit::app
