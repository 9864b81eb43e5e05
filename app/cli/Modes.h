// What the options (Options.h) ask for, decided here for every mode: the model without one, the
// classroom (--lab), the window or not, the compile tiers, and the session of a run in this
// process set up as they say. The driver (app/lcjit.cpp) picks the mode with these; the modes'
// rooms take their own options from Options (batchOptions, interactiveOptions, the sandbox's plan).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include <llvm/Support/Error.h>

#include "app/cli/Options.h"
#include "app/session/Session.h"

namespace lcjit::app {

// The window can open: a build with it, and a display.
bool haveDisplay();
// The file a model is shown in where there is no window: MODEL.png beside where lcjit runs
// (MODEL.str in a build without pictures).
std::string shownIn(const std::string& model);
// The L-system among the inputs (the last .l given), or "".
std::string modelOf(const std::vector<std::string>& inputs);
// The window is what the options ask for: no -b, -out, -c or --emit-cpp, and a display.
bool opensWindow(const Options& options);

// What the options mean once parsed, settled in them: without a model, the built-in example
// drawn into tree.png (said unless -q); -I folders absolute; --lab's classroom: the inputs
// absolute and the model's folder the working one, continuous refresh, and without a display
// --watch writing MODEL.png. Returns the folder for the session's caches ("": the user's; --lab
// keeps them in the model's folder).
std::string settleOptions(Options& options);
// --lab with a display and a model: the window (sandboxed where bubblewrap works), the watcher
// and the REPL (not in a sandbox).
bool labWindow(const Options& options);
// `folder`/.lcjit-cache of the model's folder, or "" without a model: where --lab and a sandboxed
// run keep their caches, written nowhere else.
std::string cacheInModelFolder(const std::vector<std::string>& inputs);

// The compile tiers of a run in this process: the level the model loads at, and the better one
// compiled in the background and swapped in (-1: none; BatchOptions::betterTier says when).
// With -O, that level alone; --debugger: -O0 alone; live (--watch, the window): -O0, then -O2;
// a batch run: -O1, then -O2 once the run is long.
struct CompileTiers {
  int optLevel = 1;
  int betterTier = -1;
};
CompileTiers compileTiers(const Options& options, bool window);

// The input files (classifyInputs) with the command line's -I folders and -D values.
llvm::Expected<ModelFiles> modelFiles(const Options& options);
// A session for a run in this process, set up as the options say: its cache folder, the limits,
// --seed, the environmental programs, how it compiles (compileTiers), its colours (the window's,
// or a sandboxed window's run). Says the cache's warning, if any.
llvm::Expected<std::unique_ptr<Session>> openSession(const Options& options, const ModelFiles& files,
                                                     const std::string& cacheDir, bool window);
// A load that failed, said as g++ says it for lpfg and as --watch says a failed reload (the line
// and a caret; --lab's in plain language first), and in the --run-record of a run that ends.
void reportLoadError(const std::string& message, const Options& options, const ModelFiles& files, Session* session,
                     const PhaseTimes& times);

}  // namespace lcjit::app
