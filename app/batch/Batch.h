// Batch mode (`-b`, or no display): derive the loaded model and write what the command line asks
// for (-out, -dtf, -ds, --stats…); with --watch, keep doing it after every change of an input
// file, in one process, logging one line per reload.
#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "app/common/Defaults.h"
#include "app/session/Session.h"

namespace lcjit::app {

struct BatchOptions {
  // -out: string (.str/.txt), binary string (.strb), a picture/geometry file, numbered files of
  // one (frame%04d.png) or a video (.mp4, .webm): FrameSequence.h
  std::string out;
  // Further -out files, written after the run as `out` is (not numbered files or videos).
  std::vector<std::string> moreOuts;
  int width = 800, height = 800;  // pictures (-w)
  int fps = kVideoFps;            // a video's frames per second (--fps)
  int optLevel = 1;
  // A better tier (no second tier when not above optLevel): under --watch, after each load
  // the model compiles again at this level in the background and is swapped in when ready.
  // A batch run starts with it when an earlier run left it in the object cache; else, once the
  // derivation has taken `tierAfterMs`, it is compiled in the background and swapped in between
  // steps: a long run goes on with better code, a short one is not slowed down. A build that
  // started is waited for at the end of the run, for the cache and the next run.
  int betterTier = -1;
  double tierAfterMs = kBetterTierAfterMs;
  bool quiet = false, verbose = false, debug = false, stats = false;
  bool plainErrors = false;  // --lab: compile errors in plain language first
  bool dumpSteps = false, dumpInterpreted = false, dumpInterpretedEach = false;
  // OutputFrame("file") from model code. lpfg's batch mode only records the name and writes
  // nothing (its window writes the picture once it has drawn the step), so by default neither
  // does lcjit, and the model's interpretation rules run exactly when lpfg runs them.
  // --output-frames writes each named file once its step is over (after EndEach; after Start
  // or End for their calls), as lpfg's window does when it shows every step: its interpretation
  // then runs the rules once more per picture, as the window's drawing does.
  bool outputFrames = false;
  // --profile: per-rule counts and times (ProfileReport.h) written as JSON to this file after
  // the run and its outputs (their interpretation included); "-": as a table on stdout.
  std::string profile;
  // --run-record FILE (RunRecord.h): written after the run whatever happened, with its first
  // error; `seed` is --seed's, for the record.
  std::string runRecord;
  std::optional<uint64_t> seed;
  // Told each derivation step done, and -1 once the derivation is over: a sandboxed run's
  // progress for its parent, who names it when the run dies of a limit (Sandbox.h).
  std::function<void(int step)> progress;
};

struct Options;
struct CompileTiers;
// A batch run's options as the command line (app/cli) says them, at these compile tiers.
BatchOptions batchOptions(const Options& options, const CompileTiers& tiers);

// One run of the loaded model: derive from the axiom, then write the outputs. `times` carries the
// load's phase times in and gets the run's added. Returns the process exit status.
int runBatch(Session& session, const ModelFiles& files, const BatchOptions& options, PhaseTimes& times);

// --watch: runBatch, then wait for changes of the model's input files; each change re-reads what
// §1.3's table says (a changed .l recompiles), re-runs and rewrites the outputs, and prints one
// line with the timings. A failed reload prints its diagnostics and keeps the last good model.
// `first`: the first load's phase times. Runs until the process is stopped.
int watchBatch(Session& session, const ModelFiles& files, const BatchOptions& options, PhaseTimes first);

}  // namespace lcjit::app
