// Which input files a load re-reads (manual §1.2.2's table of the New … menu items); the rest is
// carried over from the loaded model. Session::load takes one; the refresh policy says which one
// each New … action and each changed file asks for (FileMonitor.h: reloadPartsFor), so that the
// session knows files and loads, not the window's menu.
#pragma once

namespace lcjit::app {

struct ReloadParts {
  bool lsystem = true;     // re-read and recompile the .l file (and re-run)
  bool view = true;        // the view file
  bool rendering = true;   // colormap/materials, surfaces, meshes, textures
  bool parameters = true;  // functions, contours, timeline, parameters
  static ReloadParts all() { return {}; }
  static ReloadParts newLsystem() { return {true, false, true, true}; }
  static ReloadParts newRun() { return {false, false, true, true}; }
  static ReloadParts newView() { return {false, true, true, false}; }  // New rendering reads the same
  ReloadParts& operator|=(const ReloadParts& o) {
    lsystem |= o.lsystem, view |= o.view, rendering |= o.rendering, parameters |= o.parameters;
    return *this;
  }
};

}  // namespace lcjit::app
