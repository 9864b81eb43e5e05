// What model code reads from the window (manual §6.8, §7.4): the user menu (items added by
// UserMenuItem, shown on two of Ctrl/Shift/Alt + right click, read back by UserMenuChoice) and the
// mouse status (GetMouseStatus). Model code runs on the derivation thread and the window on the
// main thread, hence the locks. In batch mode nothing feeds them: neutral values.
//
// All of it is one session's (WindowInput, below): a Session owns one and hands it to each engine
// it makes, and the host functions reach it through the engine that is running, as they reach its
// environmental program. Two sessions in one process (the unit tests, a sweep) share nothing of it.
#pragma once
#include "runtime/include/lcjit/types.h"
#include <map>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace lcjit::runtime {

class UserMenu {
 public:
  void add(const std::string& label, int code);
  void clear();
  std::vector<std::pair<std::string, int>> items() const;
  // The window records a selection; choice() returns the last one since the previous call, or
  // -1 if there was none.
  void choose(int code);
  int choice();

 private:
  mutable std::mutex mutex_;
  std::vector<std::pair<std::string, int>> items_;
  int choice_ = -1;
};

// Values the model marks as tunable (lcjit's `tunable("NAME", value, min, max)`): the window's
// Parameters panel shows each as a slider; a value moved there is what the call returns from the
// next run on (no recompile). Values are kept by name across runs and reloads; a call registers its
// name, and its default and range follow the code as it is edited.
class Tunables {
 public:
  struct Entry {
    std::string name;
    float value = 0;  // what the code says
    float min = 0, max = 1;
    bool moved = false;  // the panel set `moved`
    float movedTo = 0;
  };
  // What model code's call returns: the moved value, if any, else `value` (clamped to [min, max]).
  float get(const char* name, float value, float min, float max);
  // What the call returns where no panel can have moved it (no session's engine is running).
  static float codeValue(float value, float min, float max);
  std::vector<Entry> entries() const;  // in the order first met
  void move(const std::string& name, float to);
  void reset();  // the panel's moves forgotten (the code's values again)

 private:
  mutable std::mutex mutex_;
  std::vector<Entry> entries_;
};

// The animation functions of §6.5 that steer the window: DisplayFrame (with `display on
// request: on`), RunSimulation, PauseSimulation. Model code sets them, the window takes them.
struct AnimationRequests {
  bool display = false, run = false, pause = false;
};
class AnimationControl {
 public:
  void requestDisplay() { set(&AnimationRequests::display); }
  void requestRun() { set(&AnimationRequests::run); }
  void requestPause() { set(&AnimationRequests::pause); }
  AnimationRequests take();

 private:
  void set(bool AnimationRequests::*flag);
  std::mutex mutex_;
  AnimationRequests requests_;
};

// §6.4 view functions: each view's bounding box (vvXmin …, from its last interpretation), its
// projection scale (vvScale) and the camera (GetCameraPosition), as the window last showed them.
// Unknown views: a zero box, scale 1.
class Views {
 public:
  void setBox(int id, V3f min, V3f max);
  void setCamera(int id, const CameraPosition& camera);
  // axis 0..2 = x, y, z; max selects the upper corner.
  float box(int id, int axis, bool max) const;
  float scale(int id) const;
  CameraPosition camera(int id) const;

 private:
  struct View {
    V3f min, max;
    CameraPosition camera{};
    bool hasCamera = false;
  };
  mutable std::mutex mutex_;
  std::map<int, View> views_;
};

// GetCameraPosition()'s answer for a camera, as lpfg's window gives it: left = head × up
// (Projection's view left), scale = vvScale (the inverse of the view's projection scale, times
// the user's zoom).
CameraPosition cameraPosition(V3f eye, V3f lookAt, V3f head, V3f up, float scale);

// The camera lpfg's window has until it first draws (Projection::Reset): from (0,0,1) towards the
// origin along −z, up +y, vvScale = `viewScale`. lpfg derives the model of its window with it,
// so a batch picture (lpfg's window picture) does too. (lpfg's batch mode has no view:
// GetCameraPosition then gives zeros, as here without a camera.)
CameraPosition initialWindowCamera(float viewScale);

class Mouse {
 public:
  // The window's latest pointer; pushed/released accumulate until the model reads them.
  void update(const MouseStatus& s);
  // GetMouseStatus(): the latest status; pushed/released since the previous call.
  MouseStatus take();
  // GetTabletStatus(): the pointer as a tablet pen (lcjit has no tablet driver): connected once
  // a window feeds the mouse, pressure 1 while the left button is down.
  TabletStatus tablet();
  // Whether model code asked for either since the session started: a sandboxed window's run,
  // which no window feeds, says so (app/sandbox/SandboxWindow.h).
  bool wasRead();

 private:
  std::mutex mutex_;
  MouseStatus status_;
  bool fed_ = false, read_ = false;
};

// One session's window state. The window (app/window), the REPL (its :set of tunables), batch
// runs (the camera a picture is derived with) and a sandboxed window's child are handed their
// session's; model code reaches it through Engine::windowInput() (runtime/HostFunctions.cpp).
struct WindowInput {
  UserMenu menu;
  Tunables tunables;
  AnimationControl animation;
  Views views;
  Mouse mouse;
};

}  // namespace lcjit::runtime
