// The window under --sandbox (see SandboxWindow.h). A re-run is a new child for the whole
// derivation up to the wanted step: stepping costs a run from the axiom each time, which keeps
// the parent free of model state (there is none to keep in step with the child).
#include "app/sandbox/SandboxWindow.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <utility>

#include "app/session/FileMonitor.h"
#include "app/common/Frame.h"
#include "app/common/PlainErrors.h"
#include "app/sandbox/SandboxReply.h"
#include "runtime/Engine.h"
#include "runtime/WindowInput.h"
#include "runtime/files/AnimationFile.h"
#include "runtime/turtle/Camera.h"
#include "runtime/turtle/Drawing.h"
#if LCJIT_HAVE_WINDOW
#include "viewer/Window.h"
#endif

namespace lcjit::app {

namespace {
bool writeAll(int fd, const std::string& bytes) {
  size_t done = 0;
  while (done < bytes.size()) {
    ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += size_t(n);
  }
  return true;
}
}  // namespace

int answerWindow(Session& session, const ModelFiles& files, llvm::Error loaded, const WindowAnswerOptions& o) {
  SandboxReply reply;
  auto answer = [&](int status) {
    if (!writeAll(o.replyFd, encodeSandboxReply(reply)))
      std::fprintf(stderr, "lcjit: the sandboxed run could not send its picture: %s\n", std::strerror(errno));
    return status;
  };
  if (loaded) {
    // As the in-process window shows a broken edit: with the source lines, over the last picture.
    std::string shown = withSourceLines(llvm::toString(std::move(loaded)));
    if (o.plainErrors) shown = inPlainLanguage(shown);
    std::fprintf(stderr, "%s\n", shown.c_str());
    reply.message = shown + "\n(the last good model is shown; save a fix to reload)";
    return answer(1);
  }
  // The animation file, read as the in-process window reads it (Interactive.cpp).
  runtime::AnimationSettings animation;
  for (const std::string& f : files.other)
    if (fileKindOf(f) == FileKind::Animation) {
      std::vector<std::string> warnings;
      animation = runtime::loadAnimationFile(f, warnings);
      for (const std::string& w : warnings)
        if (!o.quiet) std::fprintf(stderr, "%s\n", w.c_str());
    }
  int toStep = o.toStep == kFirstFrame ? animation.firstFrame : o.toStep;
  runtime::Engine& engine = session.engine();
  const runtime::DrawingFiles& drawing = session.drawing();
  if (!o.quiet)
    for (const std::string& w : session.warnings()) std::fprintf(stderr, "%s\n", w.c_str());
  FrameWriter frames;
  runtime::EngineHooks hooks;
  if (o.quiet) hooks.print = [](const char*) {};
  NamedFrames named;  // OutputFrame's files, written once their step is over
  hooks.outputFrame = [&](const char* path) { named.name(path); };
  auto writeNamed = [&] {
    if (named.empty()) return;
    if (auto e = named.writeAll(frames, engine, drawing)) std::fprintf(stderr, "%s\n", llvm::toString(std::move(e)).c_str());
  };
  hooks.afterStep = [&](int step) {
    writeNamed();
    if (o.debug) std::printf("lcjit: step %d: %zu modules\n", step, engine.moduleCount());
    if (o.progress) o.progress(step);
  };
  // The window's camera is the parent's: model code sees the one a new window starts with.
  runtime::WindowInput& window = session.windowInput();
  window.views.setCamera(0, runtime::initialWindowCamera(1 / runtime::projectionScale(drawing.view, 0)));
  engine.begin(hooks);
  writeNamed();  // Start's
  bool more = true;
  while (more && (toStep < 0 || engine.stepNo() < toStep)) more = engine.step();
  if (toStep < 0) engine.finish();
  writeNamed();  // End's
  reply.steps = engine.stepNo();
  reply.derivationLength = engine.derivationLength();
  reply.animation = {animation.firstFrame, animation.resolvedLastFrame(reply.derivationLength),
                     std::max(animation.step, 1), std::clamp(animation.swapIntervalMs(), 0, 3600000),
                     animation.hcenterBetweenFrames, animation.scaleBetweenFrames, animation.newViewBetweenFrames};
  reply.derived = !more || engine.stepNo() >= engine.derivationLength();
  if (o.progress && reply.derived) o.progress(-1);
  if (window.mouse.wasRead()) reply.unanswered = "GetMouseStatus/GetTabletStatus";
  auto fault = [&](llvm::Error e) {
    reply.message = llvm::toString(std::move(e));
    std::fprintf(stderr, "%s\n", reply.message.c_str());
    return answer(1);
  };
  if (auto e = engine.takeFault()) return fault(std::move(e));
  if (auto e = engine.interpret(reply.main)) return fault(std::move(e));
  runtime::Bounds b = reply.main.framingBounds();
  if (!b.empty()) window.views.setBox(0, b.min, b.max);
  auto panes = interpretViews(engine, drawing.view);
  if (!panes) return fault(panes.takeError());
  reply.panes = std::move(*panes);
  RenderLook look;
  look.of(drawing);
  reply.palette = look.palette;
  reply.textures = std::move(look.textures);
  reply.view = drawing.view;
  reply.hasPicture = true;
  return answer(0);
}

#if LCJIT_HAVE_WINDOW
namespace {

using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

class SandboxedWindow {
 public:
  SandboxedWindow(const SandboxPlan& plan, viewer::Window& window, const InteractiveOptions& options)
      : plan_(plan), window_(window), options_(options) {}
  ~SandboxedWindow() { stopRun(); }

  bool busy() const { return run_ != nullptr; }
  bool exitRequested() const { return exit_; }
  const std::vector<std::string>& inputs() const { return inputs_; }

  // A new child for the picture at `toStep` (-1: the whole derivation; kFirstFrame); one running
  // is stopped.
  void start(int toStep, bool refit) {
    stopRun();
    SandboxPlan p = plan_;
    if (toStep != -1) p.args.push_back("--to-step=" + std::to_string(toStep));  // "=": -2 is no option
    auto run = SandboxedRun::start(p);
    if (!run) return say(llvm::toString(run.takeError()));
    run_ = std::move(*run);
    startedAt_ = Clock::now();
    refit_ = refit_ || refit;
  }
  void rerun(bool refit) { start(animating_ ? kFirstFrame : -1, refit); }

  // Waits up to `ms` for the running child (reading its reply meanwhile); shows what it sent.
  void poll(int ms) {
    if (!run_ || !run_->wait(ms)) return;
    SandboxOutcome o = run_->outcome();  // a death the child could not report is on stderr now
    run_.reset();
    if (!o.inputs.empty()) inputs_ = o.inputs;
    if (o.stopped) return;
    if (o.reply.empty()) {
      running_ = false;
      std::string why = !o.fault.empty() ? o.fault
                                         : plan_.model + ": error: the sandboxed run ended without a picture (its "
                                                         "messages are above)";
      if (o.fault.empty()) std::fprintf(stderr, "%s\n", why.c_str());
      window_.setMessage(why + "\n(the last good picture is shown)");
      return;
    }
    auto reply = decodeSandboxReply(o.reply);
    if (!reply) {
      running_ = false;
      return say(plan_.model + ": error: " + llvm::toString(reply.takeError()));
    }
    step_ = reply->steps;
    derived_ = reply->derived;
    animation_ = reply->animation;
    std::string note;  // once: every run would say it again
    if (!reply->unanswered.empty() && !std::exchange(toldUnanswered_, true))
      note = "lcjit: --sandbox: " + plan_.model + ": the model reads the window's input (" + reply->unanswered +
             "), which a sandboxed run does not get: no button, no pointer (docs/security.md)";
    shownAt_ = Clock::now();
    if (!reply->message.empty()) {
      running_ = false;  // the child printed it on stderr
      window_.setMessage(reply->message);
      return;
    }
    window_.setMessage("");
    if (!note.empty()) say(note);
    if (!reply->hasPicture) return;
    if (options_.verbose)
      std::fprintf(stderr, "lcjit: sandboxed run shown: step %d of %d, %.1f ms\n", reply->steps,
                   reply->derivationLength,
                   std::chrono::duration<double, std::milli>(Clock::now() - startedAt_).count());
    // Animation frames keep the first frame's framing unless the .a file says otherwise (§8.1).
    using Framing = viewer::Window::Framing;
    Framing framing = !animating_ || refit_ || animation_.scale ? Framing::Refit
                      : animation_.hcenter                      ? Framing::HCenter
                                                                : Framing::Keep;
    refit_ = false;
    if (animating_ && animation_.newView) window_.resetView();
    if (reply->panes.empty())
      window_.setScene(reply->main, reply->view, reply->palette, reply->textures, framing);
    else
      window_.setViews(reply->panes, reply->view, reply->palette, reply->textures);
  }

  // The animation file's next frame after the one shown (AnimationSchedule's rule: every
  // `step:` steps from the first frame, and the last frame); none past the last frame or the
  // derivation's end.
  std::optional<int> nextFrame() const {
    const SandboxReply::Animation& a = animation_;
    if (derived_ || step_ >= a.lastFrame) return std::nullopt;
    long long next = step_ < a.firstFrame ? a.firstFrame
                                          : a.firstFrame + ((step_ - a.firstFrame) / a.step + 1) * 1ll * a.step;
    return int(std::min<long long>(next, a.lastFrame));
  }

  // Animation: Run/Forever take the next frame once the last one has been shown for the swap
  // interval.
  void advance() {
    if (!running_ || busy() || Clock::now() - shownAt_ < std::chrono::milliseconds(animation_.swapIntervalMs)) return;
    if (std::optional<int> next = nextFrame()) return start(*next, false);
    if (forever_) return start(kFirstFrame, false);
    running_ = false;
  }

  // File changes or a New … item: one new run of the files as they are now.
  void apply(const std::vector<Action>& actions) {
    bool again = false;
    for (Action a : actions) {
      if (a == Action::NewAnimate || !reloadPartsFor(a)) continue;
      if (resetsView(a)) window_.resetView();
      again = true;
    }
    if (again) rerun(true);
  }

  // Pointer clicks that would insert MouseIns into the string: the string is the child's.
  void refuseInsertion() {
    if (window_.takePointer().insert)
      say("lcjit: --sandbox: mouse insertion (MouseIns) changes the model's string, which lives in the sandboxed "
          "run; it is off under the sandbox (docs/security.md)");
  }

  viewer::MenuActions actions() {
    viewer::MenuActions a;
    a.saveName = fs::path(plan_.model).stem().string() + ".png";
    a.exit = [this] { exit_ = true; };
    a.animating = animating_;
    auto stop = [this] {
      running_ = false;
      if (!busy()) return;
      stopRun();
      say(plan_.model + ": the sandboxed run was stopped");
    };
    a.stop = stop;
    a.interrupt = stop;
    a.clear = [this] { start(animating_ ? step_ : -1, false); };  // the same picture, drawn anew
    a.newModel = [this] { apply({Action::NewModel}); };
    a.newLsystem = [this] { apply({Action::NewLsystem}); };
    a.newRun = [this] { apply({Action::NewRun}); };
    a.newView = [this] { apply({Action::NewView}); };
    a.newRendering = [this] { apply({Action::NewRendering}); };
    const char* stringIsTheChilds = "the model's string lives in the sandboxed run; only pictures are saved from the "
                                    "window under the sandbox (docs/security.md)";
    a.saveAs = [this, stringIsTheChilds](const std::string& path) {
      say("lcjit: --sandbox: cannot save " + path + ": " + stringIsTheChilds);
    };
    a.stringInput = a.stringOutput = [this, stringIsTheChilds] {
      say(std::string("lcjit: --sandbox: String input/output is off: ") + stringIsTheChilds);
    };
    a.animate = [this] {
      animating_ = true;
      start(kFirstFrame, true);
    };
    a.step = [this] {
      running_ = false;
      if (busy()) return;
      if (std::optional<int> next = nextFrame()) start(*next, false);
    };
    a.run = [this] { running_ = true, forever_ = false; };
    a.forever = [this] { running_ = forever_ = true; };
    a.rewind = [this] {
      running_ = false;
      start(kFirstFrame, true);
    };
    a.dontAnimate = [this] {
      animating_ = running_ = false;
      start(-1, true);
    };
    return a;
  }

  void startAnimating() { animating_ = true; }

 private:
  void stopRun() {
    if (!run_) return;
    run_->stop();
    run_->wait(-1);
    run_.reset();
  }
  void say(const std::string& line) {
    std::fprintf(stderr, "%s\n", line.c_str());
    window_.setMessage(line);
  }

  SandboxPlan plan_;
  viewer::Window& window_;
  InteractiveOptions options_;
  std::unique_ptr<SandboxedRun> run_;
  std::vector<std::string> inputs_;
  int step_ = 0;
  SandboxReply::Animation animation_;  // the last run's animation file
  bool derived_ = false, animating_ = false, running_ = false, forever_ = false, refit_ = true, exit_ = false;
  bool toldUnanswered_ = false;
  Clock::time_point shownAt_, startedAt_;
};

}  // namespace

int runSandboxedWindow(const SandboxPlan& plan, const viewer::WindowOptions& windowOptions,
                       const InteractiveOptions& options) {
  auto window = viewer::Window::create(windowOptions);
  if (!window) {
    std::fprintf(stderr, "lcjit: cannot open a window: %s\n", llvm::toString(window.takeError()).c_str());
    return 1;
  }
  SandboxedWindow model(plan, **window, options);
  if (options.animate) model.startAnimating();
  model.rerun(true);
  FileMonitor monitor;
  const bool watching = options.refresh != RefreshMode::Explicit;
  std::vector<std::string> watched;
  auto watchInputs = [&] {
    std::vector<std::string> now = model.inputs();
    if (now.empty()) now = {fs::absolute(plan.model).string()};  // nothing reported: the model at least
    if (!watching || now == watched) return;
    watched = std::move(now);
    if (!monitor.watch(watched) && !options.quiet)
      std::fprintf(stderr, "lcjit: file monitoring: %s\n", monitor.error().c_str());
  };
  watchInputs();
  for (;;) {
    // While a child runs, wait on it (its reply comes through a pipe) rather than on the window.
    model.poll(model.busy() ? 10 : 0);
    watchInputs();
    model.refuseInsertion();
    viewer::MenuActions actions = model.actions();
    if (model.exitRequested() || !(*window)->frame(actions)) break;
    (*window)->waitEvents(model.busy() ? 0 : 0.05);
    if (watching) model.apply(actionsForChanges(monitor.poll(0), options.refresh));
    model.advance();
  }
  return 0;
}
#endif

}  // namespace lcjit::app
