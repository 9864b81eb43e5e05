// --sandbox (see Sandbox.h, docs/security.md): bubblewrap's command line, the seccomp filter, the
// rlimits, and the parent's side of a sandboxed run (batch and --watch).
#include "app/Sandbox.h"

#include <fcntl.h>
#include <linux/audit.h>
#include <linux/filter.h>
#include <linux/seccomp.h>
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>

#include <fmt/printf.h>
#include <llvm/Support/Program.h>

#include "app/FileMonitor.h"
#include "app/Session.h"
#include "runtime/ModelGuard.h"
#include "runtime/files/ReplacingFile.h"

extern char** environ;

namespace lcjit::app {
namespace {

namespace fs = std::filesystem;

std::string selfExe() {
  std::error_code ec;
  fs::path p = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string() : p.string();
}

bool under(const fs::path& inner, const fs::path& outer) {
  auto o = outer.begin(), i = inner.begin();
  for (; o != outer.end() && !o->empty(); ++o, ++i)
    if (i == inner.end() || *i != *o) return false;
  return true;
}

fs::path canonicalOr(const std::string& p) {
  std::error_code ec;
  fs::path c = fs::weakly_canonical(fs::absolute(p), ec);
  return ec ? fs::absolute(p).lexically_normal() : c;
}

// The seccomp filter (classic BPF) bubblewrap loads before it runs lcjit: no new processes —
// fork, vfork, clone without CLONE_THREAD fail with EPERM; clone3, whose flags a filter cannot
// read, fails with ENOSYS so that glibc falls back to clone for its threads. Every other call is
// allowed; a call of another architecture's ABI (x32, i386 on x86-64) kills the process, since
// its numbers are not the ones checked. RLIMIT_NPROC would be the usual bound, but it does not
// hold for root (the kernel exempts uid 0 whatever the namespace), and a lab may run as root.
std::vector<sock_filter> seccompFilter() {
#if defined(__x86_64__)
  const uint32_t arch = AUDIT_ARCH_X86_64;
#elif defined(__aarch64__)
  const uint32_t arch = AUDIT_ARCH_AARCH64;
#else
  return {};
#endif
  std::vector<sock_filter> f;
  auto stmt = [&](uint16_t code, uint32_t k) { f.push_back(BPF_STMT(code, k)); };
  auto jump = [&](uint16_t code, uint32_t k, uint8_t jt, uint8_t jf) { f.push_back(BPF_JUMP(code, k, jt, jf)); };
  const uint32_t allow = SECCOMP_RET_ALLOW, deny = SECCOMP_RET_ERRNO | EPERM, nosys = SECCOMP_RET_ERRNO | ENOSYS;
  stmt(BPF_LD | BPF_W | BPF_ABS, offsetof(seccomp_data, arch));
  jump(BPF_JMP | BPF_JEQ | BPF_K, arch, 1, 0);
  stmt(BPF_RET | BPF_K, SECCOMP_RET_KILL_PROCESS);
  stmt(BPF_LD | BPF_W | BPF_ABS, offsetof(seccomp_data, nr));
#if defined(__x86_64__)
  jump(BPF_JMP | BPF_JGE | BPF_K, 0x40000000, 0, 1);  // x32
  stmt(BPF_RET | BPF_K, SECCOMP_RET_KILL_PROCESS);
  jump(BPF_JMP | BPF_JEQ | BPF_K, __NR_fork, 0, 1);
  stmt(BPF_RET | BPF_K, deny);
  jump(BPF_JMP | BPF_JEQ | BPF_K, __NR_vfork, 0, 1);
  stmt(BPF_RET | BPF_K, deny);
#endif
  jump(BPF_JMP | BPF_JEQ | BPF_K, __NR_clone3, 0, 1);
  stmt(BPF_RET | BPF_K, nosys);
  jump(BPF_JMP | BPF_JEQ | BPF_K, __NR_clone, 1, 0);
  stmt(BPF_RET | BPF_K, allow);
  stmt(BPF_LD | BPF_W | BPF_ABS, offsetof(seccomp_data, args[0]));  // the flags' low half (little-endian)
  jump(BPF_JMP | BPF_JSET | BPF_K, CLONE_THREAD, 0, 1);
  stmt(BPF_RET | BPF_K, allow);
  stmt(BPF_RET | BPF_K, deny);
  return f;
}

// A pipe whose read end holds `data` and then ends (bubblewrap reads --seccomp to the end).
int pipeWith(const void* data, size_t size) {
  int p[2];
  if (::pipe2(p, O_CLOEXEC) != 0) return -1;
  bool ok = ::write(p[1], data, size) == (ssize_t)size;  // small: fits the pipe's buffer
  ::close(p[1]);
  if (!ok) {
    ::close(p[0]);
    return -1;
  }
  return p[0];
}

// The sandbox's view of the system, read-only: /usr and what the dynamic loader, fontconfig and
// Mesa read in /etc; lcjit's binary and runtime headers where they are not under /usr. Then the
// namespaces and the process settings. Nothing else of the machine exists inside: home folders,
// /root, /var, /run, other users' files, the X and D-Bus sockets.
std::vector<std::string> systemView(const std::string& exe) {
  std::vector<std::string> a = {"--ro-bind", "/usr", "/usr"};
  for (const char* d : {"/bin", "/sbin", "/lib", "/lib32", "/lib64", "/libx32"}) {
    struct stat st {};
    if (::lstat(d, &st) != 0) continue;
    if (S_ISLNK(st.st_mode)) {
      std::error_code ec;
      fs::path target = fs::read_symlink(d, ec);
      if (!ec) a.insert(a.end(), {"--symlink", target.string(), d});
    } else if (S_ISDIR(st.st_mode)) {
      a.insert(a.end(), {"--ro-bind", d, d});
    }
  }
  for (const char* f : {"/etc/ld.so.cache", "/etc/ld.so.conf", "/etc/ld.so.conf.d", "/etc/fonts", "/etc/localtime",
                        "/etc/alternatives"})
    a.insert(a.end(), {"--ro-bind-try", f, f});
  for (const std::string& p : {exe, runtimeIncludeDir(), prebuiltDir(), std::string(LCJIT_CLANG_RESOURCE_DIR)})
    if (!p.empty() && !under(p, "/usr")) a.insert(a.end(), {"--ro-bind-try", p, p});
  a.insert(a.end(), {"--dev", "/dev", "--size", "67108864", "--tmpfs", "/dev/shm", "--remount-ro", "/dev", "--proc",
                     "/proc", "--size", "67108864", "--tmpfs", "/tmp", "--unshare-all", "--die-with-parent",
                     "--new-session"});
  // Root outside is nobody inside (without capabilities either way).
  if (::getuid() == 0) a.insert(a.end(), {"--uid", "65534", "--gid", "65534"});
  // A clean environment: secrets in variables (tokens, agents' sockets) stay out; HOME is the
  // sandbox's scratch /tmp, so that libraries' caches (Mesa's) go nowhere.
  a.push_back("--clearenv");
  for (char** e = environ; *e; ++e) {
    std::string kv = *e;
    size_t eq = kv.find('=');
    if (eq == std::string::npos) continue;
    std::string k = kv.substr(0, eq);
    bool keep = k == "PATH" || k == "LANG" || k == "LANGUAGE" || k.rfind("LC_", 0) == 0 || k == "TZ" ||
                k == "CPLUS_INCLUDE_PATH" || k == "CPATH" || k == "C_INCLUDE_PATH" ||
                (k.rfind("LCJIT_", 0) == 0 && k != "LCJIT_CACHE_DIR");
    if (keep) a.insert(a.end(), {"--setenv", k, kv.substr(eq + 1)});
  }
  a.insert(a.end(), {"--setenv", "HOME", "/tmp"});
  return a;
}

std::string bwrapPath() {
  auto p = llvm::sys::findProgramByName("bwrap");
  return p ? *p : std::string();
}

// fork + exec of `argv`, the limits set in between (bubblewrap and what it runs inherit them).
// `keep`: descriptors the child keeps open.
pid_t spawn(const std::vector<std::string>& argv, const SandboxLimits& limits, const std::vector<int>& keep,
            bool quiet) {
  std::vector<char*> cargv;
  for (const std::string& s : argv) cargv.push_back(const_cast<char*>(s.c_str()));
  cargv.push_back(nullptr);
  pid_t pid = ::fork();
  if (pid != 0) return pid;
  for (int fd : keep) ::fcntl(fd, F_SETFD, 0);
  int null = ::open("/dev/null", O_RDWR);  // no terminal input for the model
  if (null >= 0) ::dup2(null, 0);
  if (quiet) {
    int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, 1), ::dup2(null, 2);
  }
  auto set = [](int resource, rlim_t soft, rlim_t hard) {
    struct rlimit r {soft, hard};
    ::setrlimit(resource, &r);
  };
  set(RLIMIT_CORE, 0, 0);
  if (limits.memory) set(RLIMIT_AS, limits.memory, limits.memory);
  if (limits.cpuSeconds > 0) {
    rlim_t s = (rlim_t)std::ceil(limits.cpuSeconds);
    set(RLIMIT_CPU, s, s + 1);  // SIGXCPU at the limit; SIGKILL a second later if it is ignored
  }
  if (limits.fileSize) set(RLIMIT_FSIZE, limits.fileSize, limits.fileSize);
  ::signal(SIGINT, SIG_DFL);
  ::execv(cargv[0], cargv.data());
  _exit(127);
}

std::string signalFault(int sig, const SandboxLimits& limits) {
  switch (sig) {
    case SIGXCPU:
      return fmt::sprintf("it used its %g s of CPU time (limit --max-cpu)", std::ceil(limits.cpuSeconds));
    case SIGXFSZ:
      return "it wrote a file past the size limit of " + runtime::sizeInWords(limits.fileSize) + " (--max-file-size)";
    case SIGKILL:
      return "it was killed (SIGKILL): past its CPU time (--max-cpu) or by the system for want of memory";
    case SIGSYS:
      return "it made a system call the sandbox does not allow";
    case SIGSEGV:
    case SIGBUS:
    case SIGILL:
    case SIGFPE:
    case SIGABRT:
      return std::string("lcjit crashed in the sandbox: ") + strsignal(sig);
    default:
      return std::string("it was ended by a signal: ") + strsignal(sig);
  }
}

}  // namespace

const std::string& sandboxUnavailable() {
  static const std::string why = [] {
    std::string bwrap = bwrapPath();
    if (bwrap.empty()) return std::string("bubblewrap (bwrap) is not installed (Debian: apt install bubblewrap)");
    std::vector<sock_filter> filter = seccompFilter();
    if (filter.empty()) return std::string("lcjit has no seccomp filter for this processor");
    int sec = pipeWith(filter.data(), filter.size() * sizeof(sock_filter));
    std::vector<std::string> argv = {bwrap};
    for (std::string& s : systemView(selfExe())) argv.push_back(std::move(s));
    argv.insert(argv.end(), {"--seccomp", std::to_string(sec), "--", "/usr/bin/true"});
    SandboxLimits none;
    none.cpuSeconds = 10;
    pid_t pid = spawn(argv, none, {sec}, true);
    ::close(sec);
    int ws = 0;
    if (pid < 0 || ::waitpid(pid, &ws, 0) != pid) return std::string("bwrap could not be started");
    if (!WIFEXITED(ws) || WEXITSTATUS(ws) != 0)
      return std::string("bwrap cannot make a sandbox here (are user namespaces switched off? "
                         "sysctl kernel.unprivileged_userns_clone, user.max_user_namespaces)");
    return std::string();
  }();
  return why;
}

llvm::Error checkSandboxFolder(const std::string& folder, const char* what, bool writable) {
  fs::path f = canonicalOr(folder);
  auto refuse = [&](const std::string& why) {
    return llvm::createStringError("lcjit: --sandbox: " + std::string(what) + " '" + f.string() + "' " + why +
                                   "; give the model a folder of its own (docs/security.md)");
  };
  if (f == f.root_path()) return refuse("is the whole file system");
  if (const char* home = std::getenv("HOME"); home && *home && under(canonicalOr(home), f))
    return refuse("holds your home folder");
  for (const char* system : {"/usr", "/etc", "/proc", "/dev", "/sys"})
    if (writable && under(f, system)) return refuse("is a system folder");
  return llvm::Error::success();
}

llvm::Error checkSandboxInput(const std::string& input, const std::string& modelFolder) {
  fs::path named = fs::absolute(input).lexically_normal();
  fs::path folder = canonicalOr(modelFolder), target = canonicalOr(named.string());
  bool namedInside = under(canonicalOr(named.parent_path().string()), folder);
  if (!namedInside || under(target, folder)) return llvm::Error::success();
  return llvm::createStringError(input + ": error: a link to '" + target.string() +
                                 "', outside the model's folder; a sandboxed run does not follow it (docs/security.md)");
}

llvm::Expected<std::unique_ptr<SandboxedRun>> SandboxedRun::start(const SandboxPlan& plan) {
  std::unique_ptr<SandboxedRun> run(new SandboxedRun());
  run->plan_ = plan;
  std::string exe = selfExe();
  std::vector<sock_filter> filter = seccompFilter();
  int sec = pipeWith(filter.data(), filter.size() * sizeof(sock_filter));
  int report[2], info[2], reply[2] = {-1, -1};
  if (sec < 0 || ::pipe2(report, O_CLOEXEC) != 0 || ::pipe2(info, O_CLOEXEC) != 0 ||
      (plan.replyLimit && ::pipe2(reply, O_CLOEXEC) != 0))
    return llvm::createStringError(std::string("lcjit: --sandbox: no pipe: ") + std::strerror(errno));
  // A picture is megabytes: a larger pipe lets the child write it in fewer rounds.
  if (reply[0] >= 0) ::fcntl(reply[0], F_SETPIPE_SZ, 1 << 20);
  std::vector<std::string> argv = {bwrapPath()};
  for (std::string& s : systemView(exe)) argv.push_back(std::move(s));
  // Readable first, the model's folder over them: inside a readable folder it stays writable.
  fs::path folder = canonicalOr(plan.modelFolder);
  for (const std::string& r : plan.readable) {
    fs::path c = canonicalOr(r);
    if (!under(c, folder)) argv.insert(argv.end(), {"--ro-bind-try", c.string(), fs::absolute(r).string()});
  }
  argv.insert(argv.end(), {"--bind", folder.string(), folder.string()});
  if (!plan.outputFile.empty() && !under(plan.outputFile, folder)) {
    // The output file alone, not its folder (which may be anything: the home's .config…);
    // bubblewrap binds only what exists.
    int fd = ::open(plan.outputFile.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd >= 0) ::close(fd), run->createdOutput_ = plan.outputFile;
    argv.insert(argv.end(), {"--bind", plan.outputFile, plan.outputFile});
  }
  // The skeleton bubblewrap builds the view in is a tmpfs without a size: read-only, as /dev is,
  // so that the only places to write are the model's folder, the output and the small /tmp.
  argv.insert(argv.end(), {"--remount-ro", "/", "--chdir", folder.string(), "--seccomp", std::to_string(sec),
                           "--info-fd", std::to_string(info[1]), "--", exe});
  argv.insert(argv.end(), plan.args.begin(), plan.args.end());
  argv.insert(argv.end(), {"--sandboxed", std::to_string(report[1])});
  if (reply[1] >= 0) argv.insert(argv.end(), {"--reply-fd", std::to_string(reply[1])});
  std::vector<int> keep = {sec, report[1], info[1]};
  if (reply[1] >= 0) keep.push_back(reply[1]);
  pid_t pid = spawn(argv, plan.limits, keep, false);
  ::close(sec), ::close(report[1]), ::close(info[1]);
  if (reply[1] >= 0) ::close(reply[1]);
  if (pid < 0) {
    ::close(report[0]), ::close(info[0]);
    if (reply[0] >= 0) ::close(reply[0]);
    return llvm::createStringError(std::string("lcjit: --sandbox: cannot start bwrap: ") + std::strerror(errno));
  }
  run->bwrapPid_ = pid;
  run->reportFd_ = report[0];
  run->infoFd_ = info[0];
  run->replyFd_ = reply[0];
  return std::move(run);
}

SandboxedRun::~SandboxedRun() {
  if (!ended_) {
    stop();
    while (!wait(-1)) {
    }
  }
  if (reportFd_ >= 0) ::close(reportFd_);
  if (infoFd_ >= 0) ::close(infoFd_);
  if (replyFd_ >= 0) ::close(replyFd_);
}

void SandboxedRun::readReports() {
  static char buf[1 << 16];
  for (int* fd : {&reportFd_, &infoFd_, &replyFd_}) {
    if (*fd < 0) continue;
    for (;;) {
      struct pollfd p = {*fd, POLLIN, 0};
      if (::poll(&p, 1, 0) <= 0) break;
      ssize_t n = ::read(*fd, buf, sizeof buf);
      if (n <= 0) {
        ::close(*fd);
        *fd = -1;
        break;
      }
      std::string& to = fd == &reportFd_ ? reports_ : fd == &infoFd_ ? info_ : reply_;
      if (fd == &replyFd_ && reply_.size() + n > plan_.replyLimit) {
        // The reply is bounded as the child's memory is: past it, the run is stopped.
        replyTooLong_ = true;
        if (!ended_) ::kill(bwrapPid_, SIGKILL);
        ::close(*fd);
        *fd = -1;
        reply_.clear();
        break;
      }
      to.append(buf, n);
    }
  }
  if (innerPid_ < 0) {
    // bubblewrap's --info-fd: {"child-pid": N, …}, its process 1 in the sandbox, whose child is
    // the sandboxed lcjit (bubblewrap does not pass signals on).
    size_t at = info_.find("\"child-pid\"");
    size_t colon = at == std::string::npos ? at : info_.find(':', at);
    if (colon != std::string::npos) {
      int init = std::atoi(info_.c_str() + colon + 1);
      std::ifstream children("/proc/" + std::to_string(init) + "/task/" + std::to_string(init) + "/children");
      int pid = -1;
      if (children >> pid) innerPid_ = pid;
    }
  }
}

bool SandboxedRun::wait(int timeoutMs, int otherFd) {
  using Clock = std::chrono::steady_clock;
  auto until = Clock::now() + std::chrono::milliseconds(timeoutMs < 0 ? 0 : timeoutMs);
  while (!ended_) {
    passInterruptsOn();
    readReports();
    int ws = 0;
    pid_t r = ::waitpid(bwrapPid_, &ws, WNOHANG);
    if (r == bwrapPid_) {
      waitStatus_ = ws;
      ended_ = true;
      readReports();  // what the child wrote last
      break;
    }
    // The child's end shows as its pipes closing, or at the latest at the next 50 ms.
    struct pollfd fds[4];
    int n = 0;
    for (int fd : {reportFd_, infoFd_, replyFd_, otherFd})
      if (fd >= 0) fds[n++] = {fd, POLLIN, 0};
    long long toGo = std::chrono::duration_cast<std::chrono::milliseconds>(until - Clock::now()).count();
    int left = timeoutMs < 0 ? 50 : (int)std::min<long long>(50, toGo);
    if (timeoutMs >= 0 && left <= 0) return false;
    int ready = ::poll(fds, n, left);
    if (otherFd >= 0 && ready > 0 && (fds[n - 1].revents & POLLIN)) return false;
  }
  return true;
}

void SandboxedRun::stop() {
  stopped_ = true;
  if (bwrapPid_ > 0 && !ended_) ::kill(bwrapPid_, SIGKILL);  // --die-with-parent takes the sandbox with it
}

void SandboxedRun::interrupt() { ++interrupts_; }

// Ctrl-C, seen by wait(): the first asks the sandboxed lcjit's guard to interrupt model code
// (docs/faults.md), as without the sandbox; a second, or one before the child runs, ends the run.
void SandboxedRun::passInterruptsOn() {
  int n = interrupts_;
  if (n == interruptsPassed_ || ended_) return;
  interruptsPassed_ = n;
  readReports();
  if (n == 1 && innerPid_ > 0) {
    ::kill(innerPid_, SIGINT);
    return;
  }
  userKilled_ = true;
  ::kill(bwrapPid_, SIGKILL);
}

SandboxOutcome SandboxedRun::outcome() {
  SandboxOutcome o = judge();
  if (o.status != 0 && !createdOutput_.empty()) ::unlink(createdOutput_.c_str());
  if (o.status != 0 && !plan_.outputFile.empty()) runtime::ReplacingFile::removeUnfinished(plan_.outputFile);
  o.reply = std::move(reply_);
  return o;
}

SandboxOutcome SandboxedRun::judge() {
  SandboxOutcome o;
  o.stopped = stopped_;
  bool finished = false;
  std::istringstream lines(reports_);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("input ", 0) == 0) o.inputs.push_back(line.substr(6));
    if (line.rfind("status ", 0) == 0) o.status = std::atoi(line.c_str() + 7), finished = true;
    if (line.rfind("step ", 0) == 0) o.steps = std::atoi(line.c_str() + 5);
    if (line == "derived") o.derived = true;
  }
  if (stopped_) {
    o.status = 2;
    return o;
  }
  std::string when = o.derived      ? fmt::sprintf("after the derivation (%d steps)", o.steps)
                     : o.steps > 0 ? fmt::sprintf("after step %d", o.steps)
                                   : std::string("before the first step");
  if (replyTooLong_) {
    o.fault = fmt::sprintf("%s: error: the sandboxed run was stopped %s: its picture was larger than %s (--max-memory)",
                     plan_.model.c_str(), when.c_str(), runtime::sizeInWords(plan_.replyLimit).c_str());
    std::fprintf(stderr, "%s\n", o.fault.c_str());
    o.status = 1;
    return o;
  }
  if (finished) return o;
  if (userKilled_) {
    o.fault = plan_.model + ": error: the sandboxed run was ended (Ctrl-C)";
    std::fprintf(stderr, "%s\n", o.fault.c_str());
    return o;
  }
  // The child did not get to its end: bubblewrap passes a signal on as 128 + its number.
  int sig = WIFSIGNALED(waitStatus_) ? WTERMSIG(waitStatus_)
            : WIFEXITED(waitStatus_) && WEXITSTATUS(waitStatus_) > 128 ? WEXITSTATUS(waitStatus_) - 128
                                                                       : 0;
  std::string why = sig ? signalFault(sig, plan_.limits)
                        : fmt::sprintf("it ended before lcjit finished it (exit status %d: exit() in model code? "
                                 "bwrap's own error above?)",
                                 WIFEXITED(waitStatus_) ? WEXITSTATUS(waitStatus_) : -1);
  o.fault = plan_.model + ": error: the sandboxed run was stopped " + when + ": " + why;
  std::fprintf(stderr, "%s\n", o.fault.c_str());
  o.status = 1;
  return o;
}

namespace {
std::atomic<SandboxedRun*> activeRun{nullptr};
void onInterrupt(int) {
  if (SandboxedRun* run = activeRun) run->interrupt();
  else _exit(130);
}

// A run of the terminal's modes: Ctrl-C goes to it while it lasts. Null (the reason said) when
// it cannot start.
std::unique_ptr<SandboxedRun> startWithCtrlC(const SandboxPlan& plan) {
  auto run = SandboxedRun::start(plan);
  if (!run) {
    std::fprintf(stderr, "%s\n", llvm::toString(run.takeError()).c_str());
    return nullptr;
  }
  activeRun = run->get();
  std::signal(SIGINT, onInterrupt);
  return std::move(*run);
}
}  // namespace

int runSandboxedBatch(const SandboxPlan& plan) {
  std::unique_ptr<SandboxedRun> run = startWithCtrlC(plan);
  if (!run) return 1;
  run->wait(-1);
  activeRun = nullptr;
  return run->outcome().status;
}

int watchSandboxed(const SandboxPlan& plan, bool quiet) {
  FileMonitor monitor;
  std::vector<std::string> watched;
  auto watchInputs = [&](std::vector<std::string> now) {
    if (now.empty()) now = {fs::absolute(plan.model).string()};  // nothing reported: the model at least
    if (now == watched) return;
    watched = std::move(now);
    if (!monitor.watch(watched)) std::fprintf(stderr, "lcjit: file monitoring: %s\n", monitor.error().c_str());
  };
  watchInputs({});
  std::vector<std::string> changed;
  std::string names;  // of the changes that started this run
  for (int reload = 0;; ++reload) {
    auto t0 = std::chrono::steady_clock::now();
    std::unique_ptr<SandboxedRun> run = startWithCtrlC(plan);
    if (!run) return 1;
    // A save during the run makes it out of date: stop it and run the newer model.
    while (!run->wait(50, monitor.fd())) {
      std::vector<std::string> now = monitor.poll(0);
      changed.insert(changed.end(), now.begin(), now.end());
      if (!changed.empty()) run->stop();
    }
    activeRun = nullptr;
    std::signal(SIGINT, SIG_DFL);
    SandboxOutcome o = run->outcome();
    watchInputs(o.inputs);
    double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    std::string what;
    if (o.stopped) what = "its run stopped for a newer change";
    else if (o.status != 0)
      what = "the run failed" + (plan.out.empty() ? "" : ", nothing written: " + plan.out + " is the last good run's");
    else what = fmt::sprintf("ran in %.1f ms", ms) + (plan.out.empty() ? "" : ", wrote " + plan.out);
    if (reload == 0 && !quiet)
      std::fprintf(stderr, "lcjit: watching %s and its input files; every run is sandboxed (docs/security.md)\n",
                   plan.model.c_str());
    if (reload > 0) std::fprintf(stderr, "lcjit: reload %d (%s): %s\n", reload, names.c_str(), what.c_str());
    if (changed.empty()) changed = monitor.poll(-1);
    names.clear();
    for (const std::string& c : changed) names += (names.empty() ? "" : ", ") + fs::path(c).filename().string();
    changed.clear();
  }
}

void reportInput(int fd, const std::string& path) {
  std::string line = "input " + path + "\n";
  (void)!::write(fd, line.data(), line.size());
}

void reportProgress(int fd, int step) {
  std::string line = step < 0 ? std::string("derived\n") : "step " + std::to_string(step) + "\n";
  (void)!::write(fd, line.data(), line.size());
}

void reportStatus(int fd, int status) {
  std::string line = "status " + std::to_string(status) + "\n";
  (void)!::write(fd, line.data(), line.size());
}

}  // namespace lcjit::app
