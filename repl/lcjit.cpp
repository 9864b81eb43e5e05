// lcjit's command line: lpfg's options (single dash, as lpfg spells them) plus lcjit's own
// (--stats, -O, --emit-cpp, the limits of docs/faults.md). Thin: parsing here, the work in
// Session and the runtime.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <string>
#include <vector>

#include "CLI/CLI.hpp"
#include "Drawing.h"
#include "Engine.h"
#include "Frame.h"
#include "Interactive.h"
#include "ModelGuard.h"
#include "Window.h"
#include "Session.h"

namespace {

// lpfg's options are multi-letter with one dash; CLI11 wants two for long names.
std::vector<std::string> normaliseArgs(int argc, char** argv) {
  static const std::set<std::string> lpfgLong = {"-out", "-ds", "-dtf", "-dtfes", "-rmode", "-wnb", "-wp", "-wpr", "-wr",
                                                 "-cleanEA20", "-cn", "-dll", "-lp"};
  std::vector<std::string> out;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    out.push_back(lpfgLong.count(a) ? "-" + a : a);
  }
  return out;
}

// -dtf/-dtfes files go to the working folder (lpfg runs in the object's folder, so the same place
// for its users) rather than beside a model that may live in a read-only tree.
std::string stemInWorkingFolder(const std::string& p) { return std::filesystem::path(p).stem().string(); }

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"lcjit: a JIT-compiled interpreter of L+C (lpfg's plant-modelling language)", "lcjit"};
  bool batch = false, animate = false, compileOnly = false, debug = false, quiet = false, verbose = false;
  bool dumpSteps = false, dumpInterpreted = false, dumpInterpretedEach = false, stats = false, emitCpp = false;
  std::string out, rmode, dll, libPath;
  int optLevel = 1;
  lcjit::runtime::EngineLimits limits;
  uint64_t maxModules = limits.maxModules, maxMemory = limits.maxMemory;
  std::vector<float> winSize, winPos, winPosRel, winSizeRel;
  bool noBorder = false, cleanEA = false, cn = false;
  std::vector<std::string> inputs;

  app.add_flag("-b", batch, "batch mode: no window; derive and write the string to -out");
  app.add_option("--out", out,
                 "(-out) output file: .str/.txt string, .strb binary string, .png/.jpg/.bmp picture, "
                 ".obj/.ply/.stl/.gltf/.glb/.svg/.ps/.eps/.pdf/.pov geometry");
  app.add_flag("-a", animate, "animate mode: stop at the animation file's first frame (window)");
  app.add_flag("-c", compileOnly, "compile the model only");
  app.add_flag("-d", debug, "debug: the module count after every step, on stdout");
  app.add_flag("--ds", dumpSteps, "(-ds) print the string after each derivation step");
  app.add_flag("--dtf", dumpInterpreted, "(-dtf) write the final string's turtle commands to <model>.str (lpfg's text)");
  app.add_flag("--dtfes", dumpInterpretedEach, "(-dtfes) the same after every step, to <model>NNNNNNNN.str");
  app.add_flag("-q", quiet, "quiet: no messages");
  app.add_flag("-v", verbose, "verbose: phase timings and sizes on stderr");
  app.add_option("--rmode", rmode, "(-rmode) refresh mode: expl, cont, trig")->check(CLI::IsMember({"expl", "cont", "trig"}));
  app.add_option("-w", winSize, "window size")->expected(2)->allow_extra_args(false);
  app.add_option("--wp", winPos, "(-wp) window position")->expected(2)->allow_extra_args(false);
  app.add_option("--wpr", winPosRel, "(-wpr) relative window position")->expected(2)->allow_extra_args(false);
  app.add_option("--wr", winSizeRel, "(-wr) relative window size")->expected(2)->allow_extra_args(false);
  app.add_flag("--wnb", noBorder, "(-wnb) window without borders");
  app.add_flag("--cleanEA20", cleanEA, "(-cleanEA20) accepted");
  app.add_flag("--cn", cn, "(-cn) accepted");
  app.add_option("--dll,-o", dll, "(-dll/-o) accepted: lcjit keeps compiled code in memory");
  app.add_option("--lp", libPath, "(-lp) accepted");
  app.add_flag("--stats", stats, "print a JSON object of phase timings on stderr");
  app.add_option("-O", optLevel, "optimisation level of model code: 0, 1 (default) or 2")->check(CLI::Range(0, 2));
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
  app.add_option("files", inputs, "input files: [view.v anim.a color.map ...] model.l");

  std::vector<std::string> args = normaliseArgs(argc, argv);
  std::reverse(args.begin(), args.end());
  try {
    app.parse(args);
  } catch (const CLI::ParseError& e) {
    // --help exits 0; every usage error exits 1, like every other lcjit error.
    return app.exit(e) == 0 ? 0 : 1;
  }

  const bool haveDisplay = std::getenv("DISPLAY") || std::getenv("WAYLAND_DISPLAY");
  if (inputs.empty()) {
    for (const char* f : {"tree.l", "tree.v", "tree.mat"}) inputs.push_back(std::string(LCJIT_EXAMPLES_DIR) + "/" + f);
    if (out.empty()) out = "tree.png";
    batch = true;
    if (!quiet) std::fprintf(stderr, "lcjit: no model given; rendering the built-in example %s\n", inputs[0].c_str());
  }

  auto files = lcjit::classifyInputs(inputs);
  if (!files) {
    std::fprintf(stderr, "%s\n", llvm::toString(files.takeError()).c_str());
    return 1;
  }
  auto session = lcjit::Session::create();
  if (!session) {
    std::fprintf(stderr, "lcjit: %s\n", llvm::toString(session.takeError()).c_str());
    return 1;
  }
  limits.maxModules = maxModules;
  limits.maxMemory = maxMemory;
  (*session)->setLimits(limits);
  // Ctrl-C interrupts model code (a model in an endless loop) rather than lcjit.
  lcjit::runtime::interruptModelCodeOnSigint();
  lcjit::PhaseTimes times;
  if (emitCpp) {
    // Show the rewritten model even when it does not compile.
    if (auto e = (*session)->load(*files, optLevel, times)) llvm::consumeError(std::move(e));
    std::fputs((*session)->generatedCpp().c_str(), stdout);
  }
  if (auto e = (*session)->load(*files, optLevel, times)) {
    std::fprintf(stderr, "%s\n", llvm::toString(std::move(e)).c_str());
    return 1;
  }
  if (emitCpp || compileOnly) return 0;
  if (!batch && out.empty()) {
    if (haveDisplay) {
      lcjit::viewer::WindowOptions w;
      if (winSize.size() == 2) w.width = (int)winSize[0], w.height = (int)winSize[1];
      if (winPos.size() == 2) w.position = std::make_pair((int)winPos[0], (int)winPos[1]);
      if (winSizeRel.size() == 2) w.relW = winSizeRel[0], w.relH = winSizeRel[1];
      if (winPosRel.size() == 2) w.relX = winPosRel[0], w.relY = winPosRel[1];
      w.borderless = noBorder;
      w.title = "lcjit: " + std::filesystem::path(files->lsystem).filename().string();
      lcjit::InteractiveOptions io;
      io.optLevel = optLevel;
      io.quiet = quiet;
      if (!rmode.empty()) io.refresh = *lcjit::parseRefreshMode(rmode);
      io.animate = animate;
      io.verbose = verbose;
      io.debug = debug;
      return lcjit::runInteractive(**session, *files, w, io);
    }
    // No display: show the model as a picture beside it instead.
    out = std::filesystem::path(files->lsystem).stem().string() + ".png";
    if (!quiet) std::fprintf(stderr, "lcjit: no display; writing %s\n", out.c_str());
  }
  lcjit::FrameWriter frames(winSize.size() == 2 ? (int)winSize[0] : 800, winSize.size() == 2 ? (int)winSize[1] : 800);

  auto& engine = (*session)->engine();
  lcjit::runtime::EngineHooks hooks;
  if (quiet) hooks.print = [](const char*) {};
  hooks.outputFrame = [&](const char* path) {
    if (auto e = frames.write(path, engine, (*session)->drawing())) std::fprintf(stderr, "%s\n", llvm::toString(std::move(e)).c_str());
  };
  if (!quiet)
    for (const std::string& w : (*session)->warnings()) std::fprintf(stderr, "%s\n", w.c_str());
  if (dumpSteps)
    hooks.afterDerivation = [&](int step) {
      std::printf("After step %d:\n%s", step, engine.text(engine.string()).c_str());
    };
  bool interpretFailed = false;  // -dtfes: an interpretation rule's fault, reported once
  if (dumpInterpretedEach || debug)
    hooks.afterStep = [&](int step) {
      if (debug) std::printf("lcjit: step %d: %zu modules\n", step, engine.moduleCount());  // -d: lpfg's debug output
      if (!dumpInterpretedEach || interpretFailed) return;
      std::string text;
      if (auto e = engine.interpret(nullptr, nullptr, &text)) {
        std::fprintf(stderr, "%s\n", llvm::toString(std::move(e)).c_str());
        interpretFailed = true;
        return;
      }
      char suffix[16];
      std::snprintf(suffix, sizeof suffix, "%08d", step);
      std::ofstream(stemInWorkingFolder(files->lsystem) + suffix + ".str", std::ios::binary) << text;
    };
  if (verbose)
    std::fprintf(stderr, "lcjit: %s: preprocessed in %.1f ms, rewritten in %.1f ms, compiled in %.1f ms (%s)\n",
                 files->lsystem.c_str(), times.preprocessMs, times.rewriteMs, times.compileMs,
                 times.pchCached ? "cached PCH" : "PCH built");
  auto t0 = std::chrono::steady_clock::now();
  if (auto e = engine.run(hooks)) {
    std::fprintf(stderr, "%s\n", llvm::toString(std::move(e)).c_str());
    return 1;
  }
  times.deriveMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

  if (!out.empty()) {
    std::string ext = std::filesystem::path(out).extension().string();
    if (lcjit::isFrameOutput(out)) {
      lcjit::FrameTimes ft;
      if (auto e = frames.write(out, engine, (*session)->drawing(), &ft)) {
        std::fprintf(stderr, "%s\n", llvm::toString(std::move(e)).c_str());
        return 1;
      }
      times.interpretMs = ft.interpretMs;
      times.renderMs = ft.renderMs;
    } else if (ext == ".strb" || ext == ".bin") {
      if (auto e = engine.writeBinary(out)) {
        std::fprintf(stderr, "%s\n", llvm::toString(std::move(e)).c_str());
        return 1;
      }
    } else {
      std::ofstream f(out, std::ios::binary);
      if (!f) {
        std::fprintf(stderr, "%s: error: cannot write file\n", out.c_str());
        return 1;
      }
      f << engine.text(engine.string());
    }
  }
  if (dumpInterpreted) {
    std::string text;
    if (auto e = engine.interpret(nullptr, nullptr, &text)) {
      std::fprintf(stderr, "%s\n", llvm::toString(std::move(e)).c_str());
      return 1;
    }
    std::ofstream(stemInWorkingFolder(files->lsystem) + ".str", std::ios::binary) << text;
  }
  if (verbose)
    std::fprintf(stderr, "lcjit: derived %d steps in %.1f ms: %zu modules\n", engine.stepsDone(), times.deriveMs,
                 engine.moduleCount());
  if (stats) {
    std::fprintf(stderr,
                 "{\"preprocess_ms\": %.3f, \"rewrite_ms\": %.3f, \"compile_ms\": %.3f, \"frontend_ms\": %.3f, "
                 "\"optimize_ms\": %.3f, \"codegen_ms\": %.3f, \"derive_ms\": %.3f, "
                 "\"interpret_ms\": %.3f, \"render_ms\": %.3f, \"steps\": %d, \"modules\": %zu, \"pch_cached\": %s}\n",
                 times.preprocessMs, times.rewriteMs, times.compileMs, times.frontendMs, times.optimizeMs, times.codegenMs,
                 times.deriveMs, times.interpretMs, times.renderMs,
                 engine.stepsDone(),
                 engine.moduleCount(), times.pchCached ? "true" : "false");
  }
  return interpretFailed ? 1 : 0;
}
