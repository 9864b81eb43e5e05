// A Context Free design in lcjit's window: the model host (app/window/ModelHost.h) of a design
// compiled in this process, under the same window controller as an L-system's. The design is
// expanded on a worker thread and shown as flat coloured shapes on the picture plane (2D: pan and
// zoom); New model re-reads and recompiles it (a broken edit keeps the last good picture, the
// error over it), New run expands it again, Next variation (Ctrl+N) expands the next variation,
// and -rmode cont does New model at every save of the design or a file it imports. The Parameters
// panel moves the design's constant numbers (as -D would set them) and draws it again.
#pragma once
#include "app/cfdg/DesignRun.h"

namespace lcjit::viewer {
struct WindowOptions;
}

namespace lcjit::app {

struct InteractiveOptions;

// Runs the window over `design` until it closes; returns the process exit status (1 when the
// design does not load and no file is watched for a fix).
int runDesignWindow(const DesignRunOptions& design, const viewer::WindowOptions& window,
                    const InteractiveOptions& options);

}  // namespace lcjit::app
