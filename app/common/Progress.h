// How far a long derivation has come, for people: "step 40 of 200: 1204311 modules", on a
// terminal's progress line (batch, --watch, the REPL) or in the window's status line.
#pragma once
#include <cstdio>
#include <cstdlib>
#include <string>

namespace lcjit::app {

inline std::string progressText(int step, int length, size_t modules) {
  return "step " + std::to_string(step) + " of " + std::to_string(length) + ": " + std::to_string(modules) +
         (modules == 1 ? " module" : " modules");
}

// The progress line of a long derivation on a terminal: shown once the derivation has run
// half a second, rewritten at most twice a second, cleared when it ends (or goes).
// LCJIT_PROGRESS_AFTER_MS: when the line first appears (default 500; 0 from the first step).
struct TerminalProgress {
  explicit TerminalProgress(bool on) : enabled(on) {
    if (const char* e = std::getenv("LCJIT_PROGRESS_AFTER_MS")) afterMs = std::atof(e);
  }
  ~TerminalProgress() { clear(); }
  template <class Text>
  void update(double ms, Text text) {
    if (ms < afterMs || ms - lastMs < 500) return;
    lastMs = ms;
    std::fprintf(stderr, "\rlcjit: %s\033[K", text().c_str());
    showing = true;
  }
  void clear() {
    if (showing) std::fprintf(stderr, "\r\033[K");
    showing = false;
  }
  const bool enabled;
  double afterMs = 500;
  double lastMs = -1e9;
  bool showing = false;
};

}  // namespace lcjit::app
