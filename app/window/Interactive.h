// The interactive mode (manual §1.2): the model's picture in the lcjit window, the window's
// controller (WindowController.h) over the session in this process. The main menu's New … items
// reload through the Session (exactly the files of §1.2.2's table) and a broken edit keeps the
// last good model on screen. InteractiveOptions are the window's under --sandbox too.
#pragma once
#include <string>
#include <vector>

#include "app/common/Defaults.h"
#include "app/session/FileMonitor.h"
#include "app/session/Session.h"

namespace lcjit::viewer {
struct WindowOptions;
}

namespace lcjit::app {

struct InteractiveOptions {
  int optLevel = 1;
  // After a recompile at optLevel, compile again at this level in the background and swap it
  // in without re-running (no second tier when not above optLevel).
  int betterTier = -1;
  bool quiet = false;
  bool plainErrors = false;  // --lab: compile errors in plain language first
  RefreshMode refresh = RefreshMode::Explicit;  // -rmode: continuous/triggered watch the files
  bool animate = false;                         // -a: start in animate mode at the first frame
  bool verbose = false;                         // -v: reload timings on stderr
  bool debug = false;                           // -d: module count after every step on stdout
  std::vector<std::string> panels;              // --panel: panels open from the start, by title
  // --record: where Start recording writes the frames shown, a video or numbered files
  // (FrameSequence.h); "" is lpfg's MODELNNNN.png in the .a file's frame dump folder.
  std::string record;
  int fps = kVideoFps;  // --fps, of a recorded video
};

// Runs the window over `session` until it closes; returns the process exit status.
int runInteractive(Session& session, const ModelFiles& files, const viewer::WindowOptions& window,
                   const InteractiveOptions& options);

}  // namespace lcjit::app
