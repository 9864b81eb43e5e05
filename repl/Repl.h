// The REPL, `lcjit repl [files] model.l` (docs/repl.md): commands that load, derive, inspect,
// time and save the model, watch its files and show it in a window, and C++ typed at the prompt,
// compiled against the loaded model (Session::evaluate). On a terminal the input is edited with
// libedit; from a script it is read line by line and only the commands' output is printed.
#pragma once
#include <string>
#include <vector>

namespace lcjit::repl {

struct ReplOptions {
  int optLevel = 1;
  int width = 800, height = 800;  // pictures written by :save, and the :view window
  // --lab (a classroom): the window and the watcher start with the model, compile errors come in
  // plain language first, and the caches and the history live in `labFolder` (the model's).
  bool lab = false;
  std::string labFolder;
  // --steps: derive this many steps instead of the model's derivation length (-1: its own); an XL
  // model has none.
  int steps = -1;
};

// Runs until :quit or the end of the input, having loaded `inputs` (lpfg's input files, a .l
// among them) first when there are any. Returns the exit status: 0, or 1 when some command failed
// and the input was not a terminal (so that a script's failure shows).
int runRepl(const std::vector<std::string>& inputs, const ReplOptions& options);

}  // namespace lcjit::repl
