// What every engine offers the modes (batch, the window, the REPL, exports), whatever the
// language of the model it runs: a run in steps, stopped by a fault, a limit or the user, and the
// drawing of where it has got to as runtime::Geometry, which the one renderer and the exporters
// take. The L-system engine (Engine.h: L+C) is one; a language whose models expand otherwise
// brings its own (app/session/Languages.h names which engine runs which language). What only one
// kind of engine has — an L-system's string, its groups, its binary strings — stays on that engine.
#pragma once
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "runtime/ModelGuard.h"
#include <llvm/Support/Error.h>

namespace lcjit::runtime {

struct Geometry;
struct WindowInput;

// What the modes hear of a run while it goes.
struct EngineHooks {
  // Called after each derivation step, before decomposition (lpfg's -ds point).
  std::function<void(int step)> afterDerivation;
  // Called after each whole step (decomposition and EndEach done): where lpfg draws the frame.
  std::function<void(int step)> afterStep;
  // Model output (Printf).
  std::function<void(const char*)> print;
  // OutputFrame("file.ext") from model code: render or export the current string.
  std::function<void(const char* path)> outputFrame;
  // Messages about the run that do not stop it ("plant.e: warning: …": an environmental
  // program's unusable answers). Without it they go to stderr.
  std::function<void(const std::string&)> warning;
};

// Runaway growth and runaway code stop the run (docs/faults.md).
struct EngineLimits {
  size_t maxModules = 100'000'000;              // modules in the string
  size_t maxMemory = defaultMemoryLimit();      // bytes: the process, and the string's buffers
  double timeLimit = 0;                         // seconds per step (interpretation, Start, End); 0: none
  // --steps: the derivation length instead of the model's (−1: the model's). A language whose
  // models say none (GroIMP's XL, where the user clicks a rule method once per step) takes it here.
  int steps = -1;
};

class ModelRun {
 public:
  virtual ~ModelRun() = default;

  // The run in steps: begin() starts it (`hooks` must outlive it); step() takes one step, false
  // once the run is over (its length reached, or stopped); finish() ends it if it has not.
  virtual void begin(const EngineHooks& hooks) = 0;
  virtual bool step() = 0;
  virtual void finish() = 0;
  // The model asked to stop (Stop()): the run ends after the step in progress.
  virtual void stop() = 0;
  virtual bool ended() const = 0;
  virtual int stepsDone() const = 0;
  virtual int derivationLength() const = 0;  // the steps the run takes, as far as it is known

  // Faults: a crash, an uncaught exception, an interrupt or a limit ends the run's model code;
  // takeFault() gives the message (file:line: error: …, in the language's terms) once.
  virtual llvm::Error takeFault() = 0;
  virtual bool faulted() const = 0;
  virtual void setLimits(const EngineLimits& limits) = 0;
  // From any thread: the model code running now stops, with an "interrupted" fault.
  virtual void interrupt() = 0;
  // From any thread: the step in progress is abandoned (the result stays as before it).
  virtual void cancelStep() = 0;
  // A cancel that came after the step had finished must not stop the next one.
  virtual void clearCancel() = 0;

  // Where the run has got to, drawn: the geometry of view `view` (0: the model's only or first).
  // A fault in the model's drawing code is the error (the run's state is unchanged).
  virtual llvm::Error interpret(Geometry& geometry, int view = 0) = 0;
  // The views the model has opened, in order (multi-view); empty: the one view.
  virtual const std::vector<int>& views() const = 0;

  // The window state model code reads and sets (WindowInput.h: the user menu, tunable values,
  // the views' boxes and camera, the mouse, DisplayFrame & co.), or null: the neutral values of
  // a window that is not there. Its session's; it must outlive the runs.
  void setWindowInput(WindowInput* window) { windowInput_ = window; }
  WindowInput* windowInput() const { return windowInput_; }

 private:
  WindowInput* windowInput_ = nullptr;
};

}  // namespace lcjit::runtime
