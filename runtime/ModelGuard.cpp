// The guard around model code (see ModelGuard.h and docs/faults.md).
#include "runtime/ModelGuard.h"
#include "runtime/Termination.h"

#include <cxxabi.h>
#include <fcntl.h>
#include <link.h>
#include <malloc.h>
#include <poll.h>
#include <pthread.h>
#include <setjmp.h>
#include <signal.h>
#include <sys/mman.h>
#include <time.h>
#include <ucontext.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cinttypes>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <bits/functexcept.h>  // std::__throw_out_of_range & co.: the helpers model code calls to throw
#include <mutex>
#include <new>
#include <thread>
#include <typeinfo>
#include <unwind.h>

namespace lcjit::runtime {

// A thread's ModelStops: how many are alive (thrown and not yet destroyed: unwinding, or caught
// by a handler that has not let go), and how many were ever thrown.
struct StopCounts {
  std::atomic<int> alive{0}, thrown{0};
};

// The watchdog reaches into ModelGuard's state through this (ModelGuard.h keeps it private).
struct GuardInternals {
  static std::atomic<int>& stop(ModelGuard& g) { return g.stop_; }
  static std::atomic<bool>& force(ModelGuard& g) { return g.force_; }
  static std::atomic<bool>& forceAsleep(ModelGuard& g) { return g.forceAsleep_; }
  static int& depth(ModelGuard& g) { return g.depth_; }
  static uint64_t& thread(ModelGuard& g) { return g.thread_; }
  static int64_t& deadline(ModelGuard& g) { return g.deadlineNs_; }
  static std::atomic<int64_t>& stopSince(ModelGuard& g) { return g.stopSinceNs_; }
  static std::atomic<int64_t>& stopCpu(ModelGuard& g) { return g.stopCpuNs_; }
  static std::atomic<bool>& stopThrown(ModelGuard& g) { return g.stopThrown_; }
  static int& tid(ModelGuard& g) { return g.tid_; }
  static clockid_t& cpuClock(ModelGuard& g) { return g.cpuClock_; }
  static const StopCounts*& stops(ModelGuard& g) { return g.stops_; }
  static std::atomic<int>& stopsThrownAtStop(ModelGuard& g) { return g.stopsThrownAtStop_; }
  static std::atomic<bool>& running(ModelGuard& g) { return g.running_; }
  static int64_t& forceSince(ModelGuard& g) { return g.forceSinceNs_; }
  static int64_t& entered(ModelGuard& g) { return g.enteredNs_; }
  static int64_t& waitAtEnter(ModelGuard& g) { return g.waitAtEnterNs_; }
  static std::atomic<size_t>& observed(ModelGuard& g) { return g.observedBytes_; }
  static const GuardLimits& limits(const ModelGuard& g) { return g.limits_; }
};
using GI = GuardInternals;

namespace {

constexpr int kCrashSignals[] = {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT};
constexpr int kInterruptSignal = SIGUSR2;
// An interrupt is cooperative first (the engine and the host functions check, and unwind); only
// a thread still inside after a grace period is made to jump. The grace is the thread's own CPU
// time, not the clock's: on a busy machine a thread may wait long for the processor, and a jump
// while it unwinds would skip the destructors that free what the model holds. kGraceNs of CPU
// time once asked; kUnwindGraceNs while the first ModelStop thrown since is alive (unwinding, or
// a handler of the model's own that has caught it and not let go; a second one means the model
// caught the first and went on); and a thread that sleeps (in a system call: it uses no CPU time)
// is made to jump after kBlockedGraceNs on the clock. A grace is only ever the time to get to the
// next checkpoint: one that runs out first (the thread slept, or was held up in a long call of
// the host's, or by a busy machine whose stolen time counts as its own) takes nothing from the
// thread's first ModelStop, which is thrown there all the same, the force taken back and the
// unwinding grace counted from then (Watchdog::unwindingBegins).
constexpr int64_t kGraceNs = 5'000'000;
constexpr int64_t kUnwindGraceNs = 2'000'000'000;
constexpr int64_t kBlockedGraceNs = 100'000'000;
// Then SIGUSR2 every kForceTickNs until it lands in JIT'd code. Never in host code while it runs:
// a jump out of lcjit's or libc's code (a vector growing, malloc) leaves their data half changed
// (a double free); host loops check for a stop themselves instead. Only a thread
// that has been asleep in a system call for kForceAnywhereNs (a model blocked in read()) is
// jumped out of wherever it sleeps.
constexpr int64_t kForceTickNs = 250'000;
constexpr int64_t kForceAnywhereNs = 1'000'000'000;
constexpr int64_t kTickNs = 2'000'000;     // watchdog period while model code runs
constexpr int64_t kLingerNs = 200'000'000;  // keep ticking this long after the last run ended

int64_t nsOf(clockid_t clock) {
  timespec t;
  if (clock_gettime(clock, &t) != 0) return 0;
  return int64_t(t.tv_sec) * 1'000'000'000 + t.tv_nsec;
}
int64_t nowNs() { return nsOf(CLOCK_MONOTONIC); }

// How long thread `tid` of this process (0: the calling thread) has waited for a processor, in
// ns: the second field of its schedstat (Linux's scheduler statistics); -1 where there are none.
int64_t runQueueWaitNs(int tid) {
  char path[64], buf[128];
  if (tid) std::snprintf(path, sizeof path, "/proc/self/task/%d/schedstat", tid);
  else std::snprintf(path, sizeof path, "/proc/thread-self/schedstat");
  int fd = open(path, O_RDONLY | O_CLOEXEC);
  if (fd < 0) return -1;
  ssize_t n = read(fd, buf, sizeof buf - 1);
  close(fd);
  if (n <= 0) return -1;
  buf[n] = 0;
  unsigned long long onCpu = 0, waited = 0;
  return std::sscanf(buf, "%llu %llu", &onCpu, &waited) == 2 ? int64_t(waited) : -1;
}

// Whether thread `tid` of this process is asleep or waiting ('S', 'D', …), not running or
// runnable ('R'): /proc/self/task/TID/stat's state field.
bool threadAsleep(int tid) {
  char path[64], buf[256];
  std::snprintf(path, sizeof path, "/proc/self/task/%d/stat", tid);
  int fd = open(path, O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  ssize_t n = read(fd, buf, sizeof buf - 1);
  close(fd);
  if (n <= 0) return false;
  buf[n] = 0;
  const char* paren = std::strrchr(buf, ')');  // the name may hold spaces and parentheses
  return paren && paren[1] == ' ' && paren[2] != 'R';
}

thread_local StopCounts tlStops;

// How many runs have been asked to stop and have not ended: model code reads it at every module
// it emits (lcjit_stops_asked, lcjit/abi.h's __lc_put) and, when it is not zero, checks its own
// run (lcjit_checkpoint), so that a stop inside an nproduce loop unwinds from the nproduce.
std::atomic<int> gStopsAsked{0};
static_assert(sizeof(gStopsAsked) == sizeof(int) && std::atomic<int>::is_always_lock_free,
              "model code reads it as a volatile int");

// One guarded run on one thread. Signals jump to the innermost; the handler fills in what it saw.
struct Region {
  sigjmp_buf env;
  ModelGuard* guard = nullptr;
  Region* outer = nullptr;
  volatile int signo = 0, code = 0, stopKind = 0;
  void* volatile addr = nullptr;
  volatile uintptr_t sp = 0, pc = 0;
  // The calls the thread was inside (Fault::callers), taken by the crash handler, by a ModelStop,
  // or by a throw in model code: then `thrown` is the object thrown (kByLibrary: thrown by the
  // C++ library's helper that model code called).
  static constexpr int kFrames = 24;
  void* frames[kFrames];
  volatile int framesTaken = 0;
  const void* volatile thrown = nullptr;
  char assertion[200] = "";  // the condition of a failed assert() in model code
};

thread_local Region* tlRegion = nullptr;

// ---- where the thread was when the signal came

uintptr_t pcOf(void* uc) {
  auto* c = static_cast<ucontext_t*>(uc);
#if defined(__x86_64__)
  return uintptr_t(c->uc_mcontext.gregs[REG_RIP]);
#elif defined(__aarch64__)
  return uintptr_t(c->uc_mcontext.pc);
#else
  (void)c;
  return 0;
#endif
}

uintptr_t spOf(void* uc) {
  auto* c = static_cast<ucontext_t*>(uc);
#if defined(__x86_64__)
  return uintptr_t(c->uc_mcontext.gregs[REG_RSP]);
#elif defined(__aarch64__)
  return uintptr_t(c->uc_mcontext.sp);
#else
  (void)c;
  return 0;
#endif
}

// The executable segments of every loaded ELF object (lcjit, libLLVM, libc, ld.so, GL drivers):
// "host code". JIT'd model code lives in anonymous mappings, outside all of them. Rebuilt by the
// watchdog before it forces a jump; read by the SIGUSR2 handler.
// Also read by the crash handler: a stack walk starts only from host code, where the stack is
// the compiler's and libc's (model code may have overwritten its own frames, and a walk that
// faults inside the handler would end the process), and never from the unwinder's own code (the
// walk would wait for a lock the crashed thread holds).
struct HostCode {
  static constexpr int kMax = 4096;
  uintptr_t lo[kMax], hi[kMax];
  std::atomic<int> n{0};
  std::atomic<uintptr_t> unwinderLo{0}, unwinderHi{0};
  unsigned long long adds = 0, subs = 0;  // the loader's counts when last read (under mutex)
  std::mutex mutex;                       // one refresh at a time (the watchdog, a new run)
};
HostCode gHostCode;

void refreshHostCode() {
  std::lock_guard<std::mutex> lock(gHostCode.mutex);
  gHostCode.n.store(0, std::memory_order_release);
  int count = 0;
  dl_iterate_phdr(
      [](dl_phdr_info* info, size_t, void* data) {
        int& k = *static_cast<int*>(data);
        const auto unwinder = reinterpret_cast<uintptr_t>(&_Unwind_Backtrace);
        gHostCode.adds = info->dlpi_adds;
        gHostCode.subs = info->dlpi_subs;
        for (int i = 0; i < info->dlpi_phnum && k < HostCode::kMax; ++i) {
          const ElfW(Phdr)& p = info->dlpi_phdr[i];
          if (p.p_type != PT_LOAD || !(p.p_flags & PF_X)) continue;
          gHostCode.lo[k] = info->dlpi_addr + p.p_vaddr;
          gHostCode.hi[k] = info->dlpi_addr + p.p_vaddr + p.p_memsz;
          if (unwinder >= gHostCode.lo[k] && unwinder < gHostCode.hi[k]) {
            gHostCode.unwinderLo.store(gHostCode.lo[k]);
            gHostCode.unwinderHi.store(gHostCode.hi[k]);
          }
          ++k;
        }
        return 0;
      },
      &count);
  gHostCode.n.store(count, std::memory_order_release);
}

// Before a run: the table again if a library was loaded or unloaded since (FFmpeg and HarfBuzz
// are loaded when first needed). Reading the loader's counts costs one callback.
void refreshHostCodeIfChanged() {
  std::pair<unsigned long long, unsigned long long> now{0, 0};
  dl_iterate_phdr(
      [](dl_phdr_info* info, size_t, void* data) {
        *static_cast<std::pair<unsigned long long, unsigned long long>*>(data) = {info->dlpi_adds, info->dlpi_subs};
        return 1;
      },
      &now);
  {
    std::lock_guard<std::mutex> lock(gHostCode.mutex);
    if (gHostCode.n.load() > 0 && now.first == gHostCode.adds && now.second == gHostCode.subs) return;
  }
  refreshHostCode();
}

bool inHostCode(uintptr_t pc) {
  int n = gHostCode.n.load(std::memory_order_acquire);
  for (int i = 0; i < n; ++i)
    if (pc >= gHostCode.lo[i] && pc < gHostCode.hi[i]) return true;
  return false;
}

bool inUnwinder(uintptr_t pc) { return pc >= gHostCode.unwinderLo.load() && pc < gHostCode.unwinderHi.load(); }

// ---- the calls a thread is inside

// Set while the crash handler walks the stack: model code may have overwritten its frames, and a
// walk that faults comes back here (the crash handlers take nested signals) with what it had.
thread_local sigjmp_buf* tlWalk = nullptr;

// The return addresses of the calls the thread is inside, innermost first, into r.frames.
void takeFrames(Region& r) {
  r.framesTaken = 0;
  _Unwind_Backtrace(
      [](_Unwind_Context* context, void* data) -> _Unwind_Reason_Code {
        Region& region = *static_cast<Region*>(data);
        if (region.framesTaken >= Region::kFrames) return _URC_END_OF_STACK;
        region.frames[region.framesTaken] = reinterpret_cast<void*>(_Unwind_GetIP(context));
        region.framesTaken = region.framesTaken + 1;
        return _URC_NO_REASON;
      },
      &r);
}

// ---- signal handlers

struct sigaction gPrevious[NSIG];

// A signal that is not ours goes where it would have gone without lcjit's guard.
void chain(int sig, siginfo_t* info, void* uc) {
  const struct sigaction& prev = gPrevious[sig];
  if (prev.sa_flags & SA_SIGINFO) {
    if (prev.sa_sigaction) prev.sa_sigaction(sig, info, uc);
    return;
  }
  if (prev.sa_handler == SIG_IGN) return;
  if (prev.sa_handler == SIG_DFL) {
    // Die as the process would have: restore the default action; a fault of an instruction
    // happens again when the handler returns, anything else is raised again (blocked until the
    // handler returns).
    struct sigaction dfl {};
    dfl.sa_handler = SIG_DFL;
    sigemptyset(&dfl.sa_mask);
    sigaction(sig, &dfl, nullptr);
    runTerminationCleanups();
    if (info->si_code <= 0 || sig == SIGABRT) raise(sig);
    return;
  }
  prev.sa_handler(sig);
}

// The fault is the guarded thread's own: raised by an instruction it executed (the kernel), or by
// itself (abort() and raise() send the signal to their own thread).
bool ownFault(const siginfo_t* info) { return info->si_code > 0 || (info->si_code == SI_TKILL && info->si_pid == getpid()); }

// In a signal handler, once r.pc is set: the calls that led there (a crash in libc's strlen, in
// the C++ library's code that model code inlined, abort(), a sleep). Not from the unwinder
// itself: it may hold the lock a walk takes.
void takeFramesInHandler(Region& r) {
  r.thrown = nullptr;
  r.framesTaken = 0;
  if (inUnwinder(r.pc)) return;
  sigjmp_buf walk;
  if (sigsetjmp(walk, 0) == 0) {
    tlWalk = &walk;
    takeFrames(r);
  }
  tlWalk = nullptr;
}

void onCrash(int sig, siginfo_t* info, void* uc) {
  if (sigjmp_buf* walk = tlWalk) siglongjmp(*walk, 1);  // the walk below faulted
  Region* r = tlRegion;
  if (r && ownFault(info)) {
    r->signo = sig;
    r->code = info->si_code;
    r->addr = info->si_addr;
    r->sp = spOf(uc);
    r->pc = pcOf(uc);
    // The calls that led there (a crash in libc's strlen, in the C++ library's code that model
    // code inlined, abort()). Not from the unwinder itself: it may hold the lock a walk takes.
    takeFramesInHandler(*r);
    tlRegion = r->outer;
    siglongjmp(r->env, 1);
  }
  chain(sig, info, uc);
}

void onInterrupt(int sig, siginfo_t* info, void* uc) {
  int savedErrno = errno;
  if (Region* r = tlRegion) {
    for (Region* x = r; x; x = x->outer) {
      ModelGuard& g = *x->guard;
      if (!GI::force(g).load(std::memory_order_acquire)) continue;
      uintptr_t pc = pcOf(uc);
      // Inside libc or the host the thread may hold a lock (malloc's, stdio's) or be half way
      // through changing data: wait for it to come back to model code, unless it sleeps.
      if (inHostCode(pc) && !GI::forceAsleep(g).load(std::memory_order_acquire)) break;
      r->signo = sig;
      r->pc = pc;
      r->stopKind = GI::stop(g).load();
      if (inHostCode(pc)) takeFramesInHandler(*r);  // asleep in a system call: where it was called
      tlRegion = r->outer;
      siglongjmp(r->env, 1);
    }
  }
  errno = savedErrno;
  // A late one of ours (the run had ended before it arrived) is dropped; others are chained.
  if (info->si_code == SI_TKILL && info->si_pid == getpid()) return;
  chain(sig, info, uc);
}

// Puts `ours` on `sig` unless it is there. LLVM installs handlers of its own the first time the
// compiler writes a temporary file (a PCH), over ours or before them; its handler, on any signal,
// then puts back what it found for every signal, the default action if it came first, and a
// later time limit (SIGUSR2) or crash in model code would end lcjit. So ours are claimed again
// before each guarded run; LLVM, finding its own registered, does not install them again.
// (Clang's CrashRecoveryContext, if a compile ever runs under one, installs crash handlers too:
// a run claiming SIGSEGV during such a compile would take the compile's recovery away.)
void claim(int sig, const struct sigaction& ours) {
  struct sigaction now {};
  if (sigaction(sig, nullptr, &now) != 0) return;
  bool same = (now.sa_flags & SA_SIGINFO) == (ours.sa_flags & SA_SIGINFO) &&
              ((ours.sa_flags & SA_SIGINFO) ? now.sa_sigaction == ours.sa_sigaction : now.sa_handler == ours.sa_handler);
  if (!same) sigaction(sig, &ours, nullptr);
}

struct sigaction gSigintAction;
std::atomic<bool> gSigintClaimed{false};

void installHandlers() {
  static std::once_flag once;
  // What each signal did before lcjit: where a signal that is not ours goes (chain).
  std::call_once(once, [] {
    for (int s : kCrashSignals) sigaction(s, nullptr, &gPrevious[s]);
    sigaction(kInterruptSignal, nullptr, &gPrevious[kInterruptSignal]);
    // The first walk sets up the unwinder's tables (malloc): not in a signal handler.
    Region r;
    takeFrames(r);
  });
  struct sigaction sa {};
  // SA_NODEFER: a fault of the handler's stack walk comes back to the handler (tlWalk).
  sa.sa_flags = SA_SIGINFO | SA_ONSTACK | SA_RESTART | SA_NODEFER;
  sigemptyset(&sa.sa_mask);
  sigaddset(&sa.sa_mask, kInterruptSignal);
  sa.sa_sigaction = onCrash;
  for (int s : kCrashSignals) claim(s, sa);
  sa.sa_flags = SA_SIGINFO | SA_ONSTACK | SA_RESTART;
  sigemptyset(&sa.sa_mask);
  sa.sa_sigaction = onInterrupt;
  claim(kInterruptSignal, sa);
  if (gSigintClaimed.load()) claim(SIGINT, gSigintAction);
  reclaimTerminationSignals();
}

// Every thread that runs model code gets an alternate signal stack: a stack overflow leaves no
// room on the thread's own stack to run the handler.
struct AltStack {
  void* mem = nullptr;
  size_t size = 0;
  AltStack() {
    stack_t old;
    if (sigaltstack(nullptr, &old) == 0 && !(old.ss_flags & SS_DISABLE)) return;  // it has one
    size = 64 * 1024;
#ifdef _SC_SIGSTKSZ
    long min = sysconf(_SC_SIGSTKSZ);
    if (min > 0) size = std::max(size, size_t(min) * 4);
#endif
    mem = mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_STACK, -1, 0);
    if (mem == MAP_FAILED) {
      mem = nullptr;
      return;
    }
    stack_t s{};
    s.ss_sp = mem;
    s.ss_size = size;
    sigaltstack(&s, nullptr);
  }
  ~AltStack() {
    if (!mem) return;
    stack_t s{};
    s.ss_flags = SS_DISABLE;
    sigaltstack(&s, nullptr);
    munmap(mem, size);
  }
};

void ensureAltStack() { static thread_local AltStack stack; }

// ---- the watchdog: time limits, the memory limit, forced interrupts, Ctrl-C

class Watchdog {
 public:
  static Watchdog& get() {
    static Watchdog* w = create();  // never destroyed: its thread runs until the process ends
    return *w;
  }
  static Watchdog* existing() { return instance_.load(std::memory_order_acquire); }

  void enter(ModelGuard& g) {
    bool wake;
    {
      std::lock_guard<std::mutex> lock(m_);
      if (GI::depth(g)++ > 0) return;  // nested: the outermost run's registration stands
      int64_t now = nowNs();
      GI::thread(g) = uint64_t(pthread_self());
      GI::tid(g) = int(gettid());
      if (pthread_getcpuclockid(pthread_self(), &GI::cpuClock(g)) != 0) GI::cpuClock(g) = CLOCK_THREAD_CPUTIME_ID;
      GI::stops(g) = &tlStops;
      GI::stopsThrownAtStop(g).store(-1);
      if (GI::stop(g).exchange(0)) gStopsAsked.fetch_sub(1);  // one that came after the last run
      GI::force(g).store(false);
      GI::forceAsleep(g).store(false);
      GI::stopThrown(g).store(false);
      GI::stopSince(g) = 0;
      GI::observed(g) = 0;
      GI::running(g).store(true);
      double t = GI::limits(g).timeSeconds;
      GI::deadline(g) = t > 0 ? now + int64_t(t * 1e9) : 0;
      GI::entered(g) = now;
      GI::waitAtEnter(g) = t > 0 ? runQueueWaitNs(0) : -1;  // read only when there is a limit
      guards_.push_back(&g);
      active_.fetch_add(1);
      wake = sleeping_;
      sleeping_ = false;
    }
    if (wake) this->wake();
  }

  // Returns the stop asked for while the run was registered (0: none), which the run may not
  // have seen: one that came while the thread slept in a system call (it only woke early) or
  // after its last checkpoint. The outermost run's registration ends here, with that request.
  int leave(ModelGuard& g) {
    std::lock_guard<std::mutex> lock(m_);
    if (--GI::depth(g) > 0) return GI::stop(g).load();
    guards_.erase(std::find(guards_.begin(), guards_.end(), &g));
    active_.fetch_sub(1);
    // A Ctrl-C is for the runs it found; once they are over, a run that starts next (the REPL's
    // next input) is not stopped by it, however late the watchdog looks.
    if (guards_.empty()) sigintPending_.store(false);
    lastActiveNs_ = nowNs();
    GI::running(g).store(false);
    GI::force(g).store(false);
    GI::forceAsleep(g).store(false);
    GI::stopThrown(g).store(false);
    const int asked = GI::stop(g).exchange(0);
    if (asked) gStopsAsked.fetch_sub(1);
    return asked;
  }

  // Lock-free, so that a signal handler may call it (the REPL's SIGINT handler cancels a step).
  // An interrupt that comes as one run ends and the next begins may stop the next one.
  void interrupt(ModelGuard& g, FaultKind why) {
    if (!GI::running(g).load()) return;
    requestStop(g, why, nowNs());
    wake();
  }

  // On the stopped thread, as it throws its first ModelStop since the stop was asked (its
  // constructor): from now on it unwinds. Its grace starts now, as though the stop had come here,
  // and a force decided before (it was held up on its way to this checkpoint) is taken back, under
  // the lock, so that no forcing signal jumps out of the destructors that free what the model
  // holds; the watchdog forces it again only when the unwinding grace runs out.
  void unwindingBegins(ModelGuard& g) {
    std::lock_guard<std::mutex> lock(m_);
    GI::stopThrown(g).store(true);
    GI::force(g).store(false);
    GI::forceAsleep(g).store(false);
    GI::stopCpu(g).store(nsOf(GI::cpuClock(g)));
    GI::stopSince(g).store(nowNs());
    GI::stopsThrownAtStop(g).store(GI::stops(g)->thrown.load(std::memory_order_relaxed) - 1);  // this one
  }

  // Async-signal-safe.
  void wake() {
    char c = 1;
    ssize_t r = write(fds_[1], &c, 1);
    (void)r;
  }

  std::atomic<int> active_{0};
  std::atomic<bool> sigintPending_{false};

 private:
  static inline std::atomic<Watchdog*> instance_{nullptr};

  static Watchdog* create() {
    auto* w = new Watchdog();
    if (pipe2(w->fds_, O_NONBLOCK | O_CLOEXEC) != 0) w->fds_[0] = w->fds_[1] = -1;
    std::thread([w] { w->loop(); }).detach();
    instance_.store(w, std::memory_order_release);
    return w;
  }

  // Async-signal-safe (clock_gettime is).
  static void requestStop(ModelGuard& g, FaultKind why, int64_t now) {
    int none = 0;
    if (GI::stop(g).compare_exchange_strong(none, int(why))) {
      gStopsAsked.fetch_add(1);
      GI::stopCpu(g).store(nsOf(GI::cpuClock(g)));
      GI::stopSince(g).store(now);
    }
  }

  // At the deadline on the clock: whether the run has used less of its time limit than that,
  // having waited for a processor meanwhile (on a busy machine, or one thread among many: the
  // waiting is not the run's), and then the new deadline, the earliest the limit can be reached.
  // So a limit means the same on a loaded cluster node as on an idle machine.
  static bool postponeDeadline(ModelGuard& g, int64_t now) {
    if (GI::waitAtEnter(g) < 0) return false;
    const int64_t waited = runQueueWaitNs(GI::tid(g)) - GI::waitAtEnter(g);
    if (waited <= 0) return false;
    const int64_t charged = now - GI::entered(g) - waited;
    const int64_t limit = int64_t(GI::limits(g).timeSeconds * 1e9);
    if (charged >= limit) return false;
    GI::deadline(g) = now + (limit - charged);
    return true;
  }

  // Whether the grace of a stopped run is over (see kGraceNs).
  static bool graceOver(ModelGuard& g, int64_t since, int64_t now) {
    int64_t cpu = nsOf(GI::cpuClock(g)) - GI::stopCpu(g).load();
    const StopCounts& s = *GI::stops(g);
    bool unwinding = s.alive.load(std::memory_order_relaxed) > 0 &&
                     s.thrown.load(std::memory_order_relaxed) - GI::stopsThrownAtStop(g).load() <= 1;
    if (cpu >= (unwinding ? kUnwindGraceNs : kGraceNs)) return true;
    return now >= since + kBlockedGraceNs && threadAsleep(GI::tid(g));
  }

  void loop() {
    pthread_setname_np(pthread_self(), "lcjit-watchdog");
    for (;;) {
      int64_t timeoutNs = -1;
      {
        std::lock_guard<std::mutex> lock(m_);
        int64_t now = nowNs();
        if (sigintPending_.load()) {
          // Ctrl-C stops every run in progress; once they have all ended, the next Ctrl-C does it again.
          if (guards_.empty()) sigintPending_.store(false);
          for (ModelGuard* g : guards_) requestStop(*g, FaultKind::Interrupted, now);
        }
        size_t rss = 0;
        bool forcing = false;
        for (ModelGuard* g : guards_) {
          if (GI::deadline(*g) && now >= GI::deadline(*g) && !postponeDeadline(*g, now))
            requestStop(*g, FaultKind::TimeLimit, now);
          size_t limit = GI::limits(*g).memoryBytes;
          if (limit && !GI::stop(*g).load()) {
            if (!rss) rss = residentBytes();
            if (rss > limit) {
              GI::observed(*g) = rss;
              requestStop(*g, FaultKind::MemoryLimit, now);
            }
          }
          // stopSince may lag stop_ by a moment (interrupt() sets them one after the other).
          int64_t since = GI::stopSince(*g).load();
          // The thread's ModelStops so far, read here under the lock (the thread cannot leave its
          // run meanwhile, so its counts exist) the first time the stop is seen.
          if (GI::stop(*g).load() && GI::stopsThrownAtStop(*g).load() < 0)
            GI::stopsThrownAtStop(*g).store(GI::stops(*g)->thrown.load(std::memory_order_relaxed));
          if (GI::stop(*g).load() && since && graceOver(*g, since, now)) {
            if (!GI::force(*g).load()) {
              refreshHostCode();
              GI::forceSince(*g) = now;
              GI::force(*g).store(true, std::memory_order_release);
            }
            GI::forceAsleep(*g).store(now - GI::forceSince(*g) >= kForceAnywhereNs && threadAsleep(GI::tid(*g)),
                                      std::memory_order_release);
            // Under the lock: the thread is still inside its run (leave() waits), so it exists.
            pthread_kill(pthread_t(GI::thread(*g)), kInterruptSignal);
            forcing = true;
          }
        }
        if (forcing) timeoutNs = kForceTickNs;
        else if (!guards_.empty() || now - lastActiveNs_ < kLingerNs || sigintPending_.load()) timeoutNs = kTickNs;
        else sleeping_ = true;
      }
      pollfd p{fds_[0], POLLIN, 0};
      timespec timeout{time_t(timeoutNs / 1'000'000'000), long(timeoutNs % 1'000'000'000)};
      if (ppoll(&p, 1, timeoutNs < 0 ? nullptr : &timeout, nullptr) > 0) {
        char buf[64];
        while (read(fds_[0], buf, sizeof buf) > 0) {
        }
      }
      std::lock_guard<std::mutex> lock(m_);
      sleeping_ = false;
    }
  }

  std::mutex m_;
  std::vector<ModelGuard*> guards_;  // in an outermost run
  int fds_[2] = {-1, -1};           // wakes the watchdog
  bool sleeping_ = false;           // waiting with no timeout: enter() must wake it
  int64_t lastActiveNs_ = 0;
};

// ---- what went wrong, in words

std::string format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
std::string format(const char* fmt, ...) {
  char buf[256];
  va_list ap;
  va_start(ap, fmt);
  std::vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  return buf;
}


Fault stopFault(int kind, const ModelGuard& g, size_t observed) {
  switch (FaultKind(kind)) {
    case FaultKind::TimeLimit:
      return {FaultKind::TimeLimit, format("it ran longer than the time limit of %g s (--time-limit)", g.limits().timeSeconds)};
    case FaultKind::MemoryLimit:
      return {FaultKind::MemoryLimit, "lcjit's memory reached " + sizeInWords(observed) + " (limit --max-memory " +
                                          sizeInWords(g.limits().memoryBytes) + ")"};
    default:
      return {FaultKind::Interrupted, "interrupted"};
  }
}

Fault signalFault(const Region& r) {
  auto addr = uintptr_t(r.addr);
  switch (r.signo) {
    case SIGSEGV:
      if (addr < 4096) return {FaultKind::Crash, "segmentation fault (null pointer dereference)"};
      // A stack overflow faults just below the stack pointer, in the stack's guard area.
      if (r.sp && addr + 65536 >= r.sp && addr < r.sp + 65536)
        return {FaultKind::Crash, "stack overflow (endless recursion?)"};
      return {FaultKind::Crash, format("segmentation fault (invalid memory access at 0x%" PRIxPTR ")", addr)};
    case SIGBUS: return {FaultKind::Crash, format("bus error (invalid memory access at 0x%" PRIxPTR ")", addr)};
    case SIGFPE:
      if (r.code == FPE_INTDIV) return {FaultKind::Crash, "integer division by zero"};
      if (r.code == FPE_INTOVF) return {FaultKind::Crash, "integer overflow"};
      return {FaultKind::Crash, "floating-point exception"};
    case SIGILL: return {FaultKind::Crash, "illegal instruction (a trap: undefined behaviour such as a missing return?)"};
    case SIGABRT:
      if (r.assertion[0]) return {FaultKind::Abort, std::string("assertion failed: ") + r.assertion};
      return {FaultKind::Abort, "abort() was called (std::terminate? a failed assert in a library?)"};
    default: return {FaultKind::Crash, format("signal %d", r.signo)};
  }
}

std::string currentExceptionType() {
  const std::type_info* t = abi::__cxa_current_exception_type();
  if (!t) return "unknown";
  int status = 0;
  char* d = abi::__cxa_demangle(t->name(), nullptr, nullptr, &status);
  std::string name = status == 0 && d ? d : t->name();
  std::free(d);
  return name;
}

// Region::thrown when model code called the C++ library's throwing helpers (below).
const void* const kByLibrary = &kByLibrary;

// An exception model code threw: where its `throw` (or the library call that threw) was, if it
// was the last one model code threw. One the library threw inside a call of its own that model
// code made (std::stoi) has no such note, unless the call went through one of the helpers.
void noteThrowSite(Fault& f, const Region& r, const void* object) {
  if (r.thrown && (r.thrown == object || r.thrown == kByLibrary || !object))
    for (int i = 0; i < r.framesTaken; ++i) f.callers.push_back(reinterpret_cast<uintptr_t>(r.frames[i]));
}

Fault callCatching(llvm::function_ref<void()> fn, ModelGuard& g, const Region& r) {
  try {
    fn();
    return {};
  } catch (const Fault& f) {
    return f;
  } catch (const ModelStop&) {
    return stopFault(GI::stop(g).load(), g, GI::observed(g).load());
  } catch (const std::exception& e) {
    Fault f{FaultKind::Exception, currentExceptionType() + ": " + e.what()};
    noteThrowSite(f, r, dynamic_cast<const void*>(&e));
    return f;
  } catch (...) {
    Fault f{FaultKind::Exception, "an exception of type " + currentExceptionType()};
    noteThrowSite(f, r, nullptr);
    return f;
  }
}

// Model code's `throw`: where it was, then the C++ runtime's __cxa_throw.
[[noreturn]] void modelThrow(void* object, std::type_info* type, void (*destroy)(void*)) {
  if (Region* r = tlRegion) {
    takeFrames(*r);
    r->thrown = object;
  }
  abi::__cxa_throw(object, type, destroy);
}

}  // namespace
// glibc's, which <assert.h> declares only without NDEBUG (lcjit's release build has it).
extern "C" [[noreturn]] void __assert_fail(const char* assertion, const char* file, unsigned line, const char* function) noexcept;
namespace {

// Model code's failed assert(): its condition goes into the fault's message, rather than glibc's
// line, which names the generated function the rule became; then abort(), as assert does.
[[noreturn]] void modelAssertFail(const char* assertion, const char* file, unsigned line, const char* function) {
  if (Region* r = tlRegion) {
    std::snprintf(r->assertion, sizeof r->assertion, "%s", assertion);
    std::abort();
  }
  __assert_fail(assertion, file, line, function);
}

// The C++ library's helpers that its headers call to throw (std::vector::at, reserve, new[]):
// model code calls them, not __cxa_throw. Each notes where it was called from, then throws.
void noteLibraryThrow() {
  if (Region* r = tlRegion) {
    takeFrames(*r);
    r->thrown = kByLibrary;
  }
}
template <void (*Throw)(const char*)>
[[noreturn]] void libraryThrow(const char* what) {
  noteLibraryThrow();
  Throw(what);
  __builtin_unreachable();
}
template <void (*Throw)()>
[[noreturn]] void libraryThrow() {
  noteLibraryThrow();
  Throw();
  __builtin_unreachable();
}
// Its format has only %s, %zu, %lu and %%, which vsnprintf writes the same way.
[[noreturn]] __attribute__((format(printf, 1, 2))) void libraryThrowOutOfRangeFmt(const char* fmt, ...) {
  noteLibraryThrow();
  char what[1024];
  va_list ap;
  va_start(ap, fmt);
  std::vsnprintf(what, sizeof what, fmt, ap);
  va_end(ap);
  std::__throw_out_of_range(what);
}

// ---- allocation in model code

void* modelNew(size_t n) {
  ModelGuard::allocating(n);
  return ::operator new(n);
}
void* modelNewArray(size_t n) {
  ModelGuard::allocating(n);
  return ::operator new[](n);
}
void* modelMalloc(size_t n) {
  ModelGuard::allocating(n);
  return std::malloc(n);
}
void* modelCalloc(size_t n, size_t size) {
  ModelGuard::allocating(n * size);
  return std::calloc(n, size);
}
void* modelRealloc(void* p, size_t n) {
  ModelGuard::allocating(n);
  return std::realloc(p, n);
}

struct sigaction gPreviousSigint;

void onSigint(int) {
  Watchdog* w = Watchdog::existing();
  if (w && !w->sigintPending_.load() && interruptEveryRun()) return;
  // Nothing to interrupt, or the second Ctrl-C: what SIGINT did before.
  if (gPreviousSigint.sa_handler != SIG_IGN) runTerminationCleanups();
  sigaction(SIGINT, &gPreviousSigint, nullptr);
  raise(SIGINT);
}

}  // namespace

// ---- ModelGuard

ModelStop::ModelStop() {
  tlStops.alive.fetch_add(1, std::memory_order_relaxed);
  tlStops.thrown.fetch_add(1, std::memory_order_relaxed);
  for (Region* r = tlRegion; r; r = r->outer)
    if (r->guard->stopRequested() && !GI::stopThrown(*r->guard).load(std::memory_order_relaxed))
      if (Watchdog* w = Watchdog::existing()) w->unwindingBegins(*r->guard);
  // Where the run was stopped: a host function that model code called, or the engine's loop.
  if (Region* r = tlRegion) {
    takeFrames(*r);
    r->thrown = nullptr;
  }
}
ModelStop::ModelStop(const ModelStop&) { tlStops.alive.fetch_add(1, std::memory_order_relaxed); }
ModelStop::~ModelStop() { tlStops.alive.fetch_sub(1, std::memory_order_relaxed); }

ModelGuard::~ModelGuard() = default;

Fault ModelGuard::run(llvm::function_ref<void()> fn) {
  installHandlers();
  ensureAltStack();
  refreshHostCodeIfChanged();
  // A jump out of an unwinding leaves its ModelStop behind, never destroyed: start the count anew.
  if (!tlRegion) tlStops.alive.store(0, std::memory_order_relaxed);
  Watchdog& w = Watchdog::get();
  w.enter(*this);
  Region region;
  region.guard = this;
  region.outer = tlRegion;
  Fault fault;
  if (sigsetjmp(region.env, 1) == 0) {
    tlRegion = &region;
    fault = callCatching(fn, *this, region);
    tlRegion = region.outer;
  } else {
    // The handler jumped here (and restored tlRegion). A stop that was asked for explains the
    // crash that may follow it (a ModelStop thrown through noexcept code aborts).
    int asked = region.signo == kInterruptSignal ? region.stopKind : stop_.load();
    fault = asked ? stopFault(asked, *this, observedBytes_.load()) : signalFault(region);
    fault.pc = region.pc;
  }
  // A crash's or a stop's calls (an exception's are its throw's, callCatching).
  if (fault && fault.kind != FaultKind::Exception && !region.thrown)
    for (int i = 0; i < region.framesTaken; ++i) fault.callers.push_back(reinterpret_cast<uintptr_t>(region.frames[i]));
  // A stop asked for during the run fails it even when the run got to its end without seeing
  // it (a model asleep in usleep() is only woken early by the forcing signals): it is never lost.
  if (const int asked = w.leave(*this); asked && !fault) fault = stopFault(asked, *this, observedBytes_.load());
  // What the stopped run freed goes back to the system: the limit is on resident memory, and
  // malloc keeps freed memory for itself, so the next run would start at the limit.
  if (fault.kind == FaultKind::MemoryLimit) malloc_trim(0);
  return fault;
}

void ModelGuard::interrupt(FaultKind why) {
  if (Watchdog* w = Watchdog::existing()) w->interrupt(*this, why);
}

void ModelGuard::checkpoint() {
  // The first checkpoint after a stop always throws, even when the watchdog already forces the
  // jump: a thread that got here late (asleep, in a long call of the host's, kept waiting by a
  // busy machine) unwinds all the same, and frees what the model holds. Once it has had that
  // chance and the jump is forced, model code has caught the ModelStop and gone on (it may catch
  // everything): throwing again would only keep the thread in the unwinder, inside libgcc with
  // its locks, where the jump must not land.
  for (Region* r = tlRegion; r; r = r->outer)
    if (r->guard->stopRequested() &&
        (!r->guard->force_.load(std::memory_order_relaxed) || !r->guard->stopThrown_.load(std::memory_order_relaxed)))
      throw ModelStop{};
}

void ModelGuard::modelCheckpoint() {
  checkpoint();
  // The jump is forced and the model had its ModelStop: it is made here and now rather than when
  // a forcing signal finds the thread in model code (a model that allocates spends most of its time
  // in malloc and memset, where no signal may jump). The thread has come from model code into this
  // stand-in and holds nothing of lcjit's or libc's: the jump skips what a signal's would.
  Region* in = tlRegion;
  for (Region* r = in; r; r = r->outer) {
    ModelGuard& g = *r->guard;
    if (!g.stopRequested() || !g.force_.load(std::memory_order_acquire) || !g.stopThrown_.load(std::memory_order_relaxed))
      continue;
    in->signo = kInterruptSignal;
    in->stopKind = g.stop_.load();
    in->pc = 0;
    takeFrames(*in);  // the calls it was inside: the statement that called
    in->thrown = nullptr;
    tlRegion = in->outer;
    siglongjmp(in->env, 1);
  }
}

void ModelGuard::allocating(size_t bytes) {
  constexpr size_t kCheckEvery = 4u << 20;  // reading /proc/self/statm costs a few microseconds
  thread_local size_t sinceCheck = 0;
  sinceCheck += bytes;
  if (sinceCheck >= kCheckEvery && tlRegion) {
    sinceCheck = 0;
    size_t rss = 0;
    for (Region* r = tlRegion; r; r = r->outer) {
      ModelGuard& g = *r->guard;
      size_t limit = g.limits_.memoryBytes;
      if (!limit || g.stopRequested()) continue;
      if (!rss) rss = residentBytes();
      if (rss > limit) {
        g.observedBytes_ = rss;
        g.interrupt(FaultKind::MemoryLimit);
      }
    }
  }
  modelCheckpoint();
}

bool ModelGuard::inside() { return tlRegion != nullptr; }

// ---- limits (the process's memory and the fault's words: Faults.cpp)

bool interruptEveryRun() {
  Watchdog* w = Watchdog::existing();
  if (!w || w->active_.load() == 0) return false;
  w->sigintPending_.store(true);
  w->wake();
  return true;
}

void interruptModelCodeOnSigint() {
  Watchdog::get();
  static std::once_flag once;
  std::call_once(once, [] {
    sigaction(SIGINT, nullptr, &gPreviousSigint);
    gSigintAction = {};
    gSigintAction.sa_handler = onSigint;
    sigemptyset(&gSigintAction.sa_mask);
    gSigintAction.sa_flags = SA_RESTART;
    gSigintClaimed = true;
  });
  installHandlers();
}

void addModelCodeHooks(std::vector<std::pair<std::string, void*>>& symbols) {
  symbols.push_back({"lcjit_stops_asked", reinterpret_cast<void*>(&gStopsAsked)});
  symbols.push_back({"lcjit_checkpoint", reinterpret_cast<void*>(&ModelGuard::modelCheckpoint)});
  symbols.push_back({"__cxa_throw", reinterpret_cast<void*>(&modelThrow)});
  symbols.push_back({"__assert_fail", reinterpret_cast<void*>(&modelAssertFail)});
  using Thrower = void (*)(const char*);
  for (auto [name, fn] : {std::pair<const char*, void*>{"_ZSt19__throw_logic_errorPKc", reinterpret_cast<void*>(&libraryThrow<Thrower(&std::__throw_logic_error)>)},
                          {"_ZSt20__throw_length_errorPKc", reinterpret_cast<void*>(&libraryThrow<Thrower(&std::__throw_length_error)>)},
                          {"_ZSt20__throw_out_of_rangePKc", reinterpret_cast<void*>(&libraryThrow<Thrower(&std::__throw_out_of_range)>)},
                          {"_ZSt24__throw_invalid_argumentPKc", reinterpret_cast<void*>(&libraryThrow<Thrower(&std::__throw_invalid_argument)>)},
                          {"_ZSt21__throw_runtime_errorPKc", reinterpret_cast<void*>(&libraryThrow<Thrower(&std::__throw_runtime_error)>)},
                          {"_ZSt17__throw_bad_allocv", reinterpret_cast<void*>(&libraryThrow<&std::__throw_bad_alloc>)},
                          {"_ZSt28__throw_bad_array_new_lengthv", reinterpret_cast<void*>(&libraryThrow<&std::__throw_bad_array_new_length>)},
                          {"_ZSt25__throw_bad_function_callv", reinterpret_cast<void*>(&libraryThrow<&std::__throw_bad_function_call>)},
                          {"_ZSt24__throw_out_of_range_fmtPKcz", reinterpret_cast<void*>(&libraryThrowOutOfRangeFmt)}})
    symbols.push_back({name, fn});
  static_assert(sizeof(size_t) == sizeof(unsigned long), "operator new's mangled names below take unsigned long");
  symbols.push_back({"_Znwm", reinterpret_cast<void*>(&modelNew)});
  symbols.push_back({"_Znam", reinterpret_cast<void*>(&modelNewArray)});
  symbols.push_back({"malloc", reinterpret_cast<void*>(&modelMalloc)});
  symbols.push_back({"calloc", reinterpret_cast<void*>(&modelCalloc)});
  symbols.push_back({"realloc", reinterpret_cast<void*>(&modelRealloc)});
}

}  // namespace lcjit::runtime
