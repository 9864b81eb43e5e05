// --sandbox (see Sandbox.h, docs/security.md): bubblewrap's command line, the seccomp filter, the
// rlimits, and the parent's side of a sandboxed run (batch and --watch).
#include "app/sandbox/Sandbox.h"

#include <dirent.h>
#include <fcntl.h>
#include <linux/audit.h>
#include <linux/filter.h>
#include <linux/seccomp.h>
#include <poll.h>
#include <sched.h>
#include <sys/prctl.h>
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

#include "app/session/FileMonitor.h"
#include "app/common/FrameSequence.h"
#include "app/sandbox/SandboxCgroup.h"
#include "app/session/Session.h"
#include "runtime/ModelGuard.h"
#include "runtime/Termination.h"
#include "support/InputFile.h"
#include "support/ReplacingFile.h"

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

// The system calls the sandbox refuses, and with what error. Nothing here is one lcjit needs in
// the child (the compile, the JIT, the derivation, Mesa's software renderer).
struct Refused {
  long nr;
  int error;
};
constexpr Refused kRefused[] = {
#if defined(__x86_64__)
    {__NR_fork, EPERM}, {__NR_vfork, EPERM},  // no new processes (clone below)
#endif
    // clone3's flags are behind a pointer a filter cannot read: ENOSYS, so that glibc falls back
    // to clone for its threads.
    {__NR_clone3, ENOSYS},
    // New namespaces: in a user namespace of its own the model could mount a tmpfs, memory that no
    // limit of the sandbox counts, and try the kernel's namespaced code as "root".
    {__NR_unshare, EPERM}, {__NR_setns, EPERM},
    // Memory outside the address space (RLIMIT_AS): files in memory, System V shared memory and
    // message queues, which stay after they are unmapped.
    {__NR_memfd_create, EPERM}, {__NR_memfd_secret, EPERM}, {__NR_shmget, EPERM}, {__NR_msgget, EPERM},
    // Other processes: there are none in the sandbox but lcjit itself (--as-pid-1); refused all the same.
    {__NR_ptrace, EPERM}, {__NR_process_vm_readv, EPERM}, {__NR_process_vm_writev, EPERM},
    {__NR_pidfd_getfd, EPERM}, {__NR_kcmp, EPERM},
    // Kernel interfaces lcjit does not use and that have been ways out of sandboxes.
    {__NR_io_uring_setup, ENOSYS}, {__NR_io_uring_enter, ENOSYS}, {__NR_io_uring_register, ENOSYS},
    {__NR_userfaultfd, EPERM}, {__NR_bpf, EPERM}, {__NR_perf_event_open, EPERM},
    {__NR_add_key, EPERM}, {__NR_request_key, EPERM}, {__NR_keyctl, EPERM},
    // Counted against the user's limits outside the sandbox too (128 inotify instances a user):
    // the parent watches the files, the child has no use for them.
#if defined(__x86_64__)
    {__NR_inotify_init, EPERM},
#endif
    {__NR_inotify_init1, EPERM}, {__NR_fanotify_init, EPERM},
    {__NR_mount, EPERM}, {__NR_umount2, EPERM}, {__NR_pivot_root, EPERM}, {__NR_chroot, EPERM},
    {__NR_open_tree, EPERM}, {__NR_move_mount, EPERM}, {__NR_fsopen, EPERM}, {__NR_fsconfig, EPERM},
    {__NR_fsmount, EPERM}, {__NR_fspick, EPERM}, {__NR_mount_setattr, EPERM},
};

// The seccomp filter (classic BPF) bubblewrap loads before it runs lcjit: the calls of kRefused
// fail; clone makes threads only (CLONE_THREAD), in no new namespace. Every other call is
// allowed; a call of another architecture's ABI (x32, i386 on x86-64) kills the process, since
// its numbers are not the ones checked. RLIMIT_NPROC would be the usual bound on processes, but
// it does not hold for root (the kernel exempts uid 0 whatever the namespace), and a lab may run
// as root.
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
  const uint32_t allow = SECCOMP_RET_ALLOW, deny = SECCOMP_RET_ERRNO | EPERM;
  const uint32_t namespaces = CLONE_NEWNS | CLONE_NEWCGROUP | CLONE_NEWUTS | CLONE_NEWIPC | CLONE_NEWUSER |
                              CLONE_NEWPID | CLONE_NEWNET;
  stmt(BPF_LD | BPF_W | BPF_ABS, offsetof(seccomp_data, arch));
  jump(BPF_JMP | BPF_JEQ | BPF_K, arch, 1, 0);
  stmt(BPF_RET | BPF_K, SECCOMP_RET_KILL_PROCESS);
  stmt(BPF_LD | BPF_W | BPF_ABS, offsetof(seccomp_data, nr));
#if defined(__x86_64__)
  jump(BPF_JMP | BPF_JGE | BPF_K, 0x40000000, 0, 1);  // x32
  stmt(BPF_RET | BPF_K, SECCOMP_RET_KILL_PROCESS);
#endif
  for (const Refused& r : kRefused) {
    jump(BPF_JMP | BPF_JEQ | BPF_K, (uint32_t)r.nr, 0, 1);
    stmt(BPF_RET | BPF_K, SECCOMP_RET_ERRNO | (uint32_t)r.error);
  }
  jump(BPF_JMP | BPF_JEQ | BPF_K, __NR_clone, 1, 0);
  stmt(BPF_RET | BPF_K, allow);
  stmt(BPF_LD | BPF_W | BPF_ABS, offsetof(seccomp_data, args[0]));  // the flags' low half (little-endian)
  jump(BPF_JMP | BPF_JSET | BPF_K, CLONE_THREAD, 0, 2);             // not a thread: refused
  jump(BPF_JMP | BPF_JSET | BPF_K, namespaces, 1, 0);               // a thread in a new namespace: refused
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

// The variables a sandboxed run keeps: the ones lcjit and the compile read. Secrets in variables
// (tokens, agents' sockets) stay out; HOME is the sandbox's scratch /tmp, so that libraries'
// caches (Mesa's) go nowhere. bubblewrap itself is started with these alone: a process shows
// the environment it was started with in /proc/PID/environ, whatever it did to it later.
std::vector<std::string> keptEnvironment() {
  std::vector<std::string> kept;
  for (char** e = environ; *e; ++e) {
    std::string kv = *e;
    size_t eq = kv.find('=');
    if (eq == std::string::npos) continue;
    std::string k = kv.substr(0, eq);
    // lcjit's own by name, as the child reads them (not LCJIT_CACHE_DIR: the cache is the model
    // folder's); a variable that only looks like one of lcjit's is the user's like any other.
    bool keep = k == "PATH" || k == "LANG" || k == "LANGUAGE" || k.rfind("LC_", 0) == 0 || k == "TZ" ||
                k == "CPLUS_INCLUDE_PATH" || k == "CPATH" || k == "C_INCLUDE_PATH" || k == "LCJIT_RUNTIME_INCLUDE" ||
                k == "LCJIT_PREBUILT_DIR" || k == "LCJIT_VERBOSE" || k == "LCJIT_PROGRESS_AFTER_MS";
    if (keep) kept.push_back(kv);
  }
  kept.push_back("HOME=/tmp");
  return kept;
}

// The sandbox's own /dev (the harmless devices), /proc (of its own processes), and a 64 MB /tmp
// and /dev/shm, gone after the run.
std::vector<std::string> ownMounts() {
  return {"--dev", "/dev", "--size", "67108864", "--tmpfs", "/dev/shm", "--remount-ro", "/dev", "--proc", "/proc",
          "--size", "67108864", "--tmpfs", "/tmp"};
}

// The system, read-only: /usr and what the dynamic loader, fontconfig and Mesa read in /etc;
// lcjit's binary and runtime headers where they are not under /usr. Nothing else of the machine
// exists inside: home folders, /root, /var, /run, other users' files, the X and D-Bus sockets.
std::vector<std::string> systemBinds(const std::string& exe) {
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
  return a;
}

// The namespaces and the process: every namespace new, no further user namespaces; lcjit is
// process 1 (--as-pid-1): there is no other process in the sandbox — no init of bubblewrap's that
// the model could read (/proc/1/environ, /proc/1/cmdline) or stop with ptrace, which would leave
// the run waiting for it for ever. A session of its own, the environment of keptEnvironment.
std::vector<std::string> processSettings() {
  std::vector<std::string> a = {"--unshare-all", "--unshare-user", "--disable-userns", "--as-pid-1",
                                "--die-with-parent", "--new-session"};
  // Root outside is nobody inside (without capabilities either way).
  if (::getuid() == 0) a.insert(a.end(), {"--uid", "65534", "--gid", "65534"});
  a.push_back("--clearenv");
  for (const std::string& kv : keptEnvironment()) {
    size_t eq = kv.find('=');
    a.insert(a.end(), {"--setenv", kv.substr(0, eq), kv.substr(eq + 1)});
  }
  return a;
}

std::string bwrapPath() {
  auto p = llvm::sys::findProgramByName("bwrap");
  return p ? *p : std::string();
}

// The tasks (threads) the user has now: RLIMIT_NPROC counts them all, the sandbox's and the
// user's other processes' alike.
uint64_t tasksOfUser(uid_t uid) {
  uint64_t n = 0;
  DIR* proc = ::opendir("/proc");
  for (dirent* e; proc && (e = ::readdir(proc));) {
    if (e->d_name[0] < '0' || e->d_name[0] > '9') continue;
    std::ifstream status(std::string("/proc/") + e->d_name + "/status");
    uid_t real = (uid_t)-1;
    uint64_t threads = 0;
    for (std::string line; std::getline(status, line);) {
      if (line.rfind("Uid:", 0) == 0) real = (uid_t)std::strtoul(line.c_str() + 4, nullptr, 10);
      if (line.rfind("Threads:", 0) == 0) threads = std::strtoull(line.c_str() + 8, nullptr, 10);
    }
    if (real == uid) n += threads;
  }
  if (proc) ::closedir(proc);
  return n;
}

// What spawn's child does between fork and exec.
struct SpawnSetup {
  SandboxLimits limits;
  std::vector<int> keep;        // descriptors the child keeps open
  std::vector<int> cgroups;     // cgroup.procs to join (RunCgroup::joinFds)
  rlim_t tasks = 0;             // RLIMIT_NPROC, 0: unchanged
  bool quiet = false;           // standard output and error to /dev/null
  sigset_t signals{};           // the signal mask to exec with (the parent's before it blocked any)
};

// fork + exec of `argv` with the environment `env`, in a process group of its own, the limits set
// in between (bubblewrap and what it runs inherit them). Only async-signal-safe calls after the
// fork: lcjit has threads.
pid_t spawn(const std::vector<std::string>& argv, const std::vector<std::string>& env, const SpawnSetup& setup) {
  std::vector<char*> cargv, cenv;
  for (const std::string& s : argv) cargv.push_back(const_cast<char*>(s.c_str()));
  cargv.push_back(nullptr);
  for (const std::string& s : env) cenv.push_back(const_cast<char*>(s.c_str()));
  cenv.push_back(nullptr);
  int null = ::open("/dev/null", O_RDWR | O_CLOEXEC);
  pid_t parent = ::getpid();
  pid_t pid = ::fork();
  if (pid != 0) {
    if (pid > 0) ::setpgid(pid, pid);  // both sides: whichever runs first
    if (null >= 0) ::close(null);
    return pid;
  }
  ::setpgid(0, 0);
  // bubblewrap dies with lcjit from its first instruction (it asks for the same itself, but only
  // once it has made the sandbox's process): also when lcjit is killed outright.
  ::prctl(PR_SET_PDEATHSIG, SIGKILL, 0, 0, 0);
  if (::getppid() != parent) _exit(127);
  ::sigprocmask(SIG_SETMASK, &setup.signals, nullptr);
  if (!joinCgroups(setup.cgroups)) _exit(126);
  for (int fd : setup.keep) ::fcntl(fd, F_SETFD, 0);
  if (null >= 0) {
    ::dup2(null, 0);  // no terminal input for the model
    if (setup.quiet) ::dup2(null, 1), ::dup2(null, 2);
  }
  auto set = [](int resource, rlim_t soft, rlim_t hard) {
    struct rlimit r {soft, hard};
    ::setrlimit(resource, &r);
  };
  const SandboxLimits& limits = setup.limits;
  set(RLIMIT_CORE, 0, 0);
  if (limits.memory) set(RLIMIT_AS, limits.memory, limits.memory);
  if (limits.cpuSeconds > 0) {
    rlim_t s = (rlim_t)std::ceil(limits.cpuSeconds);
    set(RLIMIT_CPU, s, s + 1);  // SIGXCPU at the limit; SIGKILL a second later if it is ignored
  }
  if (limits.fileSize) set(RLIMIT_FSIZE, limits.fileSize, limits.fileSize);
  if (limits.files) set(RLIMIT_NOFILE, limits.files, limits.files);
  if (setup.tasks) set(RLIMIT_NPROC, setup.tasks, setup.tasks);
  ::signal(SIGINT, SIG_DFL);
  ::execve(cargv[0], cargv.data(), cenv.data());
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
    for (auto part : {ownMounts(), systemBinds(selfExe()), processSettings()})
      argv.insert(argv.end(), part.begin(), part.end());
    argv.insert(argv.end(), {"--seccomp", std::to_string(sec), "--", "/usr/bin/true"});
    SpawnSetup setup;
    setup.limits.cpuSeconds = 10;
    setup.keep = {sec};
    setup.quiet = true;
    ::sigprocmask(SIG_SETMASK, nullptr, &setup.signals);
    pid_t pid = spawn(argv, keptEnvironment(), setup);
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

namespace {

// Folders every user, or every program of the user's, writes to — and keeps sockets in (an
// ssh-agent's, X11's, D-Bus's, tmux's): a model shown one could read other people's files and
// connect to those sockets, which a read-only bind does not prevent.
std::vector<fs::path> sharedFolders() {
  std::vector<fs::path> shared;
  for (const char* p : {"/tmp", "/var/tmp", "/dev/shm", "/run", "/var/run", "/var/lock", "/run/lock"})
    shared.push_back(canonicalOr(p));
  for (const char* var : {"TMPDIR", "XDG_RUNTIME_DIR"})
    if (const char* v = std::getenv(var); v && *v) shared.push_back(canonicalOr(v));
  return shared;
}

// The folders bubblewrap shows the system in (systemBinds, ownMounts): the output's folder, shown
// as an empty folder of the run's own, must not be one of them, nor hold one.
bool isSystemFolder(const fs::path& f) {
  for (const char* system : {"/usr", "/etc", "/proc", "/dev", "/sys", "/bin", "/sbin", "/lib", "/lib32", "/lib64",
                             "/libx32", "/boot"})
    if (under(f, system) || under(system, f)) return true;
  return false;
}

}  // namespace

llvm::Error checkSandboxFolder(const std::string& folder, const char* what, bool writable) {
  fs::path f = canonicalOr(folder);
  auto refuse = [&](const std::string& why) {
    return llvm::createStringError("lcjit: --sandbox: " + std::string(what) + " '" + f.string() + "' " + why +
                                   "; give the model a folder of its own (docs/security.md)");
  };
  if (f == f.root_path()) return refuse("is the whole file system");
  if (const char* home = std::getenv("HOME"); home && *home && under(canonicalOr(home), f))
    return refuse("holds your home folder");
  for (const fs::path& shared : sharedFolders())
    if (under(shared, f)) return refuse(shared == f ? "is a folder every user writes to" : "holds " + shared.string() + ", a folder every user writes to");
  struct stat st {};
  if (::stat(f.c_str(), &st) == 0 && (st.st_mode & S_IWOTH))
    return refuse("is a folder every user may write to (like /tmp)");
  for (const char* system : {"/usr", "/etc", "/proc", "/dev", "/sys"})
    if (writable && under(f, system)) return refuse("is a system folder");
  return llvm::Error::success();
}

llvm::Error checkSandboxInput(const std::string& input, const std::string& modelFolder, bool folder) {
  fs::path named = fs::absolute(input).lexically_normal();
  fs::path modelDir = canonicalOr(modelFolder), target = canonicalOr(named.string());
  bool namedInside = under(canonicalOr(named.parent_path().string()), modelDir);
  if (namedInside && !under(target, modelDir))
    return llvm::createStringError(
        input + ": error: a link to '" + target.string() +
        "', outside the model's folder; a sandboxed run does not follow it" +
        (folder ? " (name the folder itself: -I " + target.string() + ")" : std::string()) + " (docs/security.md)");
  // Bound into the sandbox, a socket could be connected to; a FIFO or a device read without end.
  struct stat st {};
  if (::stat(target.c_str(), &st) != 0) return llvm::Error::success();  // the run says it is missing
  if (folder && !S_ISDIR(st.st_mode)) return llvm::createStringError(input + ": error: not a folder");
  if (std::error_code refused = support::inputRefusal(st.st_mode); !folder && refused)
    return llvm::createStringError(input + ": error: " + refused.message() +
                                   "; a sandboxed run reads only regular files (docs/security.md)");
  return llvm::Error::success();
}

llvm::Error checkSandboxOutput(const std::string& out, const std::string& modelFolder) {
  fs::path target = canonicalOr(out), folder = target.parent_path();
  auto refuse = [&](const std::string& why) {
    return llvm::createStringError("lcjit: --sandbox: -out " + out + ": " + why + " (docs/security.md)");
  };
  struct stat st {};
  if (::stat(target.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
    return refuse((S_ISDIR(st.st_mode) ? std::string("is a folder") : support::inputRefusal(st.st_mode).message()) +
                  "; name a file, which is all a sandboxed run may write there");
  if (under(target, canonicalOr(modelFolder))) return llvm::Error::success();
  if (::stat(folder.c_str(), &st) != 0 || !S_ISDIR(st.st_mode)) return refuse("its folder " + folder.string() + " is not there");
  if (folder == folder.root_path() || isSystemFolder(folder))
    return refuse("its folder " + folder.string() + " is a system folder; write it in a folder of your own");
  return llvm::Error::success();
}

const std::string& sandboxCgroupUnavailable() {
  static const std::string why = [] {
    std::string w;
    return RunCgroup::create(1ull << 30, 64, w) ? std::string() : w;
  }();
  return why;
}

namespace {
// The run a signal that ends lcjit (SIGTERM, SIGHUP, a second Ctrl-C) must take with it: a
// sandbox still being set up does not die with lcjit by itself (bubblewrap's --die-with-parent
// comes last). One run at a time per lcjit.
std::atomic<SandboxedRun*> gLiveRun{nullptr};
void killLiveRun() {
  if (SandboxedRun* run = gLiveRun.load()) run->killFromSignalHandler();
}
}  // namespace

void SandboxedRun::killFromSignalHandler() {
  if (bwrapPid_ > 0) ::kill(-bwrapPid_, SIGKILL);
  if (childPidFd_ >= 0) ::syscall(SYS_pidfd_send_signal, childPidFd_, SIGKILL, nullptr, 0);
}

llvm::Expected<std::unique_ptr<SandboxedRun>> SandboxedRun::start(const SandboxPlan& plan) {
  static bool registered = (runtime::atTermination(killLiveRun), true);
  (void)registered;
  std::unique_ptr<SandboxedRun> run(new SandboxedRun());
  run->plan_ = plan;
  // An orphan of the sandbox (bubblewrap killed while it set the sandbox up) comes to lcjit,
  // which kills and reaps it, rather than to the machine's process 1.
  ::prctl(PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0);
  std::string exe = selfExe();
  fs::path folder = canonicalOr(plan.modelFolder);
  // The output outside the model's folder: an empty folder beside it, shown at its folder's path.
  if (!plan.outputFile.empty() && !under(plan.outputFile, folder)) {
    std::string pattern = (fs::path(plan.outputFile).parent_path() / ".lcjit-sandbox-out-XXXXXX").string();
    if (!::mkdtemp(pattern.data()))
      return llvm::createStringError("lcjit: --sandbox: cannot make a folder beside " + plan.out + ": " + std::strerror(errno));
    run->staging_ = pattern;
  }
  std::vector<sock_filter> filter = seccompFilter();
  int sec = pipeWith(filter.data(), filter.size() * sizeof(sock_filter));
  int report[2], info[2], reply[2] = {-1, -1};
  if (sec < 0 || ::pipe2(report, O_CLOEXEC) != 0 || ::pipe2(info, O_CLOEXEC) != 0 ||
      (plan.replyLimit && ::pipe2(reply, O_CLOEXEC) != 0))
    return llvm::createStringError(std::string("lcjit: --sandbox: no pipe: ") + std::strerror(errno));
  // A picture is megabytes: a larger pipe lets the child write it in fewer rounds.
  if (reply[0] >= 0) ::fcntl(reply[0], F_SETPIPE_SZ, 1 << 20);
  std::vector<std::string> argv = {bwrapPath()};
  // The order matters: a later bind shows over an earlier one. The output's folder first, so that
  // the system, the inputs and the model's folder show through it where they are inside it.
  for (std::string& a : ownMounts()) argv.push_back(std::move(a));
  if (!run->staging_.empty()) {
    std::string outFolder = fs::path(plan.outputFile).parent_path().string();
    argv.insert(argv.end(), {"--bind", run->staging_, outFolder});
  }
  for (std::string& a : systemBinds(exe)) argv.push_back(std::move(a));
  // Readable next, the model's folder over them: inside a readable folder it stays writable.
  for (const std::string& r : plan.readable) {
    fs::path c = canonicalOr(r);
    if (!under(c, folder)) argv.insert(argv.end(), {"--ro-bind-try", c.string(), c.string()});
  }
  argv.insert(argv.end(), {"--bind", folder.string(), folder.string()});
  for (std::string& a : processSettings()) argv.push_back(std::move(a));
  // The skeleton bubblewrap builds the view in is a tmpfs without a size: read-only, as /dev is,
  // so that the only places to write are the model's folder, the output's and the small /tmp.
  argv.insert(argv.end(), {"--remount-ro", "/", "--chdir", folder.string(), "--seccomp", std::to_string(sec),
                           "--info-fd", std::to_string(info[1]), "--", exe});
  argv.insert(argv.end(), plan.args.begin(), plan.args.end());
  argv.insert(argv.end(), {"--sandboxed", std::to_string(report[1])});
  if (reply[1] >= 0) argv.insert(argv.end(), {"--reply-fd", std::to_string(reply[1])});
  SpawnSetup setup;
  setup.limits = plan.limits;
  setup.keep = {sec, report[1], info[1]};
  if (reply[1] >= 0) setup.keep.push_back(reply[1]);
  std::string noCgroup;
  run->cgroup_ = RunCgroup::create(plan.limits.heldMemory, plan.limits.threads, noCgroup);
  if (run->cgroup_) setup.cgroups = run->cgroup_->joinFds();
  // Without a cgroup, RLIMIT_NPROC bounds the tasks — for a user other than root, and counting
  // the user's tasks elsewhere too (the kernel counts them all).
  else if (::getuid() != 0 && plan.limits.threads) setup.tasks = tasksOfUser(::getuid()) + plan.limits.threads;
  // A signal that ends lcjit between the fork and the run's registration (gLiveRun) would leave
  // bubblewrap unknown to the cleanup: those signals wait until it is registered.
  sigset_t ending;
  sigemptyset(&ending);
  for (int sig : {SIGTERM, SIGHUP, SIGQUIT, SIGINT}) sigaddset(&ending, sig);
  ::sigprocmask(SIG_BLOCK, &ending, &setup.signals);
  pid_t pid = spawn(argv, keptEnvironment(), setup);
  if (pid > 0) {
    run->bwrapPid_ = pid;
    gLiveRun = run.get();
  }
  ::sigprocmask(SIG_SETMASK, &setup.signals, nullptr);
  ::close(sec), ::close(report[1]), ::close(info[1]);
  if (reply[1] >= 0) ::close(reply[1]);
  if (pid < 0) {
    ::close(report[0]), ::close(info[0]);
    if (reply[0] >= 0) ::close(reply[0]);
    return llvm::createStringError(std::string("lcjit: --sandbox: cannot start bwrap: ") + std::strerror(errno));
  }
  run->reportFd_ = report[0];
  run->infoFd_ = info[0];
  run->replyFd_ = reply[0];
  return std::move(run);
}

SandboxedRun::~SandboxedRun() {
  SandboxedRun* self = this;
  gLiveRun.compare_exchange_strong(self, nullptr);
  if (!ended_) {
    stop();
    while (!wait(-1)) {
    }
  }
  killAll();
  reap();
  if (reportFd_ >= 0) ::close(reportFd_);
  if (infoFd_ >= 0) ::close(infoFd_);
  if (replyFd_ >= 0) ::close(replyFd_);
  if (childPidFd_ >= 0) ::close(childPidFd_);
  cgroup_.reset();
  if (!staging_.empty()) {
    std::error_code ec;
    fs::remove_all(staging_, ec);  // what the model left there; links are removed, not followed
  }
}

namespace {
constexpr size_t kReportLine = 64 * 1024;       // an input's path, a status: far shorter
constexpr uint64_t kReportTotal = 64ull << 20;  // what a run may report in all
constexpr size_t kInfoBytes = 64 * 1024;        // bubblewrap's --info-fd: a line of JSON
constexpr size_t kInputs = 100000;              // files one run reports it read
}  // namespace

// One line of the child's report. Unknown lines are dropped: model code can write to the pipe.
void SandboxedRun::takeReportLine(const std::string& line) {
  if (line.rfind("input ", 0) == 0) {
    if (reported_.inputs.size() < kInputs) reported_.inputs.push_back(line.substr(6));
    else reported_.tooManyInputs = true;
  }
  if (line.rfind("status ", 0) == 0) reported_.status = std::atoi(line.c_str() + 7), finished_ = true;
  if (line.rfind("step ", 0) == 0) reported_.steps = std::atoi(line.c_str() + 5);
  if (line == "derived") reported_.derived = true;
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
      if (fd == &reportFd_) {
        reportBytes_ += n;
        if (reportBytes_ > kReportTotal) {
          // Past what any run reports: a model writing to the pipe. Its run is stopped.
          reportFlooded_ = true;
          killAll();
          ::close(*fd);
          *fd = -1;
          break;
        }
        for (ssize_t i = 0; i < n; ++i) {
          if (buf[i] == '\n') {
            takeReportLine(reportLine_);
            reportLine_.clear();
          } else if (reportLine_.size() < kReportLine) {
            reportLine_.push_back(buf[i]);
          }
        }
      } else if (fd == &infoFd_) {
        info_.append(buf, std::min<size_t>(n, kInfoBytes - std::min(kInfoBytes, info_.size())));
      } else if (reply_.size() + n > plan_.replyLimit) {
        // The reply is bounded as the child's memory is: past it, the run is stopped.
        replyTooLong_ = true;
        killAll();
        ::close(*fd);
        *fd = -1;
        reply_.clear();
        break;
      } else {
        reply_.append(buf, n);
      }
    }
  }
  findChild();
}

// bubblewrap's --info-fd: {"child-pid": N, …}, the sandboxed lcjit (process 1 in the sandbox),
// written before the child is let go. Held by a pidfd from then on.
void SandboxedRun::findChild() {
  if (childPid_ > 0) return;
  size_t at = info_.find("\"child-pid\"");
  size_t colon = at == std::string::npos ? at : info_.find(':', at);
  if (colon == std::string::npos) return;
  int pid = std::atoi(info_.c_str() + colon + 1);
  if (pid <= 0) return;
  childPid_ = pid;
  childPidFd_ = (int)::syscall(SYS_pidfd_open, pid, 0);
}

// Every process of the run: bubblewrap's group (with a sandbox it is still setting up), the
// sandboxed lcjit, the run's cgroup.
void SandboxedRun::killAll() {
  if (bwrapPid_ > 0) {
    // Once bubblewrap is reaped, its group's number stays taken only while a member is left —
    // an orphan that came to lcjit (ECHILD: none, and the number may be anyone's by now).
    siginfo_t member{};
    if (!ended_ || ::waitid(P_PGID, (id_t)bwrapPid_, &member, WEXITED | WNOHANG | WNOWAIT) == 0)
      ::kill(-bwrapPid_, SIGKILL);
  }
  if (infoFd_ >= 0) {
    // A child already let go has had its pid written: read it before it is too late to know it.
    struct pollfd p = {infoFd_, POLLIN, 0};
    while (::poll(&p, 1, 0) > 0) {
      char buf[4096];
      ssize_t n = ::read(infoFd_, buf, sizeof buf);
      if (n <= 0) break;
      info_.append(buf, std::min<size_t>(n, kInfoBytes - std::min(kInfoBytes, info_.size())));
    }
    findChild();
  }
  if (childPidFd_ >= 0) ::syscall(SYS_pidfd_send_signal, childPidFd_, SIGKILL, nullptr, 0);
  if (cgroup_) cgroup_->killAll();
}

// Orphans of the run that came to lcjit (PR_SET_CHILD_SUBREAPER): the sandboxed lcjit once its
// bubblewrap died, or a member of bubblewrap's group.
void SandboxedRun::reap() {
  siginfo_t info{};
  if (childPidFd_ >= 0) ::waitid(P_PIDFD, (id_t)childPidFd_, &info, WEXITED | WNOHANG);
  if (bwrapPid_ > 0)
    while (::waitpid(-bwrapPid_, nullptr, WNOHANG) > 0) {
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
      // bubblewrap ends when its child does; killed (stop, a flood), it may leave the child as
      // lcjit's: that is ended here too.
      killAll();
      reap();
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
  killAll();
}

void SandboxedRun::interrupt() { ++interrupts_; }

// Ctrl-C, seen by wait(): the first asks the sandboxed lcjit's guard to interrupt model code
// (docs/faults.md), as without the sandbox; a second, or one before the child runs, ends the run.
void SandboxedRun::passInterruptsOn() {
  int n = interrupts_;
  if (n == interruptsPassed_ || ended_) return;
  interruptsPassed_ = n;
  readReports();
  if (n == 1 && childPidFd_ >= 0) {
    ::syscall(SYS_pidfd_send_signal, childPidFd_, SIGINT, nullptr, 0);
    return;
  }
  userKilled_ = true;
  killAll();
}

// The files -out names, out of the run's own folder into the output's: the -out file, an .obj's
// .mtl, a numbered -out's frames. Only regular files with no other name (not links, which would
// point anywhere, nor hard links to a file elsewhere); the rest stays and is removed with the folder.
bool SandboxedRun::moveOutputsOut() {
  if (staging_.empty()) return true;
  fs::path out(plan_.outputFile), outFolder = out.parent_path();
  std::string name = out.filename().string();
  std::string mtl = out.extension() == ".obj" ? out.stem().string() + ".mtl" : std::string();
  bool numbered = numberedName(name, 0).has_value();
  auto wanted = [&](const std::string& entry) {
    if (entry == name || (!mtl.empty() && entry == mtl)) return true;
    if (!numbered) return false;
    // The frame's number is where the name's digits differ from frame 0's.
    size_t digits = entry.find_first_of("0123456789");
    if (digits == std::string::npos) return false;
    size_t end = entry.find_first_not_of("0123456789", digits);
    std::string number = entry.substr(digits, (end == std::string::npos ? entry.size() : end) - digits);
    if (number.size() > 9) return false;
    auto expected = numberedName(name, std::atoi(number.c_str()));
    return expected && *expected == entry;
  };
  bool ok = true;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(staging_, ec)) {
    std::string entry = e.path().filename().string();
    struct stat st {};
    if (!wanted(entry) || ::lstat(e.path().c_str(), &st) != 0 || !S_ISREG(st.st_mode) || st.st_nlink != 1) continue;
    if (::rename(e.path().c_str(), (outFolder / entry).c_str()) != 0) {
      std::fprintf(stderr, "%s: error: cannot write it: %s\n", (outFolder / entry).c_str(), std::strerror(errno));
      ok = false;
    }
  }
  return ok;
}

SandboxOutcome SandboxedRun::outcome() {
  SandboxOutcome o = judge();
  if (o.status == 0 && !o.stopped && !moveOutputsOut()) o.status = 1;
  if (o.status != 0 && !plan_.outputFile.empty() && staging_.empty())
    support::ReplacingFile::removeUnfinished(plan_.outputFile);
  o.reply = std::move(reply_);
  return o;
}

SandboxOutcome SandboxedRun::judge() {
  if (!reportLine_.empty()) takeReportLine(reportLine_), reportLine_.clear();
  SandboxOutcome o = reported_;
  o.stopped = stopped_;
  if (stopped_) {
    o.status = 2;
    return o;
  }
  std::string when = o.derived      ? fmt::sprintf("after the derivation (%d steps)", o.steps)
                     : o.steps > 0 ? fmt::sprintf("after step %d", o.steps)
                                   : std::string("before the first step");
  auto fault = [&](const std::string& why) {
    o.fault = plan_.model + ": error: the sandboxed run was stopped " + when + ": " + why;
    std::fprintf(stderr, "%s\n", o.fault.c_str());
    o.status = 1;
    return o;
  };
  if (replyTooLong_)
    return fault("its picture was larger than " + runtime::sizeInWords(plan_.replyLimit) + " (--max-memory)");
  if (reportFlooded_)
    return fault("it wrote more than " + runtime::sizeInWords(kReportTotal) +
                 " to lcjit's report pipe (model code writing to a descriptor it was not given?)");
  if (cgroup_ && cgroup_->memoryLimitReached())
    return fault("it held more than " + runtime::sizeInWords(cgroup_->memoryMax()) +
                 " of memory (--max-memory and the compiler's room; the kernel's count, shared memory included)");
  if (finished_) {
    if (cgroup_ && cgroup_->taskLimitReached() && o.status == 0)
      std::fprintf(stderr, "%s: warning: the sandboxed run was refused threads past its limit of %llu (--max-threads)\n",
                   plan_.model.c_str(), (unsigned long long)cgroup_->tasksMax());
    return o;
  }
  if (userKilled_) {
    o.fault = plan_.model + ": error: the sandboxed run was ended (Ctrl-C)";
    std::fprintf(stderr, "%s\n", o.fault.c_str());
    return o;
  }
  // The child did not get to its end: bubblewrap passes a signal on as 128 + its number.
  int sig = WIFSIGNALED(waitStatus_) ? WTERMSIG(waitStatus_)
            : WIFEXITED(waitStatus_) && WEXITSTATUS(waitStatus_) > 128 ? WEXITSTATUS(waitStatus_) - 128
                                                                       : 0;
  if (sig)
    return fault(signalFault(sig, plan_.limits));
  return fault(fmt::sprintf("it ended before lcjit finished it (exit status %d: exit() in model code? "
                            "bwrap's own error above?)",
                            WIFEXITED(waitStatus_) ? WEXITSTATUS(waitStatus_) : -1));
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

bool refuseExec() {
  // Another program in lcjit's place would be outside the guard (no --time-limit, no faults
  // reported) though still in the sandbox. bubblewrap's filter cannot refuse execve (it is how
  // bubblewrap starts lcjit); this one is stacked on it once lcjit runs. no_new_privs is set
  // (bubblewrap sets it for its own filter).
  std::vector<sock_filter> f = {
      BPF_STMT(BPF_LD | BPF_W | BPF_ABS, offsetof(seccomp_data, nr)),
      BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, __NR_execve, 2, 0),
      BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, __NR_execveat, 1, 0),
      BPF_STMT(BPF_RET | BPF_K, SECCOMP_RET_ALLOW),
      BPF_STMT(BPF_RET | BPF_K, SECCOMP_RET_ERRNO | EPERM),
  };
  struct sock_fprog prog = {(unsigned short)f.size(), f.data()};
  return ::syscall(SYS_seccomp, SECCOMP_SET_MODE_FILTER, SECCOMP_FILTER_FLAG_TSYNC, &prog) == 0;
}

void endOnSignals(int sig) {
  static const int kEnding[] = {SIGHUP, SIGINT, SIGQUIT, SIGTERM, SIGXCPU, SIGXFSZ, SIGABRT,
                                SIGUSR1, SIGUSR2, SIGALRM, SIGVTALRM, SIGPROF};
  struct sigaction end {};
  end.sa_handler = [](int s) { _exit(128 + s); };
  sigemptyset(&end.sa_mask);
  for (int s : kEnding)
    if (sig == 0 || s == sig) ::sigaction(s, &end, nullptr);
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
