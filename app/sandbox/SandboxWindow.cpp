// The window under --sandbox (see SandboxWindow.h): the child's answer, and the model host the
// window's controller drives in the parent (app/window/ModelHost.h). A re-run is a new child for
// the whole derivation up to the wanted step: stepping costs a run from the axiom each time, which
// keeps the parent free of model state (there is none to keep in step with the child).
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
#include "app/window/ModelHost.h"
#include "app/window/WindowController.h"
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
  if (auto e = interpretWindowPicture(engine, drawing.view, reply.main, reply.panes)) return fault(std::move(e));
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

// The window's model host under the sandbox (app/window/ModelHost.h): every run is a new child
// for the whole derivation up to the wanted step.
class SandboxHost final : public ModelHost {
 public:
  SandboxHost(const SandboxPlan& plan, viewer::Window& window, const InteractiveOptions& options)
      : plan_(plan), window_(window), options_(options) {}
  ~SandboxHost() override { stopRun(); }

  // ---- runs

  void derive(RunTarget target) override {
    start(target.kind == RunTarget::Kind::Whole        ? -1
          : target.kind == RunTarget::Kind::FirstFrame ? kFirstFrame
                                                       : target.step);
  }
  void redraw() override { start(toStep_ == -1 ? -1 : step_); }  // the same picture, drawn anew
  bool busy() const override { return run_ != nullptr; }
  bool itemsWaitWhileBusy() const override { return false; }  // a new run replaces the one running
  void stop() override {
    if (!busy()) return;
    stopRun();
    say(plan_.model + ": the sandboxed run was stopped");
  }
  void interrupt() override { stop(); }

  // Waits up to `waitMs` for the running child (reading its reply meanwhile); hands over what it
  // sent.
  HostNews poll(int waitMs) override {
    HostNews news = std::exchange(news_, {});
    if (!run_ || !run_->wait(waitMs)) return news;
    SandboxOutcome o = run_->outcome();  // a death the child could not report is on stderr now
    run_.reset();
    if (!o.inputs.empty()) inputs_ = o.inputs;
    if (o.stopped) return news;
    RunEnd& r = news.run.emplace();
    r.failed = true;  // until there is a picture
    if (o.reply.empty()) {
      std::string why = !o.fault.empty() ? o.fault
                                         : plan_.model + ": error: the sandboxed run ended without a picture (its "
                                                         "messages are above)";
      if (o.fault.empty()) std::fprintf(stderr, "%s\n", why.c_str());
      window_.setMessage(why + "\n(the last good picture is shown)");
      return news;
    }
    auto reply = decodeSandboxReply(o.reply);
    if (!reply) {
      say(plan_.model + ": error: " + llvm::toString(reply.takeError()));
      return news;
    }
    reply_ = std::move(*reply);
    step_ = reply_.steps;
    std::string note;  // once: every run would say it again
    if (!reply_.unanswered.empty() && !std::exchange(toldUnanswered_, true))
      note = "lcjit: --sandbox: " + plan_.model + ": the model reads the window's input (" + reply_.unanswered +
             "), which a sandboxed run does not get: no button, no pointer (docs/security.md)";
    if (!reply_.message.empty()) {
      window_.setMessage(reply_.message);  // the child printed it on stderr
      return news;
    }
    r.failed = false;
    window_.setMessage("");
    if (!note.empty()) say(note);
    if (!reply_.hasPicture) return news;
    if (options_.verbose)
      std::fprintf(stderr, "lcjit: sandboxed run shown: step %d of %d, %.1f ms\n", reply_.steps,
                   reply_.derivationLength,
                   std::chrono::duration<double, std::milli>(Clock::now() - startedAt_).count());
    r.picture = HostPicture{&reply_.main, &reply_.panes, &reply_.view, &reply_.palette, &reply_.textures};
    r.step = reply_.steps;
    r.derivationLength = reply_.derivationLength;
    r.ended = reply_.derived;
    // The child's animation file (it reads the file anew for every run); DisplayFrame() is the
    // child's, which derives to the step asked for.
    const SandboxReply::Animation& a = reply_.animation;
    r.animation.firstFrame = a.firstFrame;
    r.animation.lastFrame = a.lastFrame;
    r.animation.step = a.step;
    r.animation.swapInterval = a.swapIntervalMs / 10;
    r.animation.hcenterBetweenFrames = a.hcenter;
    r.animation.scaleBetweenFrames = a.scale;
    r.animation.newViewBetweenFrames = a.newView;
    return news;
  }

  // ---- files

  // File changes or a New … item: one new run of the files as they are now (New animate: each
  // run reads the animation file anyway).
  void apply(Action a) override {
    if (a == Action::NewAnimate || !reloadPartsFor(a)) return;
    news_.rerun = true;
    news_.resetView = news_.resetView || resetsView(a);
  }
  std::vector<std::string> watchedFiles() const override {
    if (inputs_.empty()) return {fs::absolute(plan_.model).string()};  // nothing reported: the model at least
    return inputs_;
  }

  // ---- the window's input and menu

  // Pointer clicks that would insert MouseIns into the string: the string is the child's.
  void takeInput() override {
    if (window_.takePointer().insert)
      say("lcjit: --sandbox: mouse insertion (MouseIns) changes the model's string, which lives in the sandboxed "
          "run; it is off under the sandbox (docs/security.md)");
  }

  void addToMenu(viewer::MenuActions& a) override {
    const char* stringIsTheChilds = "the model's string lives in the sandboxed run; only pictures are saved from the "
                                    "window under the sandbox (docs/security.md)";
    a.saveAs = [this, stringIsTheChilds](const std::string& path) {
      say("lcjit: --sandbox: cannot save " + path + ": " + stringIsTheChilds);
    };
    a.stringInput = a.stringOutput = [this, stringIsTheChilds] {
      say(std::string("lcjit: --sandbox: String input/output is off: ") + stringIsTheChilds);
    };
  }
  // The animation file's frame dump folder is the model's to name: the window's process does not
  // write there.
  bool records() const override { return false; }

 private:
  // A new child for the picture at `toStep` (-1: the whole derivation; kFirstFrame); one running
  // is stopped.
  void start(int toStep) {
    stopRun();
    SandboxPlan p = plan_;
    if (toStep != -1) p.args.push_back("--to-step=" + std::to_string(toStep));  // "=": -2 is no option
    auto run = SandboxedRun::start(p);
    if (!run) return say(llvm::toString(run.takeError()));
    run_ = std::move(*run);
    toStep_ = toStep;
    startedAt_ = Clock::now();
  }
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
  int toStep_ = -1;  // what the last run was started for
  SandboxReply reply_;  // the last one, with the picture shown
  HostNews news_;
  std::vector<std::string> inputs_;
  int step_ = 0;
  bool toldUnanswered_ = false;
  Clock::time_point startedAt_;
};

}  // namespace

int runSandboxedWindow(const SandboxPlan& plan, const viewer::WindowOptions& windowOptions,
                       const InteractiveOptions& options) {
  return runWindow(windowOptions, options, plan.model, [&](viewer::Window& window) -> std::unique_ptr<ModelHost> {
    return std::make_unique<SandboxHost>(plan, window, options);
  });
}
#endif

}  // namespace lcjit::app
