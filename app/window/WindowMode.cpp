// The window's mode as the command line asks for it (WindowMode.h).
#include "app/window/WindowMode.h"

#include <filesystem>

#include "app/cli/Modes.h"

namespace lcjit::app {

viewer::WindowOptions windowOptions(const Options& o) {
  viewer::WindowOptions w;
  if (o.winSize.size() == 2) w.width = (int)o.winSize[0], w.height = (int)o.winSize[1];
  if (o.winPos.size() == 2) w.position = std::make_pair((int)o.winPos[0], (int)o.winPos[1]);
  if (o.winSizeRel.size() == 2) w.relW = o.winSizeRel[0], w.relH = o.winSizeRel[1];
  if (o.winPosRel.size() == 2) w.relX = o.winPosRel[0], w.relY = o.winPosRel[1];
  w.borderless = o.noBorder;
  if (std::string model = modelOf(o.inputs); !model.empty())
    w.title = "lcjit: " + std::filesystem::path(model).filename().string();
  return w;
}

InteractiveOptions interactiveOptions(const Options& o, const CompileTiers& tiers) {
  InteractiveOptions io;
  io.optLevel = tiers.optLevel;
  io.betterTier = tiers.betterTier;
  io.plainErrors = o.lab;
  io.quiet = o.quiet;
  if (!o.rmode.empty()) io.refresh = *parseRefreshMode(o.rmode);
  io.animate = o.animate;
  io.verbose = o.verbose;
  io.debug = o.debug;
  io.panels = o.panels;
  io.record = o.record;
  io.fps = o.fps;
  return io;
}

}  // namespace lcjit::app
