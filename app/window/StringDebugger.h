// The window's String panel: the string debugger. Step forward and back; a module chosen by a
// click on the picture (or by its index) is shown with its parameters, its neighbours and the rule
// and step that made it (the engine's provenance); a chosen production can stop the derivation in
// the step it applies in. It reads the engine only when no derivation runs.
#pragma once
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "viewer/Window.h"

namespace lcjit::runtime {
class Engine;
}

namespace lcjit::app {

class StringDebugger {
 public:
  static constexpr const char* kTitle = "String";

  // What the panel's buttons ask for; the window's mode derives (on its worker) and shows.
  struct Requests {
    std::function<void(int step)> deriveTo;  // from the axiom when `step` is behind the string's
  };

  // The panel as the engine stands (call only while no derivation runs); `busy`: one does, so the
  // panel keeps its last text and its buttons wait.
  viewer::Panel panel(runtime::Engine& engine, bool busy, const Requests& requests);
  // A click on the picture hit the module at this byte offset of the string (runtime::pickSource).
  void select(const runtime::Engine& engine, size_t offset);
  std::optional<size_t> selected() const { return selected_; }

 private:
  std::optional<size_t> selected_;
  viewer::Panel last_;  // shown while a derivation runs
};

}  // namespace lcjit::app
