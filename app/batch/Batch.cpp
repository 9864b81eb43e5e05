// Batch runs and --watch (see Batch.h).
#include "app/batch/Batch.h"
#include "app/cli/Modes.h"
#include "app/common/ProfileReport.h"
#include "app/common/Progress.h"

#include "runtime/turtle/Camera.h"

#include <poll.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <future>
#include <optional>
#include <thread>
#include <utility>

#include <nlohmann/json.hpp>

#include "app/common/Background.h"
#include "runtime/turtle/Drawing.h"
#include "runtime/Engine.h"
#include "app/session/FileMonitor.h"
#include "app/common/Frame.h"
#include "app/common/FrameSequence.h"
#include "app/common/PlainErrors.h"
#include "app/batch/ProgramPages.h"
#include "app/common/RunRecord.h"
#include "runtime/WindowInput.h"
#include "support/Elapsed.h"
#include "support/ReplacingFile.h"

namespace lcjit::app {
namespace {

using support::Clock;

// -dtf/-dtfes files go to the working folder (lpfg runs in the object's folder, so the same place
// for its users) rather than beside a model that may live in a read-only tree.
std::string stemInWorkingFolder(const std::string& p) { return std::filesystem::path(p).stem().string(); }

template <class... Args>
std::string fmtMs(const char* format, Args... args) {
  char buf[160];
  std::snprintf(buf, sizeof buf, format, args...);
  return buf;
}

// A message naming FILE:LINE:COL (a fault in model code) shows that line with a caret under the
// column, as compile errors do. Returns the message.
std::string report(llvm::Error e) {
  if (!e) return {};
  std::string message = llvm::toString(std::move(e));
  std::fprintf(stderr, "%s\n", withSourceLines(message).c_str());
  return message;
}

llvm::Error writeOutput(const std::string& out, runtime::Engine& engine, const runtime::DrawingFiles& drawing,
                        FrameWriter& frames, PhaseTimes& times) {
  if (isFrameOutput(out)) {
    FrameTimes ft;
    if (auto e = frames.write(out, engine, drawing, &ft)) return e;
    times.interpretMs = ft.interpretMs;
    times.renderMs = ft.renderMs;
    return llvm::Error::success();
  }
  // Any other name is lpfg's text string, as lpfg writes it.
  if (outputKindOf(out) == OutputKind::BinaryString) return engine.writeBinary(out);
  return engine.writeTextFile(out);
}

// -dtf/-dtfes: lpfg's turtle text of the current string, streamed to `path`; the time it took is
// added to `interpretMs`.
llvm::Error writeInterpretation(runtime::Engine& engine, const std::string& path, double& interpretMs) {
  auto t0 = Clock::now();
  llvm::Error e = support::writeWholeFile(path, [&](std::ostream& out) { return engine.writeTurtleText(out); });
  interpretMs += support::msSince(t0);
  return e;
}

// What a batch of file changes re-reads (§1.3's actions, merged); nothing for the animation or
// environment files, which a batch run does not use.
std::optional<ReloadParts> partsFor(const std::vector<Action>& actions) {
  std::optional<ReloadParts> parts;
  for (Action a : actions)
    if (std::optional<ReloadParts> p = reloadPartsFor(a)) {
      if (!parts) parts = ReloadParts{false, false, false, false};
      *parts |= *p;
    }
  return parts;
}

// `stopped`: set from another thread when the run was interrupted on purpose (a newer save,
// under --watch); its fault is then not reported and the status is 2.
// VerifyString: (manual §10.4), as lpfg checks it after a batch run: the final string's module
// names against the statement's list. "Verify: Success" or "Verify: Fail" on standard output;
// on failure the two lists go to Verify_<model>_expected.txt and Verify_<model>_actual.txt, one
// name a line, and the run fails. Models without the statement pass.
bool verifyString(const runtime::Engine& engine, const std::string& lsystem, bool quiet) {
  const __lc_Model& model = engine.model();
  if (model.nVerify == 0) return true;
  const runtime::ModuleTable& modules = engine.modules();
  const runtime::ModuleBuffer& s = engine.string();
  std::vector<__lc_ModuleId> actual;
  for (size_t p = 0; p < s.size(); p = modules.next(s.data(), p)) actual.push_back(runtime::ModuleTable::idAt(s.data() + p));
  bool same = std::equal(actual.begin(), actual.end(), model.verify, model.verify + model.nVerify);
  same = same && actual.size() == model.nVerify;
  if (!quiet) std::printf("Verify: %s\n", same ? "Success" : "Fail");
  if (same) return true;
  std::ofstream expected("Verify_" + lsystem + "_expected.txt"), got("Verify_" + lsystem + "_actual.txt");
  for (uint32_t i = 0; i < model.nVerify; ++i) expected << modules.info(model.verify[i]).name << "\n";
  for (__lc_ModuleId id : actual) got << modules.info(id).name << "\n";
  return false;
}

// The better tier's build, once finished, takes over from the running code (see BatchOptions).
void takeBetterTier(Background<BetterTier>& tier, Session& session, const BatchOptions& options) {
  std::optional<BetterTier> better = tier.take();
  if (!better) return;
  if (better->error.size()) {
    std::fprintf(stderr, "lcjit: the -O%d build failed; -O%d code goes on running\n%s\n", options.betterTier,
                 session.optLevel(), better->error.c_str());
    return;
  }
  double ms = better->compileMs;
  bool cached = better->objectCached;
  if (session.installTier(std::move(*better)) && options.verbose)
    std::fprintf(stderr, "lcjit: -O%d code swapped in after step %d (%s in %.1f ms in the background)\n",
                 session.optLevel(), session.engine().stepsDone(), cached ? "loaded from the cache" : "compiled", ms);
}

// `betweenSteps`: called after each step with the derivation's time so far (ms). Without it,
// the program's pages are released once the string is large (ProgramPages.h); with it, it does.
// `error`: the first error the run reported, when it reported one.
int runOnce(Session& session, const ModelFiles& files, const BatchOptions& options, PhaseTimes& times,
            FrameWriter& frames, const std::atomic<bool>* stopped = nullptr,
            const std::function<void(double)>& betweenSteps = {}, std::string* error = nullptr) {
  auto& engine = session.engine();
  auto fail = [&](llvm::Error e) {
    std::string message = report(std::move(e));
    if (error && error->empty()) *error = message;
  };
  runtime::EngineHooks hooks;
  if (options.quiet) hooks.print = [](const char*) {};
  // OutputFrame: see BatchOptions::outputFrames.
  NamedFrames framesNamed;
  bool frameNoted = false;
  hooks.outputFrame = [&](const char* path) {
    if (options.outputFrames) {
      framesNamed.name(path);
    } else if (!frameNoted && !options.quiet) {
      frameNoted = true;
      std::fprintf(stderr, "lcjit: note: OutputFrame(\"%s\") writes nothing in batch mode, as in lpfg; --output-frames "
                   "writes each such file once its step is over\n", path);
    }
  };
  auto writeFramesNamed = [&] { fail(framesNamed.writeAll(frames, engine, session.drawing())); };
  if (options.outputFrames)
    hooks.afterStep = [&](int) { writeFramesNamed(); };
  if (!options.quiet)
    for (const std::string& w : session.warnings()) std::fprintf(stderr, "%s\n", w.c_str());
  if (options.dumpSteps)
    hooks.afterDerivation = [&](int step) { std::printf("After step %d:\n%s", step, engine.text(engine.string()).c_str()); };
  bool interpretFailed = false;  // -dtfes: an interpretation rule's fault, reported once
  if (options.dumpInterpretedEach || options.debug)
    hooks.afterStep = [&, before = std::move(hooks.afterStep)](int step) {
      if (before) before(step);
      if (options.debug) std::printf("lcjit: step %d: %zu modules\n", step, engine.moduleCount());  // -d: lpfg's debug output
      if (!options.dumpInterpretedEach || interpretFailed) return;
      char suffix[16];
      std::snprintf(suffix, sizeof suffix, "%08d", step);
      if (auto e = writeInterpretation(engine, stemInWorkingFolder(files.lsystem) + suffix + ".str", times.interpretMs)) {
        fail(std::move(e));
        interpretFailed = true;
      }
    };
  if (options.verbose)
    std::fprintf(stderr, "lcjit: %s: preprocessed in %.1f ms, rewritten in %.1f ms, compiled -O%d in %.1f ms (%s)\n",
                 files.lsystem.c_str(), times.preprocessMs, times.rewriteMs, times.optLevel >= 0 ? times.optLevel : session.optLevel(), times.compileMs,
                 times.pchCached ? "cached PCH" : "PCH built");
  // A picture or a geometry file is what lpfg's window would save: derived with its camera.
  if (!options.out.empty() && isFrameOutput(options.out))
    session.windowInput().views.setCamera(
        0, runtime::initialWindowCamera(1 / runtime::projectionScale(session.drawing().view, 0)));
  if (options.progress)
    hooks.afterStep = [&, step = std::move(hooks.afterStep)](int n) {
      options.progress(n);
      if (step) step(n);
    };
  // -out frame%04d.png or movie.mp4 (FrameSequence.h): the axiom (step 0) and every step, each
  // to a numbered file of the kind or as a video's frame. A video's file is made before the
  // derivation runs: one that cannot be written fails at once.
  std::unique_ptr<FrameSequence> sequence;
  if (!options.out.empty() && isFrameSequence(options.out)) {
    auto opened = FrameSequence::open(options.out, options.fps);
    if (!opened) {
      fail(opened.takeError());
      return 1;
    }
    sequence = std::move(*opened);
  }
  auto t0 = Clock::now();
  // On a terminal, a derivation that has run half a second shows how far it is, one line
  // rewritten at most twice a second (the module count can walk the string: not more often),
  // cleared when it ends. Short runs and logs see nothing.
  TerminalProgress shown(!options.quiet && ::isatty(STDERR_FILENO));
  if (shown.enabled) {
    hooks.print = [&](const char* text) {  // the model's output starts on a line of its own
      shown.clear();
      std::fputs(text, stdout);
    };
    hooks.afterStep = [&, step = std::move(hooks.afterStep)](int n) {
      if (step) step(n);
      shown.update(support::msSince(t0), [&] {
        return progressText(n, engine.derivationLength(), engine.moduleCount());
      });
    };
  }
  FrameSource source;
  source.writeFile = [&](const std::string& path) { return writeOutput(path, engine, session.drawing(), frames, times); };
  source.picture = [&]() -> llvm::Expected<runtime::Image> {
    FrameTimes ft;
    auto image = frames.picture(engine, session.drawing(), &ft);
    times.interpretMs = ft.interpretMs;
    times.renderMs = ft.renderMs;
    return image;
  };
  bool frameFailed = false;
  auto writeFrame = [&](int step) {
    if (frameFailed) return;
    if (auto e = sequence->add(step, source)) {
      fail(std::move(e));
      frameFailed = true;
      engine.stop();
    }
  };
  if (sequence)
    hooks.afterStep = [&, step = std::move(hooks.afterStep)](int n) {
      writeFrame(n);
      if (step) step(n);
    };
  engine.setProfiling(!options.profile.empty());
  engine.begin(hooks);
  writeFramesNamed();  // Start's
  if (sequence) writeFrame(0);
  while (engine.step()) {
    if (betweenSteps)
      betweenSteps(support::msSince(t0));
    else
      releaseProgramPagesOnceAt(engine.string().size());
  }
  engine.finish();
  writeFramesNamed();  // End's
  if (auto e = engine.takeFault()) {
    if (stopped && *stopped) {
      llvm::consumeError(std::move(e));
      if (options.verbose) std::fprintf(stderr, "lcjit: the run stopped for the change\n");
      return 2;
    }
    fail(std::move(e));
    return 1;
  }
  times.deriveMs = support::msSince(t0);
  shown.clear();
  if (options.progress) options.progress(-1);
  if (frameFailed) return 1;
  if (sequence)
    if (auto e = sequence->finish()) {
      fail(std::move(e));
      return 1;
    }
  if (!options.out.empty() && !sequence)
    if (auto e = writeOutput(options.out, engine, session.drawing(), frames, times)) {
      fail(std::move(e));
      return 1;
    }
  for (const std::string& out : options.moreOuts)
    if (auto e = writeOutput(out, engine, session.drawing(), frames, times)) {
      fail(std::move(e));
      return 1;
    }
  if (options.dumpInterpreted)
    if (auto e = writeInterpretation(engine, stemInWorkingFolder(files.lsystem) + ".str", times.interpretMs)) {
      fail(std::move(e));
      return 1;
    }
  if (!verifyString(engine, files.lsystem, options.quiet)) {
    if (error && error->empty()) *error = "the final string is not the one VerifyString states";
    return 1;
  }
  if (options.profile == "-") {
    const std::vector<ProfileRow> rows = profileRows(*engine.profile(), engine.ruleSources());
    std::fputs(profileTable(rows, rows.size()).c_str(), stdout);
    std::fflush(stdout);
  } else if (!options.profile.empty())
    if (auto e = support::writeWholeFile(options.profile,
                                         profileJson(*engine.profile(), engine.model(), engine.ruleSources(), engine.stepsDone(), times.deriveMs))) {
      llvm::consumeError(std::move(e));
      fail(llvm::createStringError(options.profile + ": error: cannot write the profile"));
      return 1;
    }
  if (options.verbose)
    std::fprintf(stderr, "lcjit: derived %d steps in %.1f ms: %zu modules\n", engine.stepsDone(), times.deriveMs,
                 engine.moduleCount());
  if (options.stats) {  // one line of JSON; milliseconds to the microsecond
    auto ms = [](double v) { return std::round(v * 1000) / 1000; };
    nlohmann::ordered_json stats = {
        {"preprocess_ms", ms(times.preprocessMs)}, {"rewrite_ms", ms(times.rewriteMs)},
        {"compile_ms", ms(times.compileMs)},       {"frontend_ms", ms(times.frontendMs)},
        {"optimize_ms", ms(times.optimizeMs)},     {"codegen_ms", ms(times.codegenMs)},
        {"load_ms", ms(times.loadMs)},             {"derive_ms", ms(times.deriveMs)},
        {"interpret_ms", ms(times.interpretMs)},   {"render_ms", ms(times.renderMs)},
        {"steps", engine.stepsDone()},             {"modules", engine.moduleCount()},
        {"pch_cached", times.pchCached}};
    addRunIdentity(stats, files, &session, options.seed);
    std::fprintf(stderr, "%s\n", stats.dump().c_str());
  }
  return interpretFailed ? 1 : 0;
}

// runOnce, with the better tier (BatchOptions::betterTier) taken from the cache or compiled in
// the background once the run is long.
int runWithTiers(Session& session, const ModelFiles& files, const BatchOptions& options, PhaseTimes& times,
                 std::string& error) {
  FrameWriter frames(options.width, options.height);
  if (options.betterTier <= session.optLevel()) return runOnce(session, files, options, times, frames, nullptr, {}, &error);
  Background<BetterTier> tier;  // its destructor waits for a started build: the cache gets it
  bool started = false;
  // An earlier run's build from the cache: a lookup, no compile.
  if (BetterTier cached = session.betterTierJob(options.betterTier, /*onlyFromCache=*/true)(); cached.code) {
    started = session.installTier(std::move(cached));
    if (started && options.verbose)
      std::fprintf(stderr, "lcjit: -O%d code of an earlier run from the cache\n", session.optLevel());
  }
  auto betweenSteps = [&](double derivedMs) {
    if (!started && derivedMs >= options.tierAfterMs) {
      started = true;
      if (options.verbose)
        std::fprintf(stderr, "lcjit: step %d after %.0f ms: compiling -O%d in the background\n",
                     session.engine().stepsDone(), derivedMs, options.betterTier);
      tier.start(session.betterTierJob(options.betterTier));
    }
    if (started) takeBetterTier(tier, session, options);
    // Not while a better tier compiles: the compiler's pages would fault straight back.
    if (!tier.running()) releaseProgramPagesOnceAt(session.engine().string().size());
  };
  int status = runOnce(session, files, options, times, frames, nullptr, betweenSteps, &error);
  if (tier.running() && options.verbose)
    std::fprintf(stderr, "lcjit: the run is over; the -O%d build finishes for the cache\n", options.betterTier);
  return status;
}

}  // namespace

BatchOptions batchOptions(const Options& o, const CompileTiers& tiers) {
  BatchOptions bo;
  if (!o.outs.empty()) {
    bo.out = o.outs[0];
    bo.moreOuts.assign(o.outs.begin() + 1, o.outs.end());
  }
  if (o.winSize.size() == 2) bo.width = (int)o.winSize[0], bo.height = (int)o.winSize[1];
  bo.fps = o.fps;
  bo.optLevel = tiers.optLevel;
  bo.betterTier = tiers.betterTier;
  bo.tierAfterMs = o.tierAfterMs;
  bo.quiet = o.quiet, bo.verbose = o.verbose, bo.debug = o.debug, bo.stats = o.stats;
  bo.plainErrors = o.lab;
  bo.dumpSteps = o.dumpSteps, bo.dumpInterpreted = o.dumpInterpreted, bo.dumpInterpretedEach = o.dumpInterpretedEach;
  bo.outputFrames = o.outputFrames;
  bo.profile = o.profile;
  bo.runRecord = o.runRecord;
  bo.seed = o.seed;
  return bo;
}

int runBatch(Session& session, const ModelFiles& files, const BatchOptions& options, PhaseTimes& times) {
  std::string error;
  int status = runWithTiers(session, files, options, times, error);
  if (!options.runRecord.empty()) {
    if (status != 0 && error.empty()) error = "the run failed";
    if (auto e = writeRunRecord(options.runRecord, files, &session, {error, options.seed}, times)) {
      report(std::move(e));
      return 1;
    }
  }
  return status;
}


// During a run under --watch, a saved input file stops it: the run is out of date, and model
// code stuck in a loop would otherwise keep the fix from ever loading. A thread watches the
// files meanwhile and interrupts the model code (again every 10 ms: that only stops model code
// while some is running); the changes it saw are the next reload's.
class StopOnChange {
 public:
  StopOnChange(FileMonitor& monitor, runtime::Engine& engine)
      : wake_(::eventfd(0, EFD_CLOEXEC)), thread_([this, &monitor, &engine] {
          while (!done_) {
            struct pollfd fds[2] = {{monitor.fd(), POLLIN, 0}, {wake_, POLLIN, 0}};
            ::poll(fds, 2, 10);
            if (done_) break;
            std::vector<std::string> changed = monitor.poll(0);
            if (!changed.empty()) {
              changed_.insert(changed_.end(), changed.begin(), changed.end());
              stopped_ = true;
            }
            if (stopped_) engine.interrupt();
          }
        }) {}
  ~StopOnChange() {
    if (thread_.joinable()) finish();
    if (wake_ >= 0) ::close(wake_);
  }
  // The changes seen during the run, once it is over (wakes the thread: no wait).
  std::vector<std::string> finish() {
    done_ = true;
    uint64_t one = 1;
    if (wake_ >= 0) (void)!::write(wake_, &one, sizeof one);
    thread_.join();
    return std::move(changed_);
  }
  const std::atomic<bool>* stopped() const { return &stopped_; }

 private:
  int wake_;
  std::atomic<bool> done_{false}, stopped_{false};
  std::vector<std::string> changed_;
  std::thread thread_;
};

int watchBatch(Session& session, const ModelFiles& files, const BatchOptions& options, PhaseTimes first) {
  FrameWriter frames(options.width, options.height);  // one headless renderer for every reload
  FileMonitor monitor;
  std::vector<std::string> changedDuringRun;
  auto run = [&](const BatchOptions& o, PhaseTimes& t) {
    StopOnChange stop(monitor, session.engine());
    int status = runOnce(session, files, o, t, frames, stop.stopped());
    changedDuringRun = stop.finish();
    return status;
  };
  std::vector<std::string> watched;
  auto watchInputs = [&] {
    const runtime::DrawingFiles none;
    std::vector<std::string> now = watchedFiles(files, session.loaded() ? session.drawing() : none);
    if (now == watched) return;
    watched = std::move(now);
    if (!monitor.watch(watched)) std::fprintf(stderr, "lcjit: file monitoring: %s\n", monitor.error().c_str());
  };
  watchInputs();
  // A model that failed to load or run still gets watched, for the fix.
  if (session.loaded()) run(options, first);
  if (!options.quiet) std::fprintf(stderr, "lcjit: watching %s and its input files\n", files.lsystem.c_str());

  // The second tier compiles on another thread while the -O0 code serves the runs.
  Background<BetterTier> tier;
  auto startTier = [&] {
    if (options.betterTier > session.optLevel() && session.loaded()) tier.start(session.betterTierJob(options.betterTier));
  };
  startTier();

  for (int reload = 0;;) {
    std::vector<std::string> changed =
        changedDuringRun.empty() ? monitor.poll(tier.running() ? 20 : -1) : std::exchange(changedDuringRun, {});
    takeBetterTier(tier, session, options);
    if (changed.empty()) continue;
    auto t0 = Clock::now();
    std::optional<ReloadParts> parts = partsFor(actionsForChanges(changed, RefreshMode::Continuous));
    if (!parts) continue;
    if (!session.loaded()) parts = ReloadParts::all();
    ++reload;
    std::string names;
    for (const std::string& c : changed) names += (names.empty() ? "" : ", ") + std::filesystem::path(c).filename().string();
    PhaseTimes times;
    if (auto e = session.load(files, options.optLevel, times, *parts)) {
      std::string shown = withSourceLines(llvm::toString(std::move(e)));
      std::fprintf(stderr, "%s\n", options.plainErrors ? inPlainLanguage(shown).c_str() : shown.c_str());
      std::fprintf(stderr, "lcjit: reload %d (%s) failed; the last good model stays\n", reload, names.c_str());
      continue;
    }
    BatchOptions quietRun = options;
    quietRun.stats = false;
    int status = run(quietRun, times);
    double totalMs = support::msSince(t0);
    std::string compiled = !parts->lsystem     ? "re-read"
                           : times.objectCached ? fmtMs("-O%d code from the cache in %.1f ms", session.optLevel(), times.compileMs)
                                                : fmtMs("compiled -O%d in %.1f ms", session.optLevel(), times.compileMs) +
                                                      (times.productionsCompiled < 0
                                                           ? std::string()
                                                           : fmtMs(" (only the %d changed production%s)", times.productionsCompiled,
                                                                   times.productionsCompiled == 1 ? "" : "s")) +
                                                      fmtMs(" (frontend %.1f", times.frontendMs) + (times.frontendBegunAhead ? " set up ahead" : "") +
                                                      fmtMs(", optimize %.1f", times.optimizeMs) +
                                                      fmtMs(", codegen %.1f", times.codegenMs) +
                                                      fmtMs(", load %.1f)", times.loadMs);
    if (status == 2)
      std::fprintf(stderr, "lcjit: reload %d (%s): %s; its run stopped for a newer change\n", reload, names.c_str(),
                   compiled.c_str());
    else if (status == 1)  // the run's error is above; what it would have written was not
      std::fprintf(stderr, "lcjit: reload %d (%s): %s; the run failed after %d steps%s%s; %.1f ms in all\n", reload,
                   names.c_str(), compiled.c_str(), session.engine().stepsDone(),
                   options.out.empty() ? "" : ", nothing written: ", options.out.empty() ? "" : (options.out + " is the last good run's").c_str(),
                   totalMs);
    else
      std::fprintf(stderr, "lcjit: reload %d (%s): %s, derived %d steps in %.1f ms%s%s; %.1f ms in all\n", reload,
                   names.c_str(), compiled.c_str(), session.engine().stepsDone(), times.deriveMs,
                   options.out.empty() ? "" : ", wrote ", options.out.c_str(), totalMs);
    if (parts->lsystem) startTier();
    watchInputs();  // the view file may name new surfaces, meshes or textures
  }
}

}  // namespace lcjit::app
