// What a sandboxed run sends the window it runs for (--sandbox with a display, docs/security.md):
// the interpreted picture (main view and multi-view panes), the view settings, colours and
// textures the renderer needs, the steps done and the message to show. A versioned binary
// format; the sender is the untrusted side, so decoding checks every size and index and turns a
// malformed or truncated reply into an error, never a crash or an allocation past its length.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <llvm/Support/Error.h>

#include "runtime/files/ViewFile.h"
#include "runtime/turtle/Geometry.h"
#include "viewer/Renderer.h"

namespace lcjit::app {

struct SandboxReply {
  int steps = 0;             // derivation steps done
  int derivationLength = 0;  // the model's (Engine::derivationLength)
  bool derived = false;      // no step is left (the derivation length reached, or Stop())
  // The animation file's frames (manual §8.1), for the window's Step, Run, Forever and Rewind:
  // the first and last frame (resolved), the steps between frames, the swap interval, framing.
  struct Animation {
    int firstFrame = 0, lastFrame = 0, step = 1, swapIntervalMs = 0;
    bool hcenter = false, scale = false, newView = false;
  } animation;
  // What the window shows over the last good picture ("" when the run went well): a compile
  // error (with its source lines) or a fault in model code. Without a picture, nothing new shows.
  std::string message;
  // What model code asked of the window that a sandboxed run cannot give, for the window to say
  // ("GetMouseStatus"), "" when nothing.
  std::string unanswered;
  bool hasPicture = false;
  runtime::Geometry main;  // without the picking sources: the window does not pick under the sandbox
  std::vector<viewer::ViewPane> panes;
  // What drawing and framing use; the turtle's own inputs (tropisms, surfaces, meshes, terrain)
  // are already in the geometry and are not sent.
  runtime::ViewSettings view;
  viewer::RenderPalette palette;
  std::vector<runtime::Image> textures;
};

std::string encodeSandboxReply(const SandboxReply& reply);
// An error names what was wrong ("the sandboxed run's reply is damaged: …").
llvm::Expected<SandboxReply> decodeSandboxReply(std::string_view bytes);

}  // namespace lcjit::app
