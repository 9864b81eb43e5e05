// lcjit's command line: lpfg's options (single dash, as lpfg spells them) plus lcjit's own
// (--stats, -O, --emit-cpp, --watch, --lab, the limits of docs/faults.md), and `lcjit repl [files]
// model.l`, the REPL (Repl.h). Thin: parsing here, the work in Session, Batch, the REPL and the runtime.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include "runtime/turtle/Drawing.h"
#include "runtime/Engine.h"
#include "app/Batch.h"
#include "app/Frame.h"
#include "app/PlainErrors.h"
#include "repl/Repl.h"
#include "runtime/ModelGuard.h"
#include "runtime/Termination.h"
#if LCJIT_HAVE_WINDOW
#include "app/Interactive.h"
#include "viewer/Window.h"
#endif
#include "app/Session.h"

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

}  // namespace

int main(int argc, char** argv) {
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
  app.add_option("--out", bo.out,
                 "(-out) output file: .str/.txt string, .strb binary string, .png/.jpg/.bmp picture, "
                 ".obj/.ply/.stl/.gltf/.glb/.svg/.ps/.eps/.pdf/.pov geometry");
  app.add_flag("-a", animate, "animate mode: stop at the animation file's first frame (window)");
  app.add_flag("-c", compileOnly,
               "compile the model only (exit 0 if it compiles, 1 if not); the compiled code is cached, so the next "
               "run starts without compiling");
  app.add_flag("-d", bo.debug, "debug: the module count after every step, on stdout");
  app.add_flag("--ds", bo.dumpSteps, "(-ds) print the string after each derivation step");
  app.add_flag("--dtf", bo.dumpInterpreted, "(-dtf) write the final string's turtle commands to <model>.str (lpfg's text)");
  app.add_flag("--dtfes", bo.dumpInterpretedEach, "(-dtfes) the same after every step, to <model>NNNNNNNN.str");
  app.add_flag("-q", bo.quiet, "quiet: no messages");
  app.add_flag("-v", bo.verbose, "verbose: phase timings and sizes on stderr");
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
  app.add_option("-O", bo.optLevel, "optimisation level of model code: 0, 1 (default) or 2")->check(CLI::Range(0, 2));
  app.add_flag("--lab", lab,
               "classroom mode: the window, file monitoring and the REPL at once; nothing written outside the "
               "model's folder (caches in .lcjit-cache there); compile errors in plain language first");
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

  std::vector<std::string> args = normaliseArgs(argc, argv);
  std::reverse(args.begin(), args.end());
  try {
    app.parse(args);
  } catch (const CLI::ParseError& e) {
    // --help exits 0; every usage error exits 1, like every other lcjit error.
    return app.exit(e) == 0 ? 0 : 1;
  }

  if (*repl) {
    if (replSize.size() == 2) replOptions.width = replSize[0], replOptions.height = replSize[1];
    return lcjit::repl::runRepl(replInputs, replOptions);
  }

  // A build without the window behaves as with no display; one without pictures shows the model
  // as its string instead.
  const bool haveDisplay = LCJIT_HAVE_WINDOW && (std::getenv("DISPLAY") || std::getenv("WAYLAND_DISPLAY"));
  const char* shownAs = LCJIT_HAVE_RENDERING ? ".png" : ".str";
  if (inputs.empty()) {
    for (const char* f : {"tree.l", "tree.v", "tree.mat"}) inputs.push_back(std::string(LCJIT_EXAMPLES_DIR) + "/" + f);
    if (bo.out.empty()) bo.out = std::string("tree") + shownAs;
    batch = true;
    if (!bo.quiet)
      std::fprintf(stderr, "lcjit: no model given; %s the built-in example %s\n",
                   LCJIT_HAVE_RENDERING ? "rendering" : "deriving", inputs[0].c_str());
  }

  for (auto& dir : includeDirs) dir = std::filesystem::absolute(dir).lexically_normal().string();
  std::string cacheDir;
  if (lab) {
    // Everything the session writes goes to the model's folder: work there, cache there.
    std::string model;
    for (auto& in : inputs) {
      in = std::filesystem::absolute(in).lexically_normal().string();
      if (std::filesystem::path(in).extension() == ".l") model = in;
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
      return lcjit::repl::runRepl(inputs, lab);
    }
    if (!batch && !haveDisplay) {  // no display: keep writing MODEL.png instead
      watch = batch = true;
      if (bo.out.empty() && !model.empty()) bo.out = std::filesystem::path(model).stem().string() + shownAs;
    }
  }
  auto files = lcjit::app::classifyInputs(inputs);
  if (!files) {
    std::fprintf(stderr, "%s\n", llvm::toString(files.takeError()).c_str());
    return 1;
  }
  files->includeDirs.insert(files->includeDirs.begin(), includeDirs.begin(), includeDirs.end());
  // Ctrl-C interrupts model code (a model in an endless loop) rather than lcjit; SIGTERM and
  // SIGHUP clean up (environmental programs) before lcjit ends. Before anything compiles: LLVM's
  // handlers then come second (runtime/ModelGuard.cpp, claim).
  lcjit::runtime::interruptModelCodeOnSigint();
  lcjit::runtime::installTerminationHandlers();
  auto session = lcjit::app::Session::create(cacheDir, files->languageStandard);
  if (!session) {
    std::fprintf(stderr, "lcjit: %s\n", llvm::toString(session.takeError()).c_str());
    return 1;
  }
  if (!(*session)->cacheWarning().empty()) std::fprintf(stderr, "lcjit: warning: %s\n", (*session)->cacheWarning().c_str());
  limits.maxModules = maxModules;
  limits.maxMemory = maxMemory;
  (*session)->setLimits(limits);
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
  if ((watch || window) && app.count("-O") == 0) bo.optLevel = 0, bo.betterTier = 2;
  // Edits are coming: every compile sets up the next one's front end ahead.
  const bool watchedWindow = window && !rmode.empty() && rmode != "expl";
  (*session)->setEditedLive(watch || watchedWindow);
  lcjit::app::PhaseTimes times;
  if (emitCpp) {
    // Show the rewritten model even when it does not compile.
    if (auto e = (*session)->load(*files, bo.optLevel, times)) llvm::consumeError(std::move(e));
    std::fputs((*session)->generatedCpp().c_str(), stdout);
  }
  if (auto e = (*session)->load(*files, bo.optLevel, times)) {
    std::string text = llvm::toString(std::move(e));
    std::fprintf(stderr, "%s\n", lab ? lcjit::app::inPlainLanguage(lcjit::app::withSourceLines(text)).c_str() : text.c_str());
    if (!watch || emitCpp || compileOnly) return 1;  // --watch waits for the fix
  }
  if (emitCpp || compileOnly) return 0;
  if (!batch && bo.out.empty()) {
#if LCJIT_HAVE_WINDOW
    if (haveDisplay) {
      lcjit::viewer::WindowOptions w;
      if (winSize.size() == 2) w.width = (int)winSize[0], w.height = (int)winSize[1];
      if (winPos.size() == 2) w.position = std::make_pair((int)winPos[0], (int)winPos[1]);
      if (winSizeRel.size() == 2) w.relW = winSizeRel[0], w.relH = winSizeRel[1];
      if (winPosRel.size() == 2) w.relX = winPosRel[0], w.relY = winPosRel[1];
      w.borderless = noBorder;
      w.title = "lcjit: " + std::filesystem::path(files->lsystem).filename().string();
      lcjit::app::InteractiveOptions io;
      io.optLevel = bo.optLevel;
      io.betterTier = bo.betterTier;
      io.plainErrors = lab;
      io.quiet = bo.quiet;
      if (!rmode.empty()) io.refresh = *lcjit::app::parseRefreshMode(rmode);
      io.animate = animate;
      io.verbose = bo.verbose;
      io.debug = bo.debug;
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
