// The window under --sandbox (and --lab with a display): every run of the model — compile,
// derivation to the step the window wants, interpretation — is a sandboxed child lcjit
// (Sandbox.h) that sends the picture back (SandboxReply.h); the window, in this process, only
// draws what it receives. Both sides are here: the child's answer and the parent's window, the
// window's controller (app/window/WindowController.h) over a host that starts the children.
#pragma once
#include <functional>

#include <llvm/Support/Error.h>

#include "app/window/Interactive.h"
#include "app/sandbox/Sandbox.h"
#include "app/session/Session.h"

namespace lcjit::viewer {
struct WindowOptions;
}

namespace lcjit::app {

// The child's side: after the load (`loaded`: its outcome), derive to `toStep` (-1: the whole
// derivation, End included), interpret, and write a SandboxReply to `replyFd`. A compile error
// or a fault is the reply's message (and on stderr, as the in-process window says it).
constexpr int kFirstFrame = -2;  // WindowAnswerOptions::toStep: the animation file's first frame
struct WindowAnswerOptions {
  int replyFd = -1;
  int toStep = -1;  // or kFirstFrame
  bool quiet = false, plainErrors = false, debug = false;
  std::function<void(int step)> progress;  // the sandbox's step reports (Sandbox.h)
};
int answerWindow(Session& session, const ModelFiles& files, llvm::Error loaded, const WindowAnswerOptions& options);

// The parent's side: the window, running `plan` (its args without --to-step) for every picture.
// Returns the process exit status when the window closes.
int runSandboxedWindow(const SandboxPlan& plan, const viewer::WindowOptions& window, const InteractiveOptions& options);

}  // namespace lcjit::app
