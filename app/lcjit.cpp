// lcjit's command line: lpfg's options (single dash, as lpfg spells them) plus lcjit's own
// (--stats, -O, --emit-cpp, --watch, --lab, --sandbox, the limits of docs/faults.md), `lcjit repl
// [files] model.l`, the REPL (Repl.h), and `lcjit sweep`, parameter studies (Sweep.h). Thin: parsing
// here, the work in Session, Batch, Sandbox, the REPL, Sweep and the runtime.
#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include "runtime/turtle/Drawing.h"
#include "runtime/Engine.h"
#include "app/batch/Batch.h"
#include "app/common/Frame.h"
#include "app/common/FrameSequence.h"
#include "app/common/PlainErrors.h"
#include "app/common/RunRecord.h"
#include "app/sandbox/Sandbox.h"
#include "app/sandbox/SandboxWindow.h"
#include "app/sweep/Sweep.h"
#include "repl/Repl.h"
#include "runtime/ModelGuard.h"
#include "runtime/Termination.h"
#if LCJIT_HAVE_WINDOW
#include "app/window/Interactive.h"
#include "viewer/Window.h"
#endif
#include "app/session/Session.h"
#include <llvm/Config/llvm-config.h>

namespace {

// lpfg's options are multi-letter with one dash; CLI11 wants two for long names.
std::vector<std::string> normaliseArgs(int argc, char** argv) {
  static const std::set<std::string> lpfgLong = {"-out", "-ds", "-dtf", "-dtfes", "-rmode", "-wnb", "-wp", "-wpr", "-wr",
                                                 "-cleanEA20", "-cn", "-dll", "-lp", "-wnm", "-tablet", "-timer",
                                                 "-timed"};
  std::vector<std::string> out;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    out.push_back(lpfgLong.count(a) ? "-" + a : a);
  }
  return out;
}

// The command line of a sandboxed run's child (Sandbox.h): the options that shape one batch run,
// with absolute paths, since the child works in the model's folder.
std::vector<std::string> childArgs(const std::vector<std::string>& inputs, const lcjit::app::BatchOptions& bo,
                                   bool explicitO, const std::vector<float>& winSize, bool compileOnly, bool emitCpp,
                                   bool cleanEA, double environmentTimeout, const lcjit::runtime::EngineLimits& limits,
                                   const std::vector<std::string>& includeDirs, bool plainErrors,
                                   const std::vector<std::string>& overrides, std::optional<uint64_t> seed) {
  namespace fs = std::filesystem;
  std::vector<std::string> a;
  if (compileOnly) a.push_back("-c");
  if (emitCpp) a.push_back("--emit-cpp");
  if (!compileOnly && !emitCpp) a.push_back("-b");
  if (!bo.out.empty()) a.insert(a.end(), {"--out", fs::absolute(bo.out).lexically_normal().string()});
  if (winSize.size() == 2) a.insert(a.end(), {"-w", std::to_string((int)winSize[0]), std::to_string((int)winSize[1])});
  a.insert(a.end(), {"--fps", std::to_string(bo.fps)});
  if (explicitO) a.insert(a.end(), {"-O", std::to_string(bo.optLevel)});
  for (auto [on, flag] : {std::pair{bo.debug, "-d"}, {bo.dumpSteps, "--ds"}, {bo.dumpInterpreted, "--dtf"},
                          {bo.dumpInterpretedEach, "--dtfes"}, {bo.outputFrames, "--output-frames"}, {bo.quiet, "-q"}, {bo.verbose, "-v"},
                          {bo.stats, "--stats"}, {cleanEA, "--cleanEA20"}, {plainErrors, "--plain-errors"}})
    if (on) a.push_back(flag);
  char number[64];
  std::snprintf(number, sizeof number, "%.17g", environmentTimeout);
  a.insert(a.end(), {"--environment-timeout", number});
  a.insert(a.end(), {"--max-modules", std::to_string(limits.maxModules), "--max-memory", std::to_string(limits.maxMemory)});
  if (limits.timeLimit > 0) {
    std::snprintf(number, sizeof number, "%.17g", limits.timeLimit);
    a.insert(a.end(), {"--time-limit", number});
  }
  for (const std::string& dir : includeDirs) a.insert(a.end(), {"-I", dir});
  for (const std::string& o : overrides) a.insert(a.end(), {"-D", o});
  if (seed) a.insert(a.end(), {"--seed", std::to_string(*seed)});
  for (const std::string& in : inputs) a.push_back(fs::absolute(in).lexically_normal().string());
  return a;
}

int lcjitMain(int argc, char** argv, int& reportFd);

}  // namespace

// A sandboxed run's child tells its parent how it ended (a death by a signal tells nothing).
int main(int argc, char** argv) {
  int reportFd = -1;
  int status = lcjitMain(argc, argv, reportFd);
  if (reportFd >= 0) lcjit::app::reportStatus(reportFd, status);
  return status;
}

namespace {
int lcjitMain(int argc, char** argv, int& reportFd) {
  CLI::App app{"lcjit: a JIT-compiled interpreter of L+C (lpfg's plant-modelling language)", "lcjit"};
  bool batch = false, animate = false, compileOnly = false, emitCpp = false, watch = false, lab = false;
  lcjit::app::BatchOptions bo;  // what a batch run does: the options below fill it in
  std::string rmode, dll, libPath;
  lcjit::runtime::EngineLimits limits;
  uint64_t maxModules = limits.maxModules, maxMemory = limits.maxMemory;
  std::vector<float> winSize, winPos, winPosRel, winSizeRel;
  bool noBorder = false, cleanEA = false, cn = false, noMessageLog = false, tablet = false, timer = false;
  std::vector<std::string> inputs;

  app.add_flag("-b", batch, "batch mode: no window; derive and write the string to -out");
  std::vector<std::string> outs;
  app.add_option("--out", outs,
                 "(-out, repeatable: each file written after the run) output file: .str/.txt string, .strb binary string, .png/.jpg/.bmp picture, "
                 ".obj/.ply/.stl/.gltf/.glb/.svg/.ps/.eps/.pdf/.pov geometry; with a printf number in its name "
                 "(frame%04d.png) the axiom and every step to numbered files; .mp4/.webm: the axiom and every "
                 "step as a video's frames")
      ->allow_extra_args(false);
  app.add_option("--fps", bo.fps, "frames per second of a video (-out movie.mp4, --record movie.webm)")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  std::string record;
  app.add_option("--record", record,
                 "where the window's Animate > Start recording writes the frames it shows: a video (.mp4, "
                 ".webm) or numbered files (frame%04d.png); default lpfg's MODEL0000.png, MODEL0001.png …");
  app.add_flag("-a", animate, "animate mode: stop at the animation file's first frame (window)");
  app.add_flag("-c", compileOnly,
               "compile the model only (exit 0 if it compiles, 1 if not); the compiled code is cached, so the next "
               "run starts without compiling");
  app.add_flag("-d", bo.debug, "debug: the module count after every step, on stdout");
  app.add_flag("--ds", bo.dumpSteps, "(-ds) print the string after each derivation step");
  app.add_flag("--dtf", bo.dumpInterpreted, "(-dtf) write the final string's turtle commands to <model>.str (lpfg's text)");
  app.add_flag("--dtfes", bo.dumpInterpretedEach, "(-dtfes) the same after every step, to <model>NNNNNNNN.str");
  app.add_flag("--output-frames", bo.outputFrames,
               "batch: write the files the model names with OutputFrame, each once its step is over (lpfg's batch "
               "mode writes none)");
  app.add_flag("-q", bo.quiet, "quiet: no messages");
  app.add_flag("-v", bo.verbose, "verbose: phase timings and sizes on stderr");
  app.set_version_flag("--version", std::string("lcjit " LCJIT_VERSION " (LLVM and Clang " LLVM_VERSION_STRING ")"));
  app.add_option("--rmode", rmode, "(-rmode) refresh mode: expl, cont, trig")->check(CLI::IsMember({"expl", "cont", "trig"}));
  app.add_option("-w", winSize, "window size")->expected(2)->allow_extra_args(false);
  app.add_option("--wp", winPos, "(-wp) window position")->expected(2)->allow_extra_args(false);
  app.add_option("--wpr", winPosRel, "(-wpr) relative window position")->expected(2)->allow_extra_args(false);
  app.add_option("--wr", winSizeRel, "(-wr) relative window size")->expected(2)->allow_extra_args(false);
  app.add_flag("--wnb", noBorder, "(-wnb) window without borders");
  app.add_flag("--wnm", noMessageLog, "(-wnm) accepted: lcjit's window has no message log");
  app.add_flag("--cleanEA20", cleanEA,
               "(-cleanEA20) an EA20 module the environmental program answers has the elements past the answer zeroed");
  double environmentTimeout = 60;
  app.add_option("--environment-timeout", environmentTimeout,
                 "seconds an environmental program (.e) may take to answer one step before it is an error (0: no "
                 "limit)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_flag("--cn", cn, "(-cn) accepted");
  app.add_flag("--tablet", tablet, "(-tablet) accepted: GetTabletStatus() follows the mouse in any case");
  app.add_flag("--timer,--timed", timer, "(-timer, -timed) accepted: --stats gives lcjit's timings");
  app.add_option("--dll,-o", dll,
                 "(-dll/-o) accepted: lcjit compiles the .l file (an lpfg lsys.so cannot be loaded); after -c the "
                 "compiled code comes from lcjit's cache");
  app.add_option("--lp", libPath, "(-lp) accepted");
  app.add_flag("--stats", bo.stats, "print a JSON object of phase timings on stderr");
  app.add_option("--profile", bo.profile,
                 "write how often each production, decomposition and interpretation rule ran and the time it took, "
                 "per step and in total, hottest first, to this JSON file (docs/studio.md)");
  app.add_option("-O", bo.optLevel,
                 "optimisation level of model code: 0, 1 or 2; without it, -O1 code first (-O0 live) and -O2 "
                 "compiled in the background and swapped in when the run is long enough to gain (docs/performance.md)")
      ->check(CLI::Range(0, 2));
  app.add_option("--tier-after", bo.tierAfterMs,
                 "batch runs without -O: compile -O2 in the background once the derivation has run this many "
                 "milliseconds (default 250)")
      ->check(CLI::NonNegativeNumber);
  std::vector<std::string> panels;
  app.add_option("--panel", panels,
                 "open this panel of the window at start (Parameters, Profile); the main menu's Panels "
                 "submenu opens and closes them (docs/studio.md)")
      ->allow_extra_args(false);
  app.add_flag("--lab", lab,
               "classroom mode: the window, file monitoring and the REPL at once; nothing written outside the "
               "model's folder (caches in .lcjit-cache there); compile errors in plain language first; every run "
               "sandboxed where bubblewrap works (--sandbox; the REPL is then off)");
  bool sandbox = false, plainErrors = false;
  lcjit::app::SandboxLimits sandboxLimits;
  app.add_flag("--sandbox", sandbox,
               "run the model (compile, derivation, interpretation, outputs) in a child process under bubblewrap: "
               "no network, the system read-only, writes only in the model's folder and the -out file, no new "
               "processes, limits on memory, CPU time and file size (docs/security.md); batch runs, --watch and "
               "the window (each picture a sandboxed run)");
  app.add_option("--max-cpu", sandboxLimits.cpuSeconds, "--sandbox: the CPU seconds one run may use")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--max-file-size", sandboxLimits.fileSize,
                 "--sandbox: the largest file one run may write (bytes, or 500M, 1G; default 1G)")
      ->transform(CLI::AsSizeValue(false));
  app.add_option("--max-threads", sandboxLimits.threads,
                 "--sandbox: the threads one run may have (its cgroup's pids.max where it has one; default 512)")
      ->check(CLI::Range(uint64_t(16), uint64_t(1) << 20));
  app.add_option("--sandboxed", reportFd, "")->group("");  // the child's side of --sandbox
  int replyFd = -1, toStep = -1;  // a sandboxed window's child (SandboxWindow.h)
  app.add_option("--reply-fd", replyFd, "")->group("");
  app.add_option("--to-step", toStep, "")->group("");
  app.add_flag("--plain-errors", plainErrors, "")->group("");  // --lab's, for the child
  app.add_flag("--watch", watch,
               "batch mode: after the run, re-read, recompile and re-run on every change of an input file");
  app.add_flag("--emit-cpp", emitCpp, "print the C++ generated from the model and exit");
  app.add_option("--max-modules", maxModules, "stop the derivation when the string has more modules")
      ->capture_default_str();
  app.add_option("--max-memory", maxMemory,
                 "stop the derivation when lcjit (or its string) needs more memory (default: half the physical memory)")
      ->transform(CLI::AsSizeValue(false));
  app.add_option("--time-limit", limits.timeLimit,
                 "stop a derivation step (or Start, End, an interpretation) that runs longer, in seconds (default: "
                 "none; Ctrl-C interrupts)")
      ->check(CLI::NonNegativeNumber);
  std::vector<std::string> overrides;
  app.add_option("-D", overrides,
                 "NAME=VALUE: the model's own #define NAME reads VALUE (no recompile of other values: each "
                 "value compiles once, then comes from the cache), and a .vset value NAME is VALUE; an unknown "
                 "NAME is an error listing the names there are (docs/sweeps.md)")
      ->allow_extra_args(false);
  std::optional<uint64_t> seed;
  app.add_option("--seed", seed,
                 "run as member N of an ensemble: the model's random numbers (ran, and the Gillespie choices) "
                 "come from its own seeds mixed with N, a different reproducible stream for each N; without "
                 "it, lpfg's (docs/sweeps.md)")
      // CLI11 would read -1 as 2^64 - 1, a number past that as 2^64 - 1 and 010 as 8; N is what a sweep
      // file's seeds are (decimal digits, 0 to 2^64 - 1), handed on written plainly.
      ->transform(CLI::Validator(
          [](std::string& text) {
            std::optional<uint64_t> n = lcjit::app::seedNumber(text);
            if (!n) return "N must be " + std::string(lcjit::app::kSeedRange) + ", not '" + text + "'";
            text = std::to_string(*n);
            return std::string();
          },
          ""));
  app.add_option("--run-record", bo.runRecord,
                 "batch mode: write what the run was run with and how it ended (the -D values, the seed, the "
                 "inputs' hashes, the error if any) and its measures (module counts, the geometry's size, "
                 "values the model reports with Report) to this JSON file, whatever happens (docs/sweeps.md)");
  bool debugger = false;
  app.add_flag("--debugger", debugger,
               "for gdb: model code at -O0 (unless -O) with full debug information, registered through "
               "the GDB JIT interface, so that `break model.l:LINE`, locals and backtraces work in the .l file "
               "(docs/faults.md)");
  std::vector<std::string> includeDirs;
  app.add_option("-I", includeDirs, "a folder searched for the model's headers (and its C++ sources'), as g++'s -I")
      ->allow_extra_args(false);
  app.add_option("files", inputs, "input files: [view.v anim.a color.map ... helper.cpp] model.l");

  // A subcommand, so that lpfg's own command line stays as it is without it.
  CLI::App* repl = app.add_subcommand("repl", "a prompt for commands and C++ run in the loaded model (docs/repl.md)");
  lcjit::repl::ReplOptions replOptions;
  std::vector<int> replSize;
  std::vector<std::string> replInputs;
  repl->add_option("-O", replOptions.optLevel, "optimisation level of model code: 0, 1 (default) or 2")->check(CLI::Range(0, 2));
  repl->add_option("-w", replSize, "size of :save pictures and of the :view window")->expected(2)->allow_extra_args(false);
  repl->add_option("files", replInputs, "input files: [view.v color.map ...] model.l; none: :load them at the prompt");

  CLI::App* sweep = app.add_subcommand("sweep", "parameter studies: the runs of a YAML sweep file, through GNU "
                                                 "parallel or a Slurm job array, in one table (docs/sweeps.md)");
  sweep->require_subcommand(1);
  lcjit::app::SweepCommand sweepCommand;
  sweepCommand.version = LCJIT_VERSION;
  auto sweepVerb = [&](const char* name, lcjit::app::SweepVerb verb, const char* what) {
    CLI::App* sub = sweep->add_subcommand(name, what);
    sub->callback([&sweepCommand, verb] { sweepCommand.verb = verb; });
    return sub;
  };
  auto outOption = [&](CLI::App* sub) {
    sub->add_option("--out", sweepCommand.dir,
                    "the sweep's folder (default: beside the sweep file, its name without extension + -runs)");
  };
  CLI::App* sweepPlan = sweepVerb("plan", lcjit::app::SweepVerb::Plan,
                                  "write the runs (DIR/tasks.tsv, DIR/ids) and what they were planned from (DIR/sweep.json)");
  sweepPlan->add_option("file", sweepCommand.file, "the sweep file (YAML)")->required();
  outOption(sweepPlan);
  CLI::App* sweepRun = sweepVerb("run", lcjit::app::SweepVerb::Run,
                                 "plan, run the runs not yet run with GNU parallel, and collect their records");
  sweepRun->add_option("file", sweepCommand.file, "the sweep file (YAML)")->required();
  sweepRun->add_option("-j", sweepCommand.jobs, "runs at once")->check(CLI::PositiveNumber)->capture_default_str();
  outOption(sweepRun);
  CLI::App* sweepSlurm = sweepVerb("slurm", lcjit::app::SweepVerb::Slurm, "plan, and write DIR/sweep.sbatch, a Slurm job array");
  sweepSlurm->add_option("file", sweepCommand.file, "the sweep file (YAML)")->required();
  sweepSlurm->add_option("--chunk", sweepCommand.chunk, "runs per array task")->check(CLI::PositiveNumber)->capture_default_str();
  outOption(sweepSlurm);
  CLI::App* sweepTask = sweepVerb("task", lcjit::app::SweepVerb::Task,
                                  "run one planned run (what parallel and Slurm call): RUNDIR/record.json whatever happens");
  sweepTask->add_option("dir", sweepCommand.dir, "the sweep's folder")->required();
  sweepTask->add_option("id", sweepCommand.id, "the run's id (a line of DIR/ids)")->required();
  CLI::App* sweepCollect = sweepVerb("collect", lcjit::app::SweepVerb::Collect,
                                     "merge the runs' records into DIR/results.csv, one row per run");
  sweepCollect->add_option("dir", sweepCommand.dir, "the sweep's folder")->required();

  std::vector<std::string> args = normaliseArgs(argc, argv);
  std::reverse(args.begin(), args.end());
  try {
    app.parse(args);
  } catch (const CLI::ParseError& e) {
    // --help exits 0; every usage error exits 1, like every other lcjit error.
    return app.exit(e) == 0 ? 0 : 1;
  }

  // The sizes of pictures and windows, before anything runs: -w 0 0 would otherwise be a picture
  // of 1 x 1 and a success.
  for (auto [option, size] : {std::pair<const char*, std::vector<float>>{"-w", winSize},
                              {"repl -w", std::vector<float>(replSize.begin(), replSize.end())}})
    if (size.size() == 2)
      if (std::string bad = lcjit::app::badPictureSize(size[0], size[1]); !bad.empty()) {
        std::fprintf(stderr, "lcjit: %s %g %g: %s\n", option, size[0], size[1], bad.c_str());
        return 1;
      }
  if (winSizeRel.size() == 2 && !(winSizeRel[0] > 0 && winSizeRel[1] > 0)) {
    std::fprintf(stderr, "lcjit: --wr %g %g: the size is a fraction of the screen's, above 0\n", winSizeRel[0], winSizeRel[1]);
    return 1;
  }

  if (!outs.empty()) {
    bo.out = outs[0];
    bo.moreOuts.assign(outs.begin() + 1, outs.end());
    for (const std::string& o : bo.moreOuts)
      if (lcjit::app::isFrameSequence(o) || lcjit::app::isFrameSequence(bo.out)) {
        std::fprintf(stderr, "lcjit: -out %s: numbered files and videos are written step by step: give them as the "
                             "only -out\n", o.c_str());
        return 1;
      }
  }
  if (!record.empty() && !lcjit::app::isFrameSequence(record)) {
    std::fprintf(stderr, "lcjit: --record %s: frames go to a video (.mp4, .webm) or to numbered files (a name with "
                         "one printf number, frame%%04d.png)\n", record.c_str());
    return 1;
  }

  if (*sweep) return lcjit::app::runSweep(sweepCommand);

  if (*repl) {
    if (replSize.size() == 2) replOptions.width = replSize[0], replOptions.height = replSize[1];
    return lcjit::repl::runRepl(replInputs, replOptions);
  }

  // A build without the window behaves as with no display; one without pictures shows the model
  // as its string instead.
  const bool haveDisplay = LCJIT_HAVE_WINDOW && (std::getenv("DISPLAY") || std::getenv("WAYLAND_DISPLAY"));
  const char* shownAs = LCJIT_HAVE_RENDERING ? ".png" : ".str";
  if (inputs.empty()) {
    for (const char* f : {"tree.l", "tree.v", "tree.mat"}) inputs.push_back(lcjit::app::examplesDir() + "/" + f);
    if (bo.out.empty()) bo.out = std::string("tree") + shownAs;
    batch = true;
    if (!bo.quiet)
      std::fprintf(stderr, "lcjit: no model given; %s the built-in example %s into %s\n",
                   LCJIT_HAVE_RENDERING ? "rendering" : "deriving", inputs[0].c_str(),
                   std::filesystem::absolute(bo.out).c_str());
  }

  for (auto& dir : includeDirs) dir = std::filesystem::absolute(dir).lexically_normal().string();
  std::string cacheDir;
  bool labWindow = false;  // --lab with a display, sandboxed
  if (lab) {
    // Everything the session writes goes to the model's folder: work there, cache there.
    std::string model;
    for (auto& in : inputs) {
      in = std::filesystem::absolute(in).lexically_normal().string();
      if (lcjit::app::fileKindOf(in) == lcjit::app::FileKind::Model) model = in;
    }
    if (!model.empty()) {
      std::filesystem::current_path(std::filesystem::path(model).parent_path());
      cacheDir = (std::filesystem::path(model).parent_path() / ".lcjit-cache").string();
    }
    if (rmode.empty()) rmode = "cont";
    if (!batch && haveDisplay && !model.empty()) {  // the window, the watcher and the REPL
      lcjit::repl::ReplOptions lab;
      lab.lab = true;
      lab.labFolder = std::filesystem::path(model).parent_path().string();
      if (winSize.size() == 2) lab.width = (int)winSize[0], lab.height = (int)winSize[1];
      if (app.count("-O")) lab.optLevel = bo.optLevel;
      // Where bubblewrap works, the window shows sandboxed runs (below), without the REPL, whose
      // C++ runs in this process; elsewhere the window and the REPL run the model here.
      if (!sandbox && !lcjit::app::sandboxUnavailable().empty()) {
        std::fprintf(stderr, "lcjit: warning: --lab runs without a sandbox: %s; the window and the REPL run the "
                             "model as you, with your files (docs/security.md)\n",
                     lcjit::app::sandboxUnavailable().c_str());
        return lcjit::repl::runRepl(inputs, lab);
      }
      labWindow = true;
    }
    if (!batch && !haveDisplay) {  // no display: keep writing MODEL.png instead
      watch = batch = true;
      if (bo.out.empty() && !model.empty()) bo.out = std::filesystem::path(model).stem().string() + shownAs;
    }
  }
#if LCJIT_HAVE_WINDOW
  // lpfg's window options; the title names the model.
  auto windowOptions = [&] {
    lcjit::viewer::WindowOptions w;
    if (winSize.size() == 2) w.width = (int)winSize[0], w.height = (int)winSize[1];
    if (winPos.size() == 2) w.position = std::make_pair((int)winPos[0], (int)winPos[1]);
    if (winSizeRel.size() == 2) w.relW = winSizeRel[0], w.relH = winSizeRel[1];
    if (winPosRel.size() == 2) w.relX = winPosRel[0], w.relY = winPosRel[1];
    w.borderless = noBorder;
    for (const std::string& in : inputs)
      if (lcjit::app::fileKindOf(in) == lcjit::app::FileKind::Model) w.title = "lcjit: " + std::filesystem::path(in).filename().string();
    return w;
  };
#endif
  // --sandbox, and --lab where it can: this process only starts and watches sandboxed runs. Not
  // even the input files are read here: the model folder's lpfg.mak runs make.
  bool sandboxed = reportFd < 0 && (sandbox || lab);
  if (sandboxed && !lcjit::app::sandboxUnavailable().empty()) {
    if (sandbox) {
      std::fprintf(stderr, "lcjit: --sandbox: %s\n", lcjit::app::sandboxUnavailable().c_str());
      return 1;
    }
    std::fprintf(stderr, "lcjit: warning: --lab runs without a sandbox: %s; the model runs as you, with your files "
                         "(docs/security.md)\n", lcjit::app::sandboxUnavailable().c_str());
    sandboxed = false;
  }
  if (sandboxed && (!bo.runRecord.empty() || !bo.moreOuts.empty())) {  // the sandbox lets its run write one -out
    std::fprintf(stderr, "lcjit: --sandbox's runs write one -out file and no --run-record\n");
    return 1;
  }
  if (sandboxed && debugger) {  // the model would run in the sandbox's process, not the debugged one
    std::fprintf(stderr, "lcjit: --debugger debugs model code in lcjit's own process: not with --sandbox or --lab\n");
    return 1;
  }
  if (sandboxed) {
    namespace fs = std::filesystem;
    [[maybe_unused]] const bool window = !batch && bo.out.empty() && !emitCpp && !compileOnly && haveDisplay;
    if (!batch && bo.out.empty() && !emitCpp && !compileOnly && !window) {
      bo.out = fs::path(inputs.back()).stem().string() + shownAs;
      for (const std::string& in : inputs)
        if (lcjit::app::fileKindOf(in) == lcjit::app::FileKind::Model) bo.out = fs::path(in).stem().string() + shownAs;
      if (!bo.quiet) std::fprintf(stderr, "lcjit: no display; writing %s\n", bo.out.c_str());
    }
    lcjit::app::SandboxPlan plan;
    for (const std::string& in : inputs)
      if (lcjit::app::fileKindOf(in) == lcjit::app::FileKind::Model) plan.model = in;
    if (plan.model.empty()) {
      std::fprintf(stderr, "error: no L-system file (.l) given\n");
      return 1;
    }
    plan.out = bo.out;
    plan.modelFolder = fs::weakly_canonical(fs::absolute(plan.model).lexically_normal().parent_path()).string();
    if (auto e = lcjit::app::checkSandboxFolder(plan.modelFolder, "the model's folder", true)) {
      std::fprintf(stderr, "%s\n", llvm::toString(std::move(e)).c_str());
      return 1;
    }
    for (const std::string& in : inputs)
      if (auto e = lcjit::app::checkSandboxInput(in, plan.modelFolder)) {
        std::fprintf(stderr, "%s\n", llvm::toString(std::move(e)).c_str());
        return 1;
      }
    // What needs a process of its own cannot run in the sandbox, which starts none.
    if (fs::exists(fs::path(plan.modelFolder) / "lpfg.mak")) {
      std::fprintf(stderr, "%s: error: lcjit reads lpfg.mak with make, a program, and a sandboxed run starts none "
                           "(docs/security.md)\n", (fs::path(plan.modelFolder) / "lpfg.mak").c_str());
      return 1;
    }
    for (const std::string& in : inputs)
      if (lcjit::app::fileKindOf(in) == lcjit::app::FileKind::Environment) {
        std::fprintf(stderr, "%s: error: an environmental program is a process of its own, and a sandboxed run "
                             "starts none (docs/security.md)\n", in.c_str());
        return 1;
      }
    // The sandbox binds paths as they are: the child names them the same way, links resolved.
    auto resolved = [](const std::string& p) { return fs::weakly_canonical(fs::absolute(p)).string(); };
    if (!bo.out.empty()) {
      if (auto e = lcjit::app::checkSandboxOutput(bo.out, plan.modelFolder)) {
        std::fprintf(stderr, "%s\n", llvm::toString(std::move(e)).c_str());
        return 1;
      }
      plan.outputFile = bo.out = resolved(bo.out);
    }
    std::vector<std::string> resolvedInputs;
    for (const std::string& in : inputs) resolvedInputs.push_back(resolved(in));
    plan.readable = resolvedInputs;
    std::vector<std::string> folders = includeDirs;
    for (const char* var : {"CPLUS_INCLUDE_PATH", "CPATH", "C_INCLUDE_PATH"})
      if (const char* v = std::getenv(var)) {
        std::stringstream list(v);
        for (std::string dir; std::getline(list, dir, ':');)
          if (!dir.empty()) folders.push_back(fs::absolute(dir).lexically_normal().string());
      }
    for (const std::string& dir : folders) {
      if (auto e = lcjit::app::checkSandboxInput(dir, plan.modelFolder, true)) {
        std::fprintf(stderr, "%s\n", llvm::toString(std::move(e)).c_str());
        return 1;
      }
      if (auto e = lcjit::app::checkSandboxFolder(dir, "the include folder", false)) {
        std::fprintf(stderr, "%s\n", llvm::toString(std::move(e)).c_str());
        return 1;
      }
      plan.readable.push_back(resolved(dir));
    }
    // The child works in the model's folder: it gets -I as the sandbox shows them, resolved.
    std::vector<std::string> childIncludeDirs;
    for (const std::string& dir : includeDirs) childIncludeDirs.push_back(resolved(dir));
    limits.maxModules = maxModules;
    limits.maxMemory = maxMemory;
    // Address space, not resident memory: the compiler and the threads reserve more than they
    // use; --max-memory (resident) is the child's guard's, with its messages.
    sandboxLimits.memory = maxMemory + (uint64_t(2) << 30);
    // All it holds, counted by the kernel where the run has a cgroup: --max-memory and the
    // compiler's room (a compile's peak is some 200 MB).
    sandboxLimits.heldMemory = maxMemory + (uint64_t(1) << 30);
    plan.limits = sandboxLimits;
    if (bo.verbose) {
      const std::string& noCgroup = lcjit::app::sandboxCgroupUnavailable();
      std::fprintf(stderr, "lcjit: --sandbox: %s\n",
                   noCgroup.empty() ? "each run has a cgroup of its own (memory held, threads)"
                                    : ("no cgroup for a run (" + noCgroup + "): memory is bounded by the address space "
                                       "and the seccomp filter, threads by RLIMIT_NPROC (docs/security.md)").c_str());
    }
    plan.args = childArgs(resolvedInputs, bo, app.count("-O") > 0, winSize, compileOnly, emitCpp, cleanEA,
                          environmentTimeout, limits, childIncludeDirs, lab, overrides, seed);
#if LCJIT_HAVE_WINDOW
    if (window) {
      plan.replyLimit = maxMemory;  // the picture is held as the child held it
      lcjit::app::InteractiveOptions io;
      io.quiet = bo.quiet;
      io.verbose = bo.verbose;
      io.plainErrors = lab;
      io.animate = animate;
      if (!rmode.empty()) io.refresh = *lcjit::app::parseRefreshMode(rmode);
      if (labWindow && !bo.quiet)
        std::fprintf(stderr, "lcjit: --lab: the window shows runs made in a sandbox; every run is sandboxed "
                             "(docs/security.md); the REPL, whose C++ would run outside it, is off\n");
      return lcjit::app::runSandboxedWindow(plan, windowOptions(), io);
    }
#endif
    if (watch && !emitCpp && !compileOnly) return lcjit::app::watchSandboxed(plan, bo.quiet);
    return lcjit::app::runSandboxedBatch(plan);
  }
  if (reportFd >= 0) {
    lcjit::app::endOnSignals();
    if (!lcjit::app::refuseExec()) {
      std::fprintf(stderr, "lcjit: --sandbox: the seccomp filter against execve was refused: %s\n", std::strerror(errno));
      return 1;
    }
    // In the sandbox: caches in the model's folder, the only place this process may write and
    // one that no other model's run shares (docs/security.md).
    for (const std::string& in : inputs)
      if (lcjit::app::fileKindOf(in) == lcjit::app::FileKind::Model)
        cacheDir = (std::filesystem::path(in).parent_path() / ".lcjit-cache").string();
    lab = lab || plainErrors;
    bo.progress = [reportFd](int step) { lcjit::app::reportProgress(reportFd, step); };
    // A cache file past --max-file-size (the compiled header is some MB) fails to be written and
    // costs the cache only; from the run on, such a file ends the run (the parent says why).
    std::signal(SIGXFSZ, SIG_IGN);
  }
  // Ctrl-C interrupts model code (a model in an endless loop) rather than lcjit; SIGTERM and
  // SIGHUP clean up (environmental programs, lpfg.mak's make) before lcjit ends. Before anything
  // compiles: LLVM's handlers then come second (runtime/ModelGuard.cpp, claim); before the
  // model's lpfg.mak is read (classifyInputs), whose make a crash must not leave running.
  lcjit::runtime::interruptModelCodeOnSigint();
  lcjit::runtime::installTerminationHandlers();
  auto files = lcjit::app::classifyInputs(inputs);
  if (!files) {
    std::fprintf(stderr, "%s\n", llvm::toString(files.takeError()).c_str());
    return 1;
  }
  files->includeDirs.insert(files->includeDirs.begin(), includeDirs.begin(), includeDirs.end());
  for (const std::string& o : overrides) {
    size_t eq = o.find('=');
    if (eq == 0 || eq == std::string::npos) {
      std::fprintf(stderr, "lcjit: -D %s: give NAME=VALUE\n", o.c_str());
      return 1;
    }
    files->overrides.emplace_back(o.substr(0, eq), o.substr(eq + 1));
  }
  bo.seed = seed;
  auto session = lcjit::app::Session::create(cacheDir, files->languageStandard, debugger);
  if (!session) {
    std::fprintf(stderr, "lcjit: %s\n", llvm::toString(session.takeError()).c_str());
    return 1;
  }
  struct LeaveAtExit {
    std::unique_ptr<lcjit::app::Session>& session;
    ~LeaveAtExit() { lcjit::app::Session::leaveAtExit(std::move(session)); }
  } leaveAtExit{*session};
  if (!(*session)->cacheWarning().empty()) std::fprintf(stderr, "lcjit: warning: %s\n", (*session)->cacheWarning().c_str());
  limits.maxModules = maxModules;
  limits.maxMemory = maxMemory;
  (*session)->setLimits(limits);
  (*session)->setEnsembleMember(seed);
  {
    lcjit::app::Session::EnvironmentSettings env;
    env.cleanEA20 = cleanEA;
    env.program.answerSeconds = environmentTimeout;
    env.start = !compileOnly && !emitCpp;
    if (bo.verbose) env.program.log = [](const std::string& line) { std::fprintf(stderr, "lcjit: %s\n", line.c_str()); };
    (*session)->setEnvironmentSettings(env);
  }
  // Live coding (--watch, the window) without -O: a quick -O0 build first, then -O2 compiled in
  // the background and swapped in (two tiers).
  const bool window = !batch && bo.out.empty() && haveDisplay && !emitCpp && !compileOnly;
  // A batch run without -O: -O1 code, and -O2 compiled in the background once the run has shown
  // it is long, or taken from the cache if an earlier run compiled it (Batch.h).
  if (debugger) {  // one tier, each statement where the debugger expects it
    if (app.count("-O") == 0) bo.optLevel = 0;
  } else if ((watch || window) && app.count("-O") == 0) {
    bo.optLevel = 0, bo.betterTier = 2;
  } else if (app.count("-O") == 0 && !compileOnly && !emitCpp) {
    bo.betterTier = 2;
  }
  (*session)->setQuickLevelBySize(app.count("-O") == 0);
  // Edits are coming: every compile sets up the next one's front end ahead.
  const bool watchedWindow = window && !rmode.empty() && rmode != "expl";
  (*session)->setEditedLive(watch || watchedWindow);
  // The window (and a sandboxed window's child, which draws for it) shows a model without colour
  // files in colours (docs/editors.md); batch pictures stay lpfg's, which the comparison with
  // lpfg relies on.
  (*session)->setLcjitColours(window || replyFd >= 0);
  lcjit::app::PhaseTimes times;
  if (emitCpp) {
    // Show the rewritten model even when it does not compile.
    if (auto e = (*session)->load(*files, bo.optLevel, times)) llvm::consumeError(std::move(e));
    std::fputs((*session)->generatedCpp().c_str(), stdout);
  }
  llvm::Error loaded = (*session)->load(*files, bo.optLevel, times);
  if (reportFd >= 0) lcjit::app::endOnSignals(SIGXFSZ);
  if (reportFd >= 0) {  // what the parent's --watch watches
    const lcjit::runtime::DrawingFiles none;
    for (const std::string& f : lcjit::app::watchedFiles(*files, (*session)->loaded() ? (*session)->drawing() : none))
      lcjit::app::reportInput(reportFd, f);
  }
  if (replyFd >= 0) {  // a sandboxed window's run: the picture goes back to the window
    lcjit::app::WindowAnswerOptions wo;
    wo.replyFd = replyFd;
    wo.toStep = toStep;
    wo.quiet = bo.quiet;
    wo.plainErrors = lab;
    wo.debug = bo.debug;
    wo.progress = bo.progress;
    return lcjit::app::answerWindow(**session, *files, std::move(loaded), wo);
  }
  if (auto e = std::move(loaded)) {
    std::string message = llvm::toString(std::move(e));
    // As g++ prints them for lpfg, and as --watch prints a failed reload: the line and a caret.
    std::string text = lcjit::app::withSourceLines(message);
    std::fprintf(stderr, "%s\n", lab ? lcjit::app::inPlainLanguage(text).c_str() : text.c_str());
    if (!bo.runRecord.empty() && !watch)
      if (auto r = lcjit::app::writeRunRecord(bo.runRecord, *files, session->get(), {message, seed}, times))
        std::fprintf(stderr, "%s\n", llvm::toString(std::move(r)).c_str());
    if (!watch || emitCpp || compileOnly) return 1;  // --watch waits for the fix
  }
  if (emitCpp || compileOnly) return 0;
  if (!batch && bo.out.empty()) {
#if LCJIT_HAVE_WINDOW
    if (haveDisplay) {
      lcjit::viewer::WindowOptions w = windowOptions();
      lcjit::app::InteractiveOptions io;
      io.optLevel = bo.optLevel;
      io.betterTier = bo.betterTier;
      io.plainErrors = lab;
      io.quiet = bo.quiet;
      if (!rmode.empty()) io.refresh = *lcjit::app::parseRefreshMode(rmode);
      io.animate = animate;
      io.verbose = bo.verbose;
      io.debug = bo.debug;
      io.panels = panels;
      io.record = record;
      io.fps = bo.fps;
      return lcjit::app::runInteractive(**session, *files, w, io);
    }
#endif
    // No display: show the model as a picture beside it instead.
    bo.out = std::filesystem::path(files->lsystem).stem().string() + shownAs;
    if (!bo.quiet)
      std::fprintf(stderr, "lcjit: %s; writing %s\n", LCJIT_HAVE_WINDOW ? "no display" : "this build has no window",
                   bo.out.c_str());
  }
  if (winSize.size() == 2) bo.width = (int)winSize[0], bo.height = (int)winSize[1];
  bo.plainErrors = lab;
  if (watch) return lcjit::app::watchBatch(**session, *files, bo, times);
  return lcjit::app::runBatch(**session, *files, bo, times);
}

}  // namespace
