// The interactive mode's window (manual §1.2) over a model host (ModelHost.h): one controller for
// the model run in this process and for the model run in a sandboxed child. It builds the menu
// (the main menu's New … items, §1.2.2, and the animate menu, §1.2.3), frames each picture the
// host brings, steps the animation through the animation file's frames (§8.1), records the frames
// shown, and watches the model's files under -rmode cont (§1.3). A broken edit keeps the last
// good model on screen (the host says why over it).
#pragma once
#include <functional>
#include <memory>
#include <string>

#include "app/window/Interactive.h"
#include "app/window/ModelHost.h"

namespace lcjit::viewer {
struct WindowOptions;
}

namespace lcjit::app {

// Opens the window, makes the host with it and runs the window over the host until it closes;
// returns the process exit status. `model`: the .l file (the window's Save name, recorded frames).
int runWindow(const viewer::WindowOptions& window, const InteractiveOptions& options, const std::string& model,
              const std::function<std::unique_ptr<ModelHost>(viewer::Window&)>& makeHost);

}  // namespace lcjit::app
