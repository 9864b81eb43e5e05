// --sandbox (and --lab where bubblewrap works) as the command line asks for it (app/cli): the
// parent's plan of a sandboxed run and its runs, and the child's side around its load.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include <llvm/Support/Error.h>

#include "app/cli/Options.h"
#include "app/sandbox/SandboxWindow.h"

namespace lcjit::app {

// The parent, which only starts and watches sandboxed runs (not even the inputs are read here:
// the model folder's lpfg.mak runs make). The plan of a run: the model's folder (writable, the
// child's working folder), what the run may read (the inputs, -I and the compilers' include
// paths), -out, its limits, and the child's command line from `options` (childArguments). Then
// the runs: the window (`labWindow`: --lab's, which says so), --watch's, or one batch run. What a
// sandboxed run cannot do is refused first. Returns the exit status.
int runSandboxed(Options options, bool labWindow);

// The child's side (--sandboxed), before any input is read: it ends on the signals process 1 of
// the sandbox would lose, starts no program, keeps its caches in the model's folder (`cacheDir`)
// and says errors as --lab does when the parent had --lab. Until the load is over a file past
// --max-file-size costs the cache only.
llvm::Error startSandboxChild(Options& options, std::string& cacheDir);
// The child's side after the load: a file past --max-file-size now ends the run, and the files
// the load read are reported (the parent's --watch watches them).
void reportLoadedInputs(int reportFd, const Session& session, const ModelFiles& files);
// The same for a run that read `files` (a Context Free design and what it imports).
void reportLoadedFiles(int reportFd, const std::vector<std::string>& files);
// The child's reports of its derivation's steps (BatchOptions::progress), none outside a sandbox.
std::function<void(int step)> childProgress(const Options& options);
// What a sandboxed window's run answers with (answerWindow), as its command line says.
WindowAnswerOptions windowAnswerOptions(const Options& options);

}  // namespace lcjit::app
