// What runs the model for the window (WindowController.h): a "model host". The controller owns
// the window's side of the interactive mode — the menu, the animation's frames and their timing,
// how each picture is framed, file monitoring, recording — and the host runs the model: it
// derives to the step the controller asks for and interprets the string, one run at a time in
// the background, reloads the model's files for the New … items and changed files, and hands
// back the picture with where the derivation stands. Two hosts: the session in this process
// (Interactive.cpp: a worker thread derives while the window draws) and a sandboxed child lcjit
// per picture (app/sandbox/SandboxWindow.cpp).
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "app/session/FileMonitor.h"
#include "runtime/files/AnimationFile.h"
#include "runtime/files/Images.h"
#include "runtime/turtle/Geometry.h"
#include "viewer/Window.h"

namespace lcjit::app {

// The picture a run asks for.
struct RunTarget {
  enum class Kind {
    Whole,       // the whole derivation, End included
    FirstFrame,  // the animation file's first frame, from the axiom (Rewind)
    Step,        // step `step`: from where the model is when that is not past it, else from the axiom
  } kind = Kind::Whole;
  int step = 0;
  bool fromAxiom = false;  // Step: from the axiom in any case (a value the run reads has changed)
  static RunTarget whole() { return {}; }
  static RunTarget firstFrame() { return {Kind::FirstFrame, 0, true}; }
  static RunTarget at(int step, bool fromAxiom = false) { return {Kind::Step, step, fromAxiom}; }
};

// A picture as the window draws it. The host keeps what it points to until its next run ends.
struct HostPicture {
  const runtime::Geometry* main = nullptr;
  const std::vector<viewer::ViewPane>* panes = nullptr;  // UseView's views (§7.3); empty: main alone
  const runtime::ViewSettings* view = nullptr;
  const viewer::RenderPalette* palette = nullptr;
  const std::vector<runtime::Image>* textures = nullptr;
};

// A run that ended.
struct RunEnd {
  // A fault in model code or a model that does not compile: nothing new to show (the host has
  // said why, on stderr and, where the window shows it, over the last good picture).
  bool failed = false;
  std::optional<HostPicture> picture;  // none: failed, or stopped for a newer run
  // With a picture: where the derivation stands, and the animation file it was run with
  // (lpfg's defaults without one).
  int step = 0, derivationLength = 0;
  bool ended = false;  // no step is left (the derivation length reached, or Stop())
  runtime::AnimationSettings animation;
};

// What the host has to tell the controller since its last poll.
struct HostNews {
  std::optional<RunEnd> run;
  // Run the model again — the whole derivation, or the animation from its first frame: a reload
  // that re-runs (New model, New L-system, New run, a changed file), the Profile panel's Run again.
  bool rerun = false;
  // Draw the string anew (New view, New rendering).
  bool redraw = false;
  // The view back to the view file's framing first (New model, New view).
  bool resetView = false;
  // The frame shown again, derived from the axiom: values the run reads changed (the Parameters
  // panel's .vset values, timelines and tunables).
  bool rerunShown = false;
  // RunSimulation and PauseSimulation from model code (§6.5).
  bool runAnimation = false, pauseAnimation = false;
};

class ModelHost {
 public:
  virtual ~ModelHost() = default;

  // ---- runs
  // Starts the run for `target`. The session's host does nothing while a run is on (the menu
  // offers nothing that starts one meanwhile); the sandbox's stops it and starts anew.
  virtual void derive(RunTarget target) = 0;
  // The picture shown drawn anew (Clear, a New view): the session's string interpreted again;
  // a sandboxed run to the same step.
  virtual void redraw() = 0;
  virtual bool busy() const = 0;
  // Whether the model's menu items wait while a run is on (greyed out): the session's engine is
  // the worker's meanwhile; a sandboxed run is simply replaced.
  virtual bool itemsWaitWhileBusy() const = 0;
  // Stop (a long step in progress ends) and Esc (model code stuck in a loop is interrupted); a
  // no-op without a run.
  virtual void stop() = 0;
  virtual void interrupt() = 0;
  // What happened since the last call, waiting up to `waitMs` for the run to end.
  virtual HostNews poll(int waitMs) = 0;
  // The picture of the last RunEnd is in the window now (what waited for it may go on: a
  // click's picking is against the picture the window shows).
  virtual void shown() {}
  // How far a long run has come, for the window's status line ("": nothing to say).
  virtual std::string progress() const { return ""; }

  // ---- files
  // A New … item or a change of the model's files (§1.2.2, §1.3); its outcome comes in HostNews.
  virtual void apply(Action a) = 0;
  // Files changed on disk, before their actions are applied.
  virtual void filesChanged(const std::vector<std::string>&) {}
  // The files to watch under -rmode cont (§1.3), as the host knows them now.
  virtual std::vector<std::string> watchedFiles() const = 0;

  // ---- the window's input and menu
  // Once a frame, before the menu: the pointer and camera model code reads, clicks that insert
  // into the string (MouseIns, §5.9).
  virtual void takeInput() = 0;
  // The host's part of the menu: Save as… a model format, String input/output, New animate, the
  // user menu (§6.8), the panels. `a` holds the controller's part.
  virtual void addToMenu(viewer::MenuActions& a) = 0;
  // Whether Start recording is offered (it writes where the animation file says).
  virtual bool records() const = 0;
};

}  // namespace lcjit::app
