// --sandbox as the command line asks for it (SandboxMode.h).
#include "app/sandbox/SandboxMode.h"

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>

#include "app/cli/Modes.h"
#include "app/sandbox/Sandbox.h"
#include "app/session/InputKinds.h"
#include "app/session/Languages.h"
#include "runtime/turtle/Drawing.h"
#if LCJIT_HAVE_WINDOW
#include "app/window/WindowMode.h"
#endif

namespace lcjit::app {

namespace fs = std::filesystem;

int runSandboxed(Options o, bool labWindow) {
  auto refused = [](llvm::Error e) {
    std::fprintf(stderr, "%s\n", llvm::toString(std::move(e)).c_str());
    return 1;
  };
  if (!o.runRecord.empty() || o.outs.size() > 1) {  // the sandbox lets its run write one -out
    std::fprintf(stderr, "lcjit: --sandbox's runs write one -out file and no --run-record\n");
    return 1;
  }
  if (!o.profile.empty() && o.profile != "-") {  // the same: the table is printed instead
    std::fprintf(stderr, "lcjit: --sandbox's runs write one -out file: --profile alone prints the profile as a "
                         "table, not to %s\n", o.profile.c_str());
    return 1;
  }
  if (o.debugger) {  // the model would run in the sandbox's process, not the debugged one
    std::fprintf(stderr, "lcjit: --debugger debugs model code in lcjit's own process: not with --sandbox or --lab\n");
    return 1;
  }
  const bool window = opensWindow(o);
  const std::string model = modelOf(o.inputs);
  if (const Language* language = languageOf(model); window && language && language->engine != EngineKind::LSystem) {
    std::fprintf(stderr, "lcjit: the window over sandboxed runs shows L-systems; a %s runs sandboxed in batch "
                         "mode or with --watch (-b, -out)\n", std::string(language->model).c_str());
    return 1;
  }
  if (!o.batch && o.outs.empty() && !o.emitCpp && !o.compileOnly && !window) {
    o.outs = {shownIn(model.empty() ? o.inputs.back() : model)};
    if (!o.quiet) std::fprintf(stderr, "lcjit: no display; writing %s\n", o.outs[0].c_str());
  }
  SandboxPlan plan;
  plan.model = model;
  if (plan.model.empty()) {
    std::fprintf(stderr, "error: %s\n", noModelGiven().c_str());
    return 1;
  }
  plan.out = o.outs.empty() ? "" : o.outs[0];
  plan.modelFolder = fs::weakly_canonical(fs::absolute(plan.model).lexically_normal().parent_path()).string();
  if (auto e = checkSandboxFolder(plan.modelFolder, "the model's folder", true)) return refused(std::move(e));
  for (const std::string& in : o.inputs)
    if (auto e = checkSandboxInput(in, plan.modelFolder)) return refused(std::move(e));
  // What needs a process of its own cannot run in the sandbox, which starts none.
  if (fs::exists(fs::path(plan.modelFolder) / "lpfg.mak")) {
    std::fprintf(stderr, "%s: error: lcjit reads lpfg.mak with make, a program, and a sandboxed run starts none "
                         "(docs/security.md)\n", (fs::path(plan.modelFolder) / "lpfg.mak").c_str());
    return 1;
  }
  for (const std::string& in : o.inputs)
    if (fileKindOf(in) == FileKind::Environment) {
      std::fprintf(stderr, "%s: error: an environmental program is a process of its own, and a sandboxed run "
                           "starts none (docs/security.md)\n", in.c_str());
      return 1;
    }
  // The sandbox binds paths as they are: the child names them the same way, links resolved.
  auto resolved = [](const std::string& p) { return fs::weakly_canonical(fs::absolute(p)).string(); };
  if (!o.outs.empty()) {
    if (auto e = checkSandboxOutput(o.outs[0], plan.modelFolder)) return refused(std::move(e));
    plan.outputFile = o.outs[0] = resolved(o.outs[0]);
  }
  Options child = o;  // what the child runs with: paths as the sandbox shows them
  child.inputs.clear();
  for (const std::string& in : o.inputs) child.inputs.push_back(resolved(in));
  plan.readable = child.inputs;
  std::vector<std::string> folders = o.includeDirs;
  for (const char* var : {"CPLUS_INCLUDE_PATH", "CPATH", "C_INCLUDE_PATH"})
    if (const char* v = std::getenv(var)) {
      std::stringstream list(v);
      for (std::string dir; std::getline(list, dir, ':');)
        if (!dir.empty()) folders.push_back(fs::absolute(dir).lexically_normal().string());
    }
  for (const std::string& dir : folders) {
    if (auto e = checkSandboxInput(dir, plan.modelFolder, true)) return refused(std::move(e));
    if (auto e = checkSandboxFolder(dir, "the include folder", false)) return refused(std::move(e));
    plan.readable.push_back(resolved(dir));
  }
  // The child works in the model's folder: it gets -I as the sandbox shows them, resolved.
  for (std::string& dir : child.includeDirs) dir = resolved(dir);
  plan.limits.cpuSeconds = o.maxCpuSeconds;
  plan.limits.fileSize = o.maxFileSize;
  plan.limits.threads = o.maxThreads;
  // Address space, not resident memory: the compiler and the threads reserve more than they
  // use; --max-memory (resident) is the child's guard's, with its messages.
  plan.limits.memory = o.maxMemory + (uint64_t(2) << 30);
  // All it holds, counted by the kernel where the run has a cgroup: --max-memory and the
  // compiler's room (a compile's peak is some 200 MB).
  plan.limits.heldMemory = o.maxMemory + (uint64_t(1) << 30);
  if (o.verbose) {
    const std::string& noCgroup = sandboxCgroupUnavailable();
    std::fprintf(stderr, "lcjit: --sandbox: %s\n",
                 noCgroup.empty() ? "each run has a cgroup of its own (memory held, threads)"
                                  : ("no cgroup for a run (" + noCgroup + "): memory is bounded by the address space "
                                     "and the seccomp filter, threads by RLIMIT_NPROC (docs/security.md)").c_str());
  }
  // Each run is a batch run (or -c, --emit-cpp); --lab's plain errors go with it.
  child.batch = !o.compileOnly && !o.emitCpp;
  child.plainErrors = o.lab;
  if (window) child.profile.clear();  // each picture is a run: no table on the terminal for each
  plan.args = childArguments(child);
#if LCJIT_HAVE_WINDOW
  if (window) {
    plan.replyLimit = o.maxMemory;  // the picture is held as the child held it
    if (labWindow && !o.quiet)
      std::fprintf(stderr, "lcjit: --lab: the window shows runs made in a sandbox; every run is sandboxed "
                           "(docs/security.md); the REPL, whose C++ would run outside it, is off\n");
    return runSandboxedWindow(plan, windowOptions(o), interactiveOptions(o, compileTiers(o, window)));
  }
#endif
  if (o.watch && !o.emitCpp && !o.compileOnly) return watchSandboxed(plan, o.quiet);
  return runSandboxedBatch(plan);
}

llvm::Error startSandboxChild(Options& o, std::string& cacheDir) {
  endOnSignals();
  if (!refuseExec())
    return llvm::createStringError(std::string("lcjit: --sandbox: the seccomp filter against execve was refused: ") +
                                   std::strerror(errno));
  // In the sandbox: caches in the model's folder, the only place this process may write and
  // one that no other model's run shares (docs/security.md).
  if (std::string inModelFolder = cacheInModelFolder(o.inputs); !inModelFolder.empty()) cacheDir = inModelFolder;
  o.lab = o.lab || o.plainErrors;
  // A cache file past --max-file-size (the compiled header is some MB) fails to be written and
  // costs the cache only; from the run on, such a file ends the run (the parent says why).
  std::signal(SIGXFSZ, SIG_IGN);
  return llvm::Error::success();
}

void reportLoadedInputs(int reportFd, const Session& session, const ModelFiles& files) {
  const runtime::DrawingFiles none;
  reportLoadedFiles(reportFd, watchedFiles(files, session.loaded() ? session.drawing() : none));
}

void reportLoadedFiles(int reportFd, const std::vector<std::string>& files) {
  endOnSignals(SIGXFSZ);
  for (const std::string& f : files) reportInput(reportFd, f);
}

std::function<void(int step)> childProgress(const Options& o) {
  if (o.reportFd < 0) return nullptr;
  return [fd = o.reportFd](int step) { reportProgress(fd, step); };
}

WindowAnswerOptions windowAnswerOptions(const Options& o) {
  WindowAnswerOptions wo;
  wo.replyFd = o.replyFd;
  wo.toStep = o.toStep;
  wo.quiet = o.quiet;
  wo.plainErrors = o.lab;
  wo.debug = o.debug;
  wo.progress = childProgress(o);
  return wo;
}

}  // namespace lcjit::app
