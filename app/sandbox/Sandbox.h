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

class RunCgroup;

struct SandboxLimits {
  uint64_t memory = 0;         // address space (RLIMIT_AS), bytes; 0: none
  // All the memory the run holds — resident, files in memory, the kernel's for it — where it has
  // a cgroup of its own (SandboxCgroup.h); bytes, 0: none.
  uint64_t heldMemory = 0;
  // --max-cpu, --max-file-size, --max-threads (their defaults are the command line's, Options.h):
  double cpuSeconds = 0;       // CPU time of one run (RLIMIT_CPU); 0: none
  uint64_t fileSize = 0;       // the largest file a run may write (RLIMIT_FSIZE); 0: none
  // Tasks (threads) of one run: pids.max of its cgroup, else RLIMIT_NPROC (not for root); 0: none.
  uint64_t threads = 0;
  uint64_t files = 1024;       // open files (RLIMIT_NOFILE): each may hold kernel memory (a socket's buffers)
};

// What one sandboxed run may see and what it runs.
struct SandboxPlan {
  std::string model;                  // the .l file as the user named it (for messages)
  std::string modelFolder;            // absolute: writable, and the child's working folder
  std::string out;                    // -out as the user named it (for messages), or ""
  // -out, absolute, symbolic links resolved. Outside the model's folder the run writes it into an
  // empty folder of its own that the sandbox shows at the output's folder's path; the parent
  // moves the file (and an .obj's .mtl, a numbered -out's frames) out of it after a run that
  // succeeded, and nothing else (checkSandboxOutput).
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
// would hand the model ~/.ssh and the rest; nor be or hold a folder every user writes to (/tmp,
// /run…: other people's files, and the sockets there, which a read-only bind does not keep a
// model from connecting to); nor, when `writable`, be a system folder.
llvm::Error checkSandboxFolder(const std::string& folder, const char* what, bool writable);

// An input named inside the model's folder must be there, not a link out of it: whoever wrote the
// folder could otherwise have the run shown any file the user can read (a link plant.v ->
// ~/.ssh/id_rsa), or make a folder the link's target the writable one. An input file must be a
// regular file: a socket bound into the sandbox could be connected to, a FIFO or a device read
// without end. `folder`: an include folder (-I), which must be a folder.
llvm::Error checkSandboxInput(const std::string& input, const std::string& modelFolder, bool folder = false);

// -out must name a file (a folder would be bound writable whole), in a folder that exists and is
// not a system folder (the sandbox shows that folder as an empty one of its own).
llvm::Error checkSandboxOutput(const std::string& out, const std::string& modelFolder);

// Why a sandboxed run has no cgroup of its own here ("" when it has): said once per process
// (docs/security.md: what the limits then count).
const std::string& sandboxCgroupUnavailable();

struct SandboxOutcome {
  int status = 1;                   // the exit status to pass on
  bool stopped = false;             // stop() ended it
  std::vector<std::string> inputs;  // the files the run read, as the child reported them
  int steps = 0;                    // derivation steps done, as the child reported them
  bool derived = false;             // the derivation was over
  std::string reply;                // what the child sent on the reply pipe (SandboxPlan::replyLimit)
  bool tooManyInputs = false;       // the child reported more inputs than the parent keeps
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
  void killFromSignalHandler();  // lcjit is ending: the run's processes go with it (async-signal-safe)
  // After wait() returned true: the status, with a fault the child could not report itself
  // (a signal, a limit) printed on stderr, worded as lcjit's own.
  SandboxOutcome outcome();

 private:
  SandboxedRun() = default;
  void readReports();
  void takeReportLine(const std::string& line);
  void findChild();
  void killAll();
  void reap();
  void passInterruptsOn();
  bool moveOutputsOut();
  SandboxOutcome judge();
  SandboxPlan plan_;
  // bubblewrap leads a process group of its own (its pid): killing the group takes a sandbox
  // still being set up with it. The sandboxed lcjit (process 1 of the sandbox, --as-pid-1) is
  // known by a pidfd once bubblewrap has said its pid: no other process can take that number.
  int bwrapPid_ = -1, childPid_ = -1, childPidFd_ = -1, interruptsPassed_ = 0;
  std::atomic<int> interrupts_{0};  // counted by a signal handler
  int reportFd_ = -1, infoFd_ = -1, replyFd_ = -1;
  // The child's reports, taken a line at a time as they come: the parent keeps what it
  // understands, bounded, whatever the model writes to the pipe (it can: docs/security.md).
  std::string reportLine_, info_, reply_;
  uint64_t reportBytes_ = 0;
  bool reportFlooded_ = false, replyTooLong_ = false;
  SandboxOutcome reported_;
  bool finished_ = false;  // the child reported its status
  int waitStatus_ = 0;
  bool ended_ = false, stopped_ = false, userKilled_ = false;
  std::unique_ptr<RunCgroup> cgroup_;
  std::string staging_;  // the output's folder as the run sees it (SandboxPlan::outputFile), or ""
};

// Runs the plan once (batch mode), Ctrl-C interrupting the model. Returns the exit status.
int runSandboxedBatch(const SandboxPlan& plan);
// --watch: runs the plan, then again after every change of a file it read, killing a run that
// a newer change makes out of date. Runs until the process is stopped.
int watchSandboxed(const SandboxPlan& plan, bool quiet);

// The child's side. The sandboxed lcjit is process 1 of its PID namespace (--as-pid-1), and the
// kernel gives process 1 no signal whose action is the default but SIGKILL and its own faults:
// SIGXCPU at the CPU limit, SIGXFSZ past the file size, abort()'s SIGABRT would be lost. These
// end it as they end any other process, with 128 + the signal as its status, which bubblewrap
// passes on as it passes a death by a signal. `sig` 0: all of them; else that one.
void endOnSignals(int sig = 0);
// The child's side: no other program in lcjit's place (execve refused from now on, in every
// thread). False if the kernel refused the filter.
bool refuseExec();

// The child's side: lines on the report descriptor the parent gave with --sandboxed.
void reportInput(int fd, const std::string& path);
void reportStatus(int fd, int status);
void reportProgress(int fd, int step);  // BatchOptions::progress

}  // namespace lcjit::app
