// The options' one table (declare, below): each option's spelling — lpfg's multi-letter ones with
// lpfg's single dash — its field of Options, its help and checks, and whether a sandboxed run's
// child takes it. CLI11 parses by it; childArguments (and commandLine) write back by it;
// argumentsForParse reads lpfg's spellings from it.
#include "app/cli/Options.h"

#include <algorithm>
#include <charconv>
#include <functional>
#include <set>
#include <type_traits>

#include <CLI/CLI.hpp>
#include <fmt/printf.h>
#include <llvm/Config/llvm-config.h>

#include "app/common/Frame.h"
#include "app/common/FrameSequence.h"
#include "app/session/InputKinds.h"
#include "app/sweep/Sweep.h"

namespace lcjit::app {

runtime::EngineLimits Options::limits() const {
  runtime::EngineLimits l;
  l.maxModules = maxModules;
  l.maxMemory = maxMemory;
  l.timeLimit = timeLimit;
  l.steps = steps.value_or(-1);
  return l;
}

namespace {

// Whether a sandboxed run's child takes an option: each is one or the other, said where it is
// declared, so that a new option's place is decided with it.
enum class Child {
  Takes,  // as the parent has it (after the sandbox has made its paths absolute)
  Not,    // the parent's alone: the window, the watcher, the sandbox; refused with --sandbox; or
          // an lpfg option that does nothing
};

template <class T>
struct IsOptional : std::false_type {};
template <class T>
struct IsOptional<std::optional<T>> : std::true_type {};

template <class T>
std::string numberText(T v) {
  if constexpr (std::is_floating_point_v<T>) {
    char text[64];  // the shortest that reads back as the same number
    return std::string(text, std::to_chars(text, text + sizeof text, v).ptr);
  } else {
    return std::to_string(v);
  }
}

// Declares options on a CLI::App bound to an Options, and keeps, for each option, how to write
// its value from any Options and whether a child takes it.
class Table {
 public:
  using Writer = std::function<void(const Options&, std::vector<std::string>&)>;

  Table(CLI::App& app, Options& bound) : app_(app), bound_(bound) {}

  template <class T>
  CLI::Option* option(const std::string& names, T Options::*field, const std::string& help, Child child) {
    std::string spelt = cli11Names(names);
    keep(spelt, field, child);
    return app_.add_option(spelt, bound_.*field, help);
  }
  CLI::Option* flag(const std::string& names, bool Options::*field, const std::string& help, Child child) {
    std::string spelt = cli11Names(names);
    keep(spelt, field, child);
    return app_.add_flag(spelt, bound_.*field, help);
  }
  CLI::App& app() { return app_; }
  // lpfg's spellings with one dash ("-out"), declared as CLI11's ("--out").
  const std::set<std::string>& lpfgSpellings() const { return lpfg_; }
  // The options first (those a child takes, or all of them), then the inputs.
  std::vector<std::string> write(const Options& options, bool childOnly) const {
    std::vector<std::string> args;
    for (const Kept& k : named_)
      if (!childOnly || k.child == Child::Takes) k.write(options, args);
    for (const Kept& k : positional_)
      if (!childOnly || k.child == Child::Takes) k.write(options, args);
    return args;
  }

 private:
  std::string cli11Names(const std::string& names) {
    std::string out;
    for (size_t start = 0; start <= names.size();) {
      size_t end = std::min(names.find(',', start), names.size());
      std::string name = names.substr(start, end - start);
      if (name.size() > 2 && name[0] == '-' && name[1] != '-') {
        lpfg_.insert(name);
        name = "-" + name;
      }
      out += (out.empty() ? "" : ",") + name;
      start = end + 1;
    }
    return out;
  }

  // How to write the option back, `names` as CLI11 takes them: it is written as the first.
  template <class T>
  void keep(const std::string& names, T Options::*field, Child child) {
    const bool positional = names[0] != '-';
    const std::string spelling = names.substr(0, names.find(','));
    Writer w = [positional, spelling, field](const Options& options, std::vector<std::string>& args) {
      const T& v = options.*field;
      auto named = [&](std::vector<std::string> values) {
        if (!positional) args.push_back(spelling);
        args.insert(args.end(), values.begin(), values.end());
      };
      if constexpr (std::is_same_v<T, bool>) {
        if (v) args.push_back(spelling);
      } else if constexpr (std::is_same_v<T, std::string>) {
        if (!v.empty()) named({v});
      } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
        for (const std::string& s : v) named({s});  // repeatable, one value each
      } else if constexpr (std::is_same_v<T, std::vector<float>>) {
        std::vector<std::string> numbers;  // all at once (-w W H)
        for (float f : v) numbers.push_back(numberText(f));
        if (!numbers.empty()) named(numbers);
      } else if constexpr (IsOptional<T>::value) {
        if (v) named({numberText(*v)});
      } else {
        static_assert(std::is_arithmetic_v<T>, "childArguments cannot write an option of this type");
        named({numberText(v)});
      }
    };
    (positional ? positional_ : named_).push_back({child, std::move(w)});
  }

  CLI::App& app_;
  Options& bound_;
  std::set<std::string> lpfg_;
  struct Kept {
    Child child;
    Writer write;
  };
  std::vector<Kept> named_, positional_;
};

// The command line, in the order `lcjit --help` lists it.
void declare(Table& t) {
  using O = Options;
  const Child takes = Child::Takes, no = Child::Not;
  t.flag("-b", &O::batch, "batch mode: no window; derive and write the string to -out", takes);
  t.option("-out", &O::outs,
           "(-out, repeatable: each file written after the run) output file: .str/.txt string, .strb binary string, .png/.jpg/.bmp picture, "
           ".obj/.ply/.stl/.gltf/.glb/.svg/.ps/.eps/.pdf/.pov geometry; with a printf number in its name "
           "(frame%04d.png) the axiom and every step to numbered files; .mp4/.webm: the axiom and every "
           "step as a video's frames", takes)
      ->allow_extra_args(false);
  t.option("--fps", &O::fps, "frames per second of a video (-out movie.mp4, --record movie.webm)", takes)
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  t.option("--record", &O::record,
           "where the window's Animate > Start recording writes the frames it shows: a video (.mp4, "
           ".webm) or numbered files (frame%04d.png); default lpfg's MODEL0000.png, MODEL0001.png …", no);
  t.flag("-a", &O::animate, "animate mode: stop at the animation file's first frame (window)", no);
  t.flag("-c", &O::compileOnly,
         "compile the model only (exit 0 if it compiles, 1 if not); the compiled code is cached, so the next "
         "run starts without compiling", takes);
  t.flag("-d", &O::debug, "debug: the module count after every step, on stdout", takes);
  t.flag("-ds", &O::dumpSteps, "(-ds) print the string after each derivation step", takes);
  t.flag("-dtf", &O::dumpInterpreted, "(-dtf) write the final string's turtle commands to <model>.str (lpfg's text)", takes);
  t.flag("-dtfes", &O::dumpInterpretedEach, "(-dtfes) the same after every step, to <model>NNNNNNNN.str", takes);
  t.flag("--output-frames", &O::outputFrames,
         "batch: write the files the model names with OutputFrame, each once its step is over (lpfg's batch "
         "mode writes none)", takes);
  t.flag("-q", &O::quiet, "quiet: no messages", takes);
  t.flag("-v", &O::verbose, "verbose: phase timings and sizes on stderr", takes);
  t.app().set_version_flag("--version", std::string("lcjit " LCJIT_VERSION " (LLVM and Clang " LLVM_VERSION_STRING ")"));
  t.option("-rmode", &O::rmode, "(-rmode) refresh mode: expl, cont, trig", no)->check(CLI::IsMember({"expl", "cont", "trig"}));
  t.option("-w", &O::winSize, "window size", takes)->expected(2)->allow_extra_args(false);
  t.option("-wp", &O::winPos, "(-wp) window position", no)->expected(2)->allow_extra_args(false);
  t.option("-wpr", &O::winPosRel, "(-wpr) relative window position", no)->expected(2)->allow_extra_args(false);
  t.option("-wr", &O::winSizeRel, "(-wr) relative window size", no)->expected(2)->allow_extra_args(false);
  t.flag("-wnb", &O::noBorder, "(-wnb) window without borders", no);
  t.flag("-wnm", &O::noMessageLog, "(-wnm) accepted: lcjit's window has no message log", no);
  t.flag("-cleanEA20", &O::cleanEA20,
         "(-cleanEA20) an EA20 module the environmental program answers has the elements past the answer zeroed", takes);
  t.option("--environment-timeout", &O::environmentTimeout,
           "seconds an environmental program (.e) may take to answer one step before it is an error (0: no "
           "limit)", takes)
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  t.flag("-cn", &O::cn, "(-cn) accepted", no);
  t.flag("-tablet", &O::tablet, "(-tablet) accepted: GetTabletStatus() follows the mouse in any case", no);
  t.flag("-timer,-timed", &O::timer, "(-timer, -timed) accepted: --stats gives lcjit's timings", no);
  t.option("-dll,-o", &O::dll,
           "(-dll/-o) accepted: lcjit compiles the .l file (an lpfg lsys.so cannot be loaded); after -c the "
           "compiled code comes from lcjit's cache", no);
  t.option("-lp", &O::libPath, "(-lp) accepted", no);
  t.flag("--stats", &O::stats, "print a JSON object of phase timings on stderr", takes);
  // A sandboxed run's child takes the table (`--profile` alone, on its stdout); a file is refused
  // with --sandbox (the child writes no file but -out) and the window's runs print none.
  t.option("--profile", &O::profile,
           "write how often each rule (a production, decomposition or interpretation rule; a design's rule or "
           "path) ran and the time it took, hottest first, to this JSON file (an L-system's per step too; "
           "docs/studio.md, docs/cfdg.md); without a file, or with -, print them as a table on stdout", takes)
      ->expected(0, 1)
      ->default_str("-");
  t.option("-O", &O::optLevel,
           "optimisation level of model code: 0, 1 or 2; without it, -O1 code first (-O0 live) and -O2 "
           "compiled in the background and swapped in when the run is long enough to gain (docs/performance.md)", takes)
      ->check(CLI::Range(0, 2));
  t.option("--tier-after", &O::tierAfterMs,
           "batch runs without -O: compile -O2 in the background once the derivation has run this many "
           "milliseconds (default 250)", takes)
      ->check(CLI::NonNegativeNumber);
  t.option("--panel", &O::panels,
           "open this panel of the window at start (Parameters, Profile); the main menu's Panels "
           "submenu opens and closes them (docs/studio.md)", no)
      ->allow_extra_args(false);
  t.flag("--lab", &O::lab,
         "classroom mode: the window, file monitoring and the REPL at once; nothing written outside the "
         "model's folder (caches in .lcjit-cache there); compile errors in plain language first; every run "
         "sandboxed where bubblewrap works (--sandbox; the REPL is then off)", no);
  t.flag("--sandbox", &O::sandbox,
         "run the model (compile, derivation, interpretation, outputs) in a child process under bubblewrap: "
         "no network, the system read-only, writes only in the model's folder and the -out file, no new "
         "processes, limits on memory, CPU time and file size (docs/security.md); batch runs, --watch and "
         "the window (each picture a sandboxed run)", no);
  t.option("--max-cpu", &O::maxCpuSeconds, "--sandbox: the CPU seconds one run may use", no)
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  t.option("--max-file-size", &O::maxFileSize,
           "--sandbox: the largest file one run may write (bytes, or 500M, 1G; default 1G)", no)
      ->transform(CLI::AsSizeValue(false));
  t.option("--max-threads", &O::maxThreads,
           "--sandbox: the threads one run may have (its cgroup's pids.max where it has one; default 512)", no)
      ->check(CLI::Range(uint64_t(16), uint64_t(1) << 20));
  // The child's side of --sandbox, and of a sandboxed window (SandboxWindow.h): the sandbox gives
  // each run its own.
  t.option("--sandboxed", &O::reportFd, "", no)->group("");
  t.option("--reply-fd", &O::replyFd, "", no)->group("");
  t.option("--to-step", &O::toStep, "", no)->group("");
  t.flag("--plain-errors", &O::plainErrors, "", takes)->group("");  // --lab's, for the child
  t.flag("--watch", &O::watch,
         "batch mode: after the run, re-read, recompile and re-run on every change of an input file", no);
  t.flag("--emit-cpp", &O::emitCpp, "print the C++ generated from the model and exit", takes);
  t.option("--max-modules", &O::maxModules, "stop the derivation when the string has more modules", takes)
      ->capture_default_str();
  t.option("--max-memory", &O::maxMemory,
           "stop the derivation when lcjit (or its string) needs more memory (default: half the physical memory)", takes)
      ->transform(CLI::AsSizeValue(false));
  t.option("--time-limit", &O::timeLimit,
           "stop a derivation step (or Start, End, an interpretation) that runs longer, in seconds (default: "
           "none; Ctrl-C interrupts)", takes)
      ->check(CLI::NonNegativeNumber);
  t.option("--steps", &O::steps,
           "derive this many steps instead of the model's derivation length (an XL model has none: 0 "
           "without --steps, as GroIMP before its rules are run)", takes)
      ->check(CLI::NonNegativeNumber);
  t.option("--run", &O::run,
           "NAME: the rule method of an XL model each step applies (GroIMP's button; default: its first)",
           takes);
  t.option("-D", &O::overrides,
           "NAME=VALUE: the model's own #define NAME reads VALUE (no recompile of other values: each "
           "value compiles once, then comes from the cache), and a .vset value NAME is VALUE; an unknown "
           "NAME is an error listing the names there are (docs/sweeps.md)", takes)
      ->allow_extra_args(false);
  t.option("--seed", &O::seed,
           "run as member N of an ensemble: the model's random numbers (ran, and the Gillespie choices) "
           "come from its own seeds mixed with N, a different reproducible stream for each N; without "
           "it, lpfg's (docs/sweeps.md)", takes)
      // CLI11 would read -1 as 2^64 - 1, a number past that as 2^64 - 1 and 010 as 8; N is what a sweep
      // file's seeds are (decimal digits, 0 to 2^64 - 1), handed on written plainly.
      ->transform(CLI::Validator(
          [](std::string& text) {
            std::optional<uint64_t> n = seedNumber(text);
            if (!n) return "N must be " + std::string(kSeedRange) + ", not '" + text + "'";
            text = std::to_string(*n);
            return std::string();
          },
          ""));
  t.option("--variation", &O::variation,
           "a Context Free design's variation: letters (A, ZZT) or a number, as Context Free's -v takes "
           "them (default: a random one, printed)", takes);
  t.option("--frames", &O::frames,
           "a Context Free design's animation of N frames (Context Free's -a N; 0: one picture): -out "
           "with a number in its name (frame%03d.png) writes each frame, -out movie.mp4 a video "
           "(docs/cfdg.md)", takes)
      ->check(CLI::NonNegativeNumber);
  // Refused with --sandbox (the run writes its -out alone).
  t.option("--run-record", &O::runRecord,
           "batch mode: write what the run was run with and how it ended (the -D values, the seed, the "
           "inputs' hashes, the error if any) and its measures (module counts, the geometry's size, "
           "values the model reports with Report) to this JSON file, whatever happens (docs/sweeps.md)", no);
  // Refused with --sandbox: the model would run in the sandbox's process, not the debugged one.
  t.flag("--debugger", &O::debugger,
         "for gdb: model code at -O0 (unless -O) with full debug information, registered through "
         "the GDB JIT interface, so that `break model.l:LINE`, locals and backtraces work in the .l file "
         "(docs/faults.md)", no);
  t.option("-I", &O::includeDirs, "a folder searched for the model's headers (and its C++ sources'), as g++'s -I", takes)
      ->allow_extra_args(false);
  t.option("files", &O::inputs, "input files: [view.v anim.a color.map ... helper.cpp] model.l", takes);
}

// The table on a scratch App: what it says apart from the binding.
struct Scratch {
  CLI::App app;
  Options bound;
  Table table{app, bound};
  Scratch() { declare(table); }
};

}  // namespace

void declareOptions(CLI::App& app, Options& into) {
  Table t(app, into);
  declare(t);
}

std::vector<std::string> argumentsForParse(int argc, char** argv) {
  Scratch scratch;
  const std::set<std::string>& lpfg = scratch.table.lpfgSpellings();
  std::vector<std::string> args;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    args.push_back(lpfg.count(a) ? "-" + a : a);
  }
  std::reverse(args.begin(), args.end());
  return args;
}

llvm::Error checkPictureSize(const char* option, const std::vector<float>& size) {
  // Before anything runs: -w 0 0 would otherwise be a picture of 1 x 1 and a success.
  if (size.size() == 2)
    if (std::string bad = badPictureSize(size[0], size[1]); !bad.empty())
      return llvm::createStringError(fmt::sprintf("lcjit: %s %g %g: %s", option, size[0], size[1], bad));
  return llvm::Error::success();
}

llvm::Error checkOptions(const Options& o) {
  if (o.winSizeRel.size() == 2 && !(o.winSizeRel[0] > 0 && o.winSizeRel[1] > 0))
    return llvm::createStringError(fmt::sprintf("lcjit: --wr %g %g: the size is a fraction of the screen's, above 0",
                                                o.winSizeRel[0], o.winSizeRel[1]));
  for (size_t i = 1; i < o.outs.size(); ++i)
    if (isFrameSequence(o.outs[i]) || isFrameSequence(o.outs[0]))
      return llvm::createStringError("lcjit: -out " + o.outs[i] +
                                     ": numbered files and videos are written step by step: give them as the only -out");
  // --profile takes its file when one follows: never an input's (`--profile model.l` would write the
  // profile over the model).
  if (!o.profile.empty() && o.profile != "-" && fileKindOf(o.profile) != FileKind::Other)
    return llvm::createStringError("lcjit: --profile " + o.profile +
                                   ": that is an input file; the profile is written to a .json file, or printed "
                                   "as a table with --profile alone (after the model's name, or before another option)");
  if (!o.record.empty() && !isFrameSequence(o.record))
    return llvm::createStringError("lcjit: --record " + o.record +
                                   ": frames go to a video (.mp4, .webm) or to numbered files (a name with one printf "
                                   "number, frame%04d.png)");
  return llvm::Error::success();
}

std::vector<std::string> childArguments(const Options& options) { return Scratch().table.write(options, true); }

std::vector<std::string> commandLine(const Options& options) { return Scratch().table.write(options, false); }

}  // namespace lcjit::app
