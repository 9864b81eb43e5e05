// --sandbox (docs/security.md): the model's run — compile, derivation, interpretation, outputs —
// happens in a child lcjit under bubblewrap, with rlimits and no way to start processes; the
// parent relays its output and turns its death by a signal or a limit into an L+C error.
#pragma once
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <llvm/Support/Error.h>

namespace lcjit::app {

struct SandboxLimits {
  uint64_t memory = 0;         // address space (RLIMIT_AS), bytes; 0: none
  double cpuSeconds = 600;     // CPU time of one run (RLIMIT_CPU)
  uint64_t fileSize = 1ull << 30;  // the largest file a run may write (RLIMIT_FSIZE)
};

// What one sandboxed run may see and what it runs.
struct SandboxPlan {
  std::string model;                  // the .l file as the user named it (for messages)
  std::string modelFolder;            // absolute: writable, and the child's working folder
  std::string out;                    // -out as the user named it (for messages), or ""
  // -out (absolute, symbolic links resolved) where it is outside the model's folder: the one
  // file there the run may write.
  std::string outputFile;
  std::vector<std::string> readable;  // files and folders it reads besides (inputs, -I)
  std::vector<std::string> args;      // the child lcjit's arguments
  SandboxLimits limits;
  // > 0: the child answers a window (SandboxReply.h) on a pipe of its own (--reply-fd), in at
  // most this many bytes; a longer reply stops the run.
  uint64_t replyLimit = 0;
};

// "" when bubblewrap can make a sandbox here; otherwise why not (not installed, user namespaces
// switched off…). Tried once per process.
const std::string& sandboxUnavailable();

// A folder the sandbox shows must not hold the user's home (or be the whole system): binding it
// would hand the model ~/.ssh and the rest; nor, when `writable`, be a system folder.
llvm::Error checkSandboxFolder(const std::string& folder, const char* what, bool writable);

// An input file named inside the model's folder must be there, not a link out of it: whoever
// wrote the folder could otherwise have the run shown any file the user can read (a link
// plant.v -> ~/.ssh/id_rsa), or make a folder the link's target the writable one.
llvm::Error checkSandboxInput(const std::string& input, const std::string& modelFolder);

struct SandboxOutcome {
  int status = 1;                   // the exit status to pass on
  bool stopped = false;             // stop() ended it
  std::vector<std::string> inputs;  // the files the run read, as the child reported them
  int steps = 0;                    // derivation steps done, as the child reported them
  bool derived = false;             // the derivation was over
  std::string reply;                // what the child sent on the reply pipe (SandboxPlan::replyLimit)
  // A fault the child could not report itself, as printed on stderr ("" if none).
  std::string fault;
};

// One child lcjit in bubblewrap. The child inherits stdout and stderr.
class SandboxedRun {
 public:
  static llvm::Expected<std::unique_ptr<SandboxedRun>> start(const SandboxPlan& plan);
  ~SandboxedRun();
  // Waits up to `timeoutMs` (< 0: until it ends) while also watching `otherFd` (-1: none);
  // returns true once the run has ended. Reads the child's reports meanwhile.
  bool wait(int timeoutMs, int otherFd = -1);
  void stop();       // kills the run (a newer change under --watch)
  void interrupt();  // Ctrl-C (from a signal handler): the child's model guard interrupts model code
  // After wait() returned true: the status, with a fault the child could not report itself
  // (a signal, a limit) printed on stderr, worded as lcjit's own.
  SandboxOutcome outcome();

 private:
  SandboxedRun() = default;
  void readReports();
  void passInterruptsOn();
  SandboxOutcome judge();
  SandboxPlan plan_;
  int bwrapPid_ = -1, innerPid_ = -1, interruptsPassed_ = 0;
  std::atomic<int> interrupts_{0};  // counted by a signal handler
  int reportFd_ = -1, infoFd_ = -1, replyFd_ = -1;
  std::string reports_, info_, reply_;
  bool replyTooLong_ = false;
  int waitStatus_ = 0;
  bool ended_ = false, stopped_ = false, userKilled_ = false;
  std::string createdOutput_;  // made empty for the bind: removed again when the run fails
};

// Runs the plan once (batch mode), Ctrl-C interrupting the model. Returns the exit status.
int runSandboxedBatch(const SandboxPlan& plan);
// --watch: runs the plan, then again after every change of a file it read, killing a run that
// a newer change makes out of date. Runs until the process is stopped.
int watchSandboxed(const SandboxPlan& plan, bool quiet);

// The child's side: lines on the report descriptor the parent gave with --sandboxed.
void reportInput(int fd, const std::string& path);
void reportStatus(int fd, int status);
void reportProgress(int fd, int step);  // BatchOptions::progress

}  // namespace lcjit::app
