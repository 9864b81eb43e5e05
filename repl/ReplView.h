// The REPL's `:view` window: the model's picture, redrawn between keys on the REPL's one thread.
// In a build without the window (LCJIT_WITH_WINDOW=OFF) open() says so and nothing else changes.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include <llvm/Support/Error.h>

namespace lcjit::runtime {
class Engine;
struct DrawingFiles;
}  // namespace lcjit::runtime

namespace lcjit::repl {

class ReplView {
 public:
  ReplView();
  ~ReplView();

  llvm::Error open(int width, int height, const std::string& title);
  void close();
  bool isOpen() const;

  // The string or the model changed: the next pump() draws it anew.
  void markChanged() { changed_ = true; }
  // The REPL's thread has read the input there was (the window may sleep until the next key).
  void inputConsumed();

  struct Pump {
    runtime::Engine& engine;
    const runtime::DrawingFiles& drawing;
    std::string saveName;                                // the Save As dialog's proposal
    std::function<void(const std::string&)> saveAs;      // writes a picture of the model
    std::function<void(llvm::Error)> report;             // a fault while interpreting
  };
  // Draws a frame and sleeps until a window event or a key, at most 0.1 s. False: the user
  // closed the window (it is closed now).
  bool pump(const Pump& p);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  bool changed_ = false;
};

}  // namespace lcjit::repl
