// The window's mode as the command line asks for it (app/cli): lpfg's window options (-w, -wp,
// -wpr, -wr, -wnb; the title names the model) and the controller's (InteractiveOptions), for the
// window over a model here and the one over sandboxed runs alike.
#pragma once
#include "app/window/Interactive.h"
#include "viewer/Window.h"

namespace lcjit::app {

struct Options;
struct CompileTiers;

viewer::WindowOptions windowOptions(const Options& options);
InteractiveOptions interactiveOptions(const Options& options, const CompileTiers& tiers);

}  // namespace lcjit::app
