// Refresh modes and file monitoring (manual §1.1.1 -rmode, §1.2.2 main menu, §1.3 file
// monitoring): the policy as data — which action a changed input file triggers, which files each
// menu action re-reads — and an inotify watcher of a set of files. Nothing here needs a window.
//
// lpfg facts (mainwindow.cpp, comlineparam.cpp, lpfg.cpp):
//  * `-rmode expl|explicit|cont|continuous|trig|triggered`; default explicit. lpfg treats
//    triggered exactly like continuous: both switch on the same directory watcher at start-up,
//    and the menu has a single "Triggered/Continuous" item. (The name comes from vlab, where a
//    "triggered" object is refreshed when an editor launched from the object saves a file; for
//    lpfg itself the save is just a file change.) So actionForChange gives the same action for
//    Continuous and Triggered, and nothing for Explicit (only the menu re-reads).
//  * On a change lpfg matches the file's NAME against its input files and runs: L-system → New
//    L-system; view → New view; animation → re-read the animation file only; colormap/material →
//    re-read colours and redraw; function/fset/tset/vset files → re-read functions and re-run;
//    contour files → re-read contours and re-run; textures and .s surfaces → re-read the view
//    file's rendering data (colours, surfaces, textures) without resetting the view. Other files
//    (the environment .e, compiler output) are ignored.
#pragma once
#include <chrono>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>

#include "app/session/InputKinds.h"
#include "app/session/ReloadParts.h"
#include <vector>

namespace lcjit::app {

enum class RefreshMode { Explicit, Continuous, Triggered };
// "expl"/"explicit", "cont"/"continuous", "trig"/"triggered" (lpfg's -rmode values).
std::optional<RefreshMode> parseRefreshMode(std::string_view s);

// The main menu's New … commands (§1.2.2) and the animate menu's New animate (§1.2.3).
enum class Action { None, NewModel, NewLsystem, NewRun, NewView, NewRendering, NewAnimate };

const char* toString(Action a);

// §1.3 table: the action run when a file of kind `k` changes under `mode` (None in Explicit, and
// for files the table does not name). Animation = "Rereads file only" = NewAnimate.
Action actionForChange(FileKind k, RefreshMode mode);

// §1.2.2 summary table: which kinds of input file each action re-reads. NewModel and NewLsystem
// re-read the L-system file (and recompile); NewModel, NewView and NewRendering the view file;
// all five the colours, surfaces, textures; NewModel, NewLsystem and NewRun the functions,
// contours, timeline and parameters. NewModel also re-reads the animation file (lpfg does; the
// manual says "all input files") and the environment file; NewAnimate only the animation file.
std::set<FileKind> filesReadBy(Action a);
// The view-side effects of an action (§1.2.2 columns "Reset view", "Reset rendering") and whether
// it re-runs the simulation.
bool resetsView(Action a);
bool resetsRendering(Action a);
bool rerunsSimulation(Action a);
// The same table as the parts of a load (Session::load): what a New … action re-reads; nothing
// for New animate, which re-reads the animation file only (not part of a Session).
std::optional<ReloadParts> reloadPartsFor(Action a);

// The actions for a batch of changed files, in the order to run them, without those another one
// in the batch covers: NewModel alone covers all; NewAnimate first (its settings apply to the
// re-run); then NewLsystem (covers NewRun) or NewRun; then NewView (covers NewRendering), or
// NewRendering if neither NewLsystem nor NewRun (which re-read colours, surfaces, textures) runs.
std::vector<Action> actionsForChanges(const std::vector<std::string>& paths, RefreshMode mode);

// Watches a set of files through inotify on their DIRECTORIES (so a save that writes a temporary
// file and renames it over the original is seen, as is a file deleted and created again) and
// reports which watched files changed. A finished save (the file closed after writing, or renamed
// into place) is reported at once (after kSavedQuiet); otherwise events for one file that come
// less than `quiet` apart (default 100 ms) are one change, reported once the file has been quiet
// that long (or after `maxDelay`, 2 s, of continuous events). Not thread-safe; one poller.
class FileMonitor {
 public:
  explicit FileMonitor(std::chrono::milliseconds quiet = std::chrono::milliseconds(100),
                       std::chrono::milliseconds maxDelay = std::chrono::milliseconds(2000));
  ~FileMonitor();
  FileMonitor(const FileMonitor&) = delete;
  FileMonitor& operator=(const FileMonitor&) = delete;

  // Replaces the watched set; changes of files in both sets not yet reported stay pending. Files
  // need not exist yet; their directories must. Returns false (see error()) if inotify or some
  // directory could not be watched; the others are still watched.
  bool watch(const std::vector<std::string>& paths);
  void clear() { watch({}); }
  const std::string& error() const { return error_; }

  // Waits at most `timeoutMs` (0: do not wait; < 0: until a change) for changes that have
  // settled, and returns the watched paths (as given to watch()) that changed, each once, in
  // watch() order. Changes still within their quiet period stay pending for the next call.
  std::vector<std::string> poll(int timeoutMs);
  // The inotify descriptor (-1 without one), for waiting on it beside other things; poll(0)
  // when it is readable. Changes also settle with time alone: poll now and then anyway.
  int fd() const { return fd_; }

 private:
  using Clock = std::chrono::steady_clock;
  struct Pending {
    Clock::time_point first, last;
    bool saved = false;  // the last event finished a save (closed after writing, renamed into place)
  };
  // A finished save still waits this long, for the events of the same save that follow it.
  static constexpr std::chrono::milliseconds kSavedQuiet{1};
  int fd_ = -1;
  std::chrono::milliseconds quiet_, maxDelay_;
  std::vector<std::string> paths_;                // as given
  std::map<int, std::map<std::string, std::vector<size_t>>> byWatch_;  // wd → file name → paths_ indices
  std::map<size_t, Pending> pending_;             // paths_ index → times
  std::string error_;

  void drain();  // reads all available inotify events into pending_
  Clock::time_point settlesAt(const Pending& p) const;
  std::optional<Clock::time_point> readyAt() const;  // when the earliest pending change settles
  std::vector<std::string> takeReady(Clock::time_point now);
};

}  // namespace lcjit::app
