// lcjit's driver, as clang-repl's is: parse the command line, pick the mode, run it, and turn
// what went wrong into the exit status (1 for every error, usage errors included). A model run's
// options — lpfg's and lcjit's own — are app/cli/Options.h and what they ask for app/cli/Modes.h;
// the subcommands `lcjit repl [files] model.l` (the REPL, repl/Repl.h) and `lcjit sweep`
// (parameter studies, app/sweep/Sweep.h) are declared here. The work is in the modes' rooms:
// app/batch, app/window, app/sandbox, repl/, app/sweep.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include "app/batch/Batch.h"
#include "app/cfdg/DesignRun.h"
#include "app/session/Languages.h"
#include "app/cli/Modes.h"
#include "app/cli/Options.h"
#include "app/sandbox/Sandbox.h"
#include "app/sandbox/SandboxMode.h"
#include "app/sweep/Sweep.h"
#include "repl/Repl.h"
#include "runtime/ModelGuard.h"
#include "runtime/Termination.h"
#if LCJIT_HAVE_WINDOW
#include "app/cfdg/DesignWindow.h"
#include "app/window/WindowMode.h"
#endif

namespace {

namespace app = lcjit::app;

int failed(llvm::Error e) {
  std::fprintf(stderr, "%s\n", llvm::toString(std::move(e)).c_str());
  return 1;
}

// `lcjit sweep VERB …` (docs/sweeps.md).
void declareSweep(CLI::App& sweep, app::SweepCommand& command) {
  sweep.require_subcommand(1);
  auto verb = [&](const char* name, app::SweepVerb v, const char* what) {
    CLI::App* sub = sweep.add_subcommand(name, what);
    sub->callback([&command, v] { command.verb = v; });
    return sub;
  };
  auto outOption = [&](CLI::App* sub) {
    sub->add_option("--out", command.dir,
                    "the sweep's folder (default: beside the sweep file, its name without extension + -runs)");
  };
  CLI::App* plan = verb("plan", app::SweepVerb::Plan,
                        "write the runs (DIR/tasks.tsv, DIR/ids) and what they were planned from (DIR/sweep.json)");
  plan->add_option("file", command.file, "the sweep file (YAML)")->required();
  outOption(plan);
  CLI::App* run = verb("run", app::SweepVerb::Run,
                       "plan, run the runs not yet run with GNU parallel, and collect their records");
  run->add_option("file", command.file, "the sweep file (YAML)")->required();
  run->add_option("-j", command.jobs, "runs at once")->check(CLI::PositiveNumber)->capture_default_str();
  outOption(run);
  CLI::App* slurm = verb("slurm", app::SweepVerb::Slurm, "plan, and write DIR/sweep.sbatch, a Slurm job array");
  slurm->add_option("file", command.file, "the sweep file (YAML)")->required();
  slurm->add_option("--chunk", command.chunk, "runs per array task")->check(CLI::PositiveNumber)->capture_default_str();
  outOption(slurm);
  CLI::App* task = verb("task", app::SweepVerb::Task,
                        "run one planned run (what parallel and Slurm call): RUNDIR/record.json whatever happens");
  task->add_option("dir", command.dir, "the sweep's folder")->required();
  task->add_option("id", command.id, "the run's id (a line of DIR/ids)")->required();
  CLI::App* collect = verb("collect", app::SweepVerb::Collect,
                           "merge the runs' records into DIR/results.csv, one row per run");
  collect->add_option("dir", command.dir, "the sweep's folder")->required();
}

bool isDesign(const app::Options& options) {
  const app::Language* language = app::languageOf(app::modelOf(options.inputs));
  return language && language->engine == app::EngineKind::ShapeExpansion;
}

// A Context Free design in this process: in the window, or written (batch, --watch, a sandboxed
// run's child).
int runDesignHere(const app::Options& options, const std::string& cacheDir) {
  app::DesignRunOptions design = app::designRunOptions(options, cacheDir);
  if (options.reportFd >= 0)
    design.loaded = [fd = options.reportFd](const std::vector<std::string>& files) { app::reportLoadedFiles(fd, files); };
#if LCJIT_HAVE_WINDOW
  if (app::opensWindow(options))
    return app::runDesignWindow(design, app::windowOptions(options),
                                app::interactiveOptions(options, app::compileTiers(options, true)));
#endif
  return app::runDesign(design);
}

// A run of the model in this process: in batch mode, in the window, or as a sandboxed run's child.
int runHere(app::Options& options, std::string cacheDir) {
  if (options.reportFd >= 0)
    if (auto e = app::startSandboxChild(options, cacheDir)) return failed(std::move(e));
  if (isDesign(options)) return runDesignHere(options, cacheDir);
  // Ctrl-C interrupts model code (a model in an endless loop) rather than lcjit; SIGTERM and
  // SIGHUP clean up (environmental programs, lpfg.mak's make) before lcjit ends. Before anything
  // compiles: LLVM's handlers then come second (runtime/ModelGuard.cpp, claim); before the
  // model's lpfg.mak is read (classifyInputs), whose make a crash must not leave running.
  lcjit::runtime::interruptModelCodeOnSigint();
  lcjit::runtime::installTerminationHandlers();
  auto files = app::modelFiles(options);
  if (!files) return failed(files.takeError());
  const bool window = app::opensWindow(options);
  auto session = app::openSession(options, *files, cacheDir, window);
  if (!session) return failed(session.takeError());
  struct LeaveAtExit {
    std::unique_ptr<app::Session>& session;
    ~LeaveAtExit() { app::Session::leaveAtExit(std::move(session)); }
  } leaveAtExit{*session};
  const app::CompileTiers tiers = app::compileTiers(options, window);
  app::PhaseTimes times;
  if (options.emitCpp) {
    // Show the rewritten model even when it does not compile.
    if (auto e = (*session)->load(*files, tiers.optLevel, times)) llvm::consumeError(std::move(e));
    std::fputs((*session)->generatedCpp().c_str(), stdout);
  }
  llvm::Error loaded = (*session)->load(*files, tiers.optLevel, times);
  if (options.reportFd >= 0) app::reportLoadedInputs(options.reportFd, **session, *files);
  if (options.replyFd >= 0)  // a sandboxed window's run: the picture goes back to the window
    return app::answerWindow(**session, *files, std::move(loaded), app::windowAnswerOptions(options));
  if (auto e = std::move(loaded)) {
    app::reportLoadError(llvm::toString(std::move(e)), options, *files, session->get(), times);
    if (!options.watch || options.emitCpp || options.compileOnly) return 1;  // --watch waits for the fix
  }
  if (options.emitCpp || options.compileOnly) return 0;
#if LCJIT_HAVE_WINDOW
  if (window)
    return app::runInteractive(**session, *files, app::windowOptions(options), app::interactiveOptions(options, tiers));
#endif
  if (!options.batch && options.outs.empty()) {  // no display: the model as a picture beside it
    options.outs = {app::shownIn(files->lsystem)};
    if (!options.quiet)
      std::fprintf(stderr, "lcjit: %s; writing %s\n", LCJIT_HAVE_WINDOW ? "no display" : "this build has no window",
                   options.outs[0].c_str());
  }
  app::BatchOptions bo = app::batchOptions(options, tiers);
  bo.progress = app::childProgress(options);
  if (options.watch) return app::watchBatch(**session, *files, bo, times);
  return app::runBatch(**session, *files, bo, times);
}

int lcjitMain(int argc, char** argv, int& reportFd) {
  CLI::App cli{"lcjit: a JIT-compiled interpreter of L+C (lpfg's plant-modelling language)", "lcjit"};
  app::Options options;
  app::declareOptions(cli, options);
  // Subcommands, so that lpfg's own command line stays as it is without them.
  CLI::App* repl = cli.add_subcommand("repl", "a prompt for commands and C++ run in the loaded model (docs/repl.md)");
  lcjit::repl::ReplOptions replOptions;
  std::vector<int> replSize;
  std::vector<std::string> replInputs;
  repl->add_option("-O", replOptions.optLevel, "optimisation level of model code: 0, 1 (default) or 2")->check(CLI::Range(0, 2));
  repl->add_option("-w", replSize, "size of :save pictures and of the :view window")->expected(2)->allow_extra_args(false);
  repl->add_option("--steps", replOptions.steps,
                   "derive this many steps instead of the model's derivation length (an XL model has none)")
      ->check(CLI::NonNegativeNumber);
  repl->add_option("files", replInputs, "input files: [view.v color.map ...] model.l; none: :load them at the prompt");
  CLI::App* sweep = cli.add_subcommand("sweep", "parameter studies: the runs of a YAML sweep file, through GNU "
                                                "parallel or a Slurm job array, in one table (docs/sweeps.md)");
  app::SweepCommand sweepCommand;
  sweepCommand.version = LCJIT_VERSION;
  declareSweep(*sweep, sweepCommand);

  CLI::App* cfdg = cli.add_subcommand("cfdg", "Context Free's own command line (cfdg 3.4's options): a script "
                                               "written for cfdg works with lcjit cfdg (docs/cfdg.md)");
  app::DesignRunOptions cfdgOptions;
  app::declareCfdgOptions(*cfdg, cfdgOptions);

  try {
    cli.parse(app::argumentsForParse(argc, argv));
  } catch (const CLI::ParseError& e) {
    reportFd = options.reportFd;
    // --help exits 0; every usage error exits 1, like every other lcjit error.
    return cli.exit(e) == 0 ? 0 : 1;
  }
  reportFd = options.reportFd;
  if (auto e = app::checkPictureSize("-w", options.winSize)) return failed(std::move(e));
  if (auto e = app::checkPictureSize("repl -w", std::vector<float>(replSize.begin(), replSize.end())))
    return failed(std::move(e));
  if (auto e = app::checkOptions(options)) return failed(std::move(e));

  if (*sweep) return app::runSweep(sweepCommand);
  if (*cfdg) return app::runDesign(cfdgOptions);
  if (*repl) {
    if (replSize.size() == 2) replOptions.width = replSize[0], replOptions.height = replSize[1];
    return lcjit::repl::runRepl(replInputs, replOptions);
  }

  const std::string cacheDir = app::settleOptions(options);
  if (isDesign(options)) {
    if (options.lab) {  // --lab's window and REPL are an L-system's
      std::fprintf(stderr, "lcjit: --lab runs L-systems; a design runs with --watch (and --sandbox)\n");
      return 1;
    }
    if (!options.sandbox && options.reportFd < 0) return runDesignHere(options, cacheDir);
  }
  const bool labWindow = app::labWindow(options);
  // --lab with a display where bubblewrap does not work: the window and the REPL in this process.
  if (labWindow && !options.sandbox && !app::sandboxUnavailable().empty()) {
    std::fprintf(stderr, "lcjit: warning: --lab runs without a sandbox: %s; the window and the REPL run the "
                         "model as you, with your files (docs/security.md)\n", app::sandboxUnavailable().c_str());
    lcjit::repl::ReplOptions lab;
    lab.lab = true;
    lab.labFolder = std::filesystem::path(app::modelOf(options.inputs)).parent_path().string();
    if (options.winSize.size() == 2) lab.width = (int)options.winSize[0], lab.height = (int)options.winSize[1];
    if (options.optLevel) lab.optLevel = *options.optLevel;
    return lcjit::repl::runRepl(options.inputs, lab);
  }
  // --sandbox, and --lab where it can: this process only starts and watches sandboxed runs.
  if (options.reportFd < 0 && (options.sandbox || options.lab)) {
    if (app::sandboxUnavailable().empty()) return app::runSandboxed(options, labWindow);
    if (options.sandbox) {
      std::fprintf(stderr, "lcjit: --sandbox: %s\n", app::sandboxUnavailable().c_str());
      return 1;
    }
    std::fprintf(stderr, "lcjit: warning: --lab runs without a sandbox: %s; the model runs as you, with your files "
                         "(docs/security.md)\n", app::sandboxUnavailable().c_str());
  }
  return runHere(options, cacheDir);
}

}  // namespace

// A sandboxed run's child tells its parent how it ended (a death by a signal tells nothing).
int main(int argc, char** argv) {
  int reportFd = -1;
  int status = lcjitMain(argc, argv, reportFd);
  if (reportFd >= 0) app::reportStatus(reportFd, status);
  return status;
}
