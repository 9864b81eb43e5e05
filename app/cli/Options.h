// lcjit's command line for a model run — lpfg's options (single dash, as lpfg spells them) and
// lcjit's own — as one struct. declareOptions spells each option once, for CLI11, and says there
// whether a sandboxed run's child takes it; childArguments writes the ones it takes back from the
// struct, so that an option cannot be declared and forgotten by the sandbox (Sandbox.h).
// The subcommands (`lcjit repl`, `lcjit sweep`) have options of their own, declared by the driver.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <llvm/Support/Error.h>

#include "app/common/Defaults.h"
#include "runtime/Engine.h"

namespace CLI {
class App;
}

namespace lcjit::app {

struct Options {
  // What the run does and on what.
  bool batch = false;        // -b: no window
  bool animate = false;      // -a: the window starts at the animation file's first frame
  bool compileOnly = false;  // -c
  bool emitCpp = false;      // --emit-cpp
  bool watch = false;        // --watch
  bool lab = false;          // --lab
  bool sandbox = false;      // --sandbox
  bool debugger = false;     // --debugger
  std::vector<std::string> inputs;  // [view.v anim.a color.map … helper.cpp] model.l

  // What it writes and says.
  std::vector<std::string> outs;  // -out, in order (Batch.h: the first, then the others)
  int fps = kVideoFps;
  std::string record;    // --record (the window's)
  std::string profile;   // --profile
  std::string runRecord; // --run-record
  bool debug = false, quiet = false, verbose = false, stats = false;  // -d -q -v --stats
  bool dumpSteps = false, dumpInterpreted = false, dumpInterpretedEach = false;  // -ds -dtf -dtfes
  bool outputFrames = false;  // --output-frames

  // The window (lpfg's options).
  std::string rmode;  // -rmode: expl, cont, trig ("": lpfg's default, expl)
  std::vector<float> winSize, winPos, winPosRel, winSizeRel;  // -w -wp -wpr -wr: two numbers or none
  bool noBorder = false;      // -wnb
  bool noMessageLog = false;  // -wnm
  std::vector<std::string> panels;  // --panel

  // Accepted from lpfg's command line, with nothing to do in lcjit.
  bool cn = false, tablet = false, timer = false;
  std::string dll, libPath;  // -dll/-o, -lp

  // The model's code and its run.
  std::optional<int> optLevel;  // -O; without it the tiers are lcjit's choice (compileTiers)
  double tierAfterMs = kBetterTierAfterMs;  // --tier-after
  std::vector<std::string> includeDirs;  // -I
  std::vector<std::string> overrides;    // -D NAME=VALUE, as given
  std::optional<uint64_t> seed;          // --seed
  std::string variation;                 // --variation: a Context Free design's variation code
  int frames = 0;                        // --frames: a Context Free design's animation of N frames
  bool cleanEA20 = false;                // -cleanEA20
  double environmentTimeout = 60;        // --environment-timeout
  // The limits of every derivation (runtime::EngineLimits, whose defaults they start from).
  size_t maxModules = runtime::EngineLimits().maxModules;
  size_t maxMemory = runtime::EngineLimits().maxMemory;
  double timeLimit = runtime::EngineLimits().timeLimit;
  std::optional<int> steps;  // --steps (runtime::EngineLimits::steps)
  std::string run;           // --run: an XL model's rule method each step applies (ModelFiles::run)

  // --sandbox's limits on one run (SandboxLimits: the plan adds the memory's from --max-memory).
  double maxCpuSeconds = 600;
  uint64_t maxFileSize = 1ull << 30;
  uint64_t maxThreads = 512;

  // A sandboxed run's child (Sandbox.h, SandboxWindow.h): given by the sandbox, not by users.
  int reportFd = -1;         // --sandboxed FD: the reports to the parent
  int replyFd = -1;          // --reply-fd FD: the picture for a sandboxed window
  int toStep = -1;           // --to-step N: where that picture is
  bool plainErrors = false;  // --plain-errors: --lab's, for the child

  runtime::EngineLimits limits() const;
  bool operator==(const Options&) const = default;
};

// Declares the options on `app` (help and checks as `lcjit --help` shows them), bound to `into`.
void declareOptions(CLI::App& app, Options& into);
// The arguments for CLI11's parse of the whole command line (the subcommands' too), in the order
// CLI::App::parse takes them: lpfg's multi-letter options have one dash where CLI11 wants two.
std::vector<std::string> argumentsForParse(int argc, char** argv);
// After the parse: what CLI11's checks cannot see (an -out that is a video among several, a
// --record that is no video, a -wr of no size), with the message lcjit says.
llvm::Error checkOptions(const Options& options);
// `option` WIDTH HEIGHT (-w, the REPL's -w) as a picture's or a window's size.
llvm::Error checkPictureSize(const char* option, const std::vector<float>& size);

// The command line of a sandboxed run's child: every option the child takes, as `options` has
// it, then the inputs. The sandbox adds its own (--sandboxed, --reply-fd, --to-step).
std::vector<std::string> childArguments(const Options& options);
// Every option as `options` has it (the parent's alone too), then the inputs: a command line that
// parses back to `options`, for messages.
std::vector<std::string> commandLine(const Options& options);

}  // namespace lcjit::app
