// Model code runs in lcjit's own process, behind a guard: a crash (SIGSEGV, SIGBUS, SIGFPE,
// SIGILL, SIGABRT — null pointers, division by zero, stack overflow, abort()), an uncaught C++
// exception, an interrupt (Ctrl-C, Esc, Stop) or a limit (time, memory) ends the guarded call with
// a Fault instead of ending the program. docs/faults.md says why in-process and what it cannot
// promise: the jump out of a crash skips whatever the model was in the middle of, so a lock or
// heap state it broke stays broken, and what it had allocated is lost.
//
// How: ModelGuard::run() marks the calling thread as running model code (sigsetjmp); the signal
// handlers, installed once and chained to whatever was installed before them, siglongjmp back
// when the signal comes from that thread while it is inside, on an alternate signal stack (so a
// stack overflow can be handled). Interrupts are cooperative first — the engine and the host
// functions model code calls check stopRequested() and throw ModelStop, which unwinds cleanly —
// and forced after a short grace period: a watchdog thread sends the thread SIGUSR2, whose
// handler jumps out when the thread is executing JIT'd code (not inside libc or the host, where
// it could hold a lock), and model code's next call into lcjit jumps at once. A thread forced
// before it got to a checkpoint still throws its ModelStop there, and unwinds. The same watchdog
// enforces the time limit and polls the process's resident memory against the memory limit.
#pragma once
#include <atomic>
#include <ctime>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <llvm/ADT/STLFunctionalExtras.h>

namespace lcjit::runtime {

enum class FaultKind : int {
  None = 0,
  Crash,        // SIGSEGV, SIGBUS, SIGFPE, SIGILL: `what` says which and, where it can, why
  Abort,        // SIGABRT: abort(), a failed assert, std::terminate
  Exception,    // a C++ exception left model code
  Interrupted,  // interrupt(): Ctrl-C, Esc, Stop
  TimeLimit,    // the guarded call ran longer than its time limit
  MemoryLimit,  // the process's memory (or the string's buffers) passed the memory limit
  StringLimit,  // the string passed the module limit
  Environment,  // the environmental program failed: `what` is the whole message, naming the .e file
};

struct Fault {
  FaultKind kind = FaultKind::None;
  std::string what;  // "segmentation fault (null pointer dereference)", "std::runtime_error: boom"…
  // Where the thread was, for naming the statement (the JIT maps addresses back to the source):
  // the instruction it was executing when a signal came (0: none), then the return addresses of
  // the calls it was inside, innermost first, where they were taken (a crash outside model code,
  // abort(), a stop while inside a host function) or the call of a `throw` in model code.
  uintptr_t pc = 0;
  std::vector<uintptr_t> callers;
  explicit operator bool() const { return kind != FaultKind::None; }
};

// Thrown by the host (engine loops, host functions, model code's operator new) when the guarded
// call has been asked to stop: unwinding runs the destructors a jump would skip. Deliberately not
// a std::exception, so that model code's catch (std::exception&) does not swallow it. It counts
// itself, so that the watchdog gives a thread unwinding from its first one the time to finish
// (freeing what the model holds) rather than jumping out of its destructors.
struct ModelStop {
  ModelStop();
  ModelStop(const ModelStop&);
  ~ModelStop();
};

// Where model code at an address was compiled from: a statement's file, line and column. The JIT
// knows; whoever loaded the code hands the engine a CodeLocator that asks it. `returnAddress`:
// the address is one a call returns to.
struct CodePlace {
  std::string file;  // absolute
  unsigned line = 0, column = 0;  // column 0: not known
};
using CodeLocator = std::function<std::optional<CodePlace>(uintptr_t address, bool returnAddress)>;
// The statement a fault happened in: the first of its addresses (Fault::pc, then its callers)
// that `locate` places in model code.
std::optional<CodePlace> faultPlace(const Fault& f, const CodeLocator& locate);
// "m.l:8:16" ("m.l:8" without a column): the file as one of `names` (the model's files as the
// user gave them, relative or not) when it is one of them, else in full.
std::string placeText(const CodePlace& p, std::initializer_list<std::string_view> names);

struct GuardLimits {
  double timeSeconds = 0;   // per guarded call; 0: none
  size_t memoryBytes = 0;   // resident memory of the whole process; 0: none
};

// The default memory limit: half the physical memory (or of a cgroup's memory.max, if lower).
size_t defaultMemoryLimit();
// The process's resident memory (/proc/self/statm), in bytes.
size_t residentBytes();

struct StopCounts;  // a thread's ModelStops (ModelGuard.cpp)

class ModelGuard {
 public:
  ModelGuard() = default;
  ~ModelGuard();
  ModelGuard(const ModelGuard&) = delete;
  ModelGuard& operator=(const ModelGuard&) = delete;

  // Runs `fn` on the calling thread; returns a Fault (kind None when `fn` returned normally).
  // Host code inside may throw a Fault to end the run with it (the engine's string limits).
  // Runs nest (a guarded call inside a guarded call, on the same thread): a fault ends the
  // innermost one; an interrupt or a limit of the outer run stops the outer run too.
  Fault run(llvm::function_ref<void()> fn);
  void setLimits(const GuardLimits& limits) { limits_ = limits; }
  const GuardLimits& limits() const { return limits_; }

  // From any thread, and from a signal handler (it only stores atomics and writes to a pipe):
  // the run in progress, if any, stops with `why`.
  void interrupt(FaultKind why = FaultKind::Interrupted);
  // Whether the run in progress has been asked to stop (relaxed load: for per-module checks).
  bool stopRequested() const { return stop_.load(std::memory_order_relaxed) != 0; }
  // Host functions model code calls: throws ModelStop when the calling thread's guarded run has
  // been asked to stop, unless the thread has had its ModelStop for that stop already and the
  // jump is being forced (the model caught it and went on). Does nothing outside a run.
  static void checkpoint();
  // Model code's own calls into lcjit (lcjit_checkpoint, the allocation stand-ins): checkpoint(),
  // and when the jump is forced after the thread had its ModelStop, the jump, made there at once.
  static void modelCheckpoint();
  // The stand-ins for model code's allocations: modelCheckpoint(), and every few megabytes asked
  // for, the memory limit checked on the calling thread itself, so that a model allocating in a
  // loop stops near its limit however late the watchdog gets the processor (a busy machine).
  static void allocating(size_t bytes);
  // Whether the calling thread is inside a guarded run.
  static bool inside();

 private:
  friend struct GuardInternals;
  GuardLimits limits_;
  std::atomic<int> stop_{0};       // FaultKind asked for, 0 = none
  std::atomic<bool> force_{false};  // the watchdog asks the SIGUSR2 handler to jump
  std::atomic<bool> forceAsleep_{false};  // … out of host code too: the thread sleeps in a system call
  std::atomic<bool> running_{false};       // inside run() (the outermost)
  std::atomic<int64_t> stopSinceNs_{0};   // when stop_ was set
  std::atomic<int64_t> stopCpuNs_{0};     // the running thread's CPU time then
  // The running thread has thrown its first ModelStop since stop_ was set: its chance to unwind.
  // Written on that thread only (the ModelStop, run()), so checkpoint() reads it without a lock.
  std::atomic<bool> stopThrown_{false};
  // Set under the watchdog's lock.
  int depth_ = 0;  // nesting of run() on its thread
  uint64_t thread_ = 0;  // pthread_t of the running thread
  int tid_ = 0;                               // its kernel id (/proc/self/task/TID)
  clockid_t cpuClock_ = CLOCK_THREAD_CPUTIME_ID;  // its CPU-time clock
  const StopCounts* stops_ = nullptr;  // its ModelStops
  std::atomic<int> stopsThrownAtStop_{-1};  // how many it had thrown when the watchdog saw stop_
  int64_t deadlineNs_ = 0, forceSinceNs_ = 0;
  // The time limit counts the time the run ran or slept, not the time it waited for a processor
  // (a busy machine's): when it began, and the thread's run-queue wait then (-1: not known).
  int64_t enteredNs_ = 0, waitAtEnterNs_ = -1;
  std::atomic<size_t> observedBytes_{0};  // the resident memory that tripped the memory limit
};

// Ctrl-C: while model code runs, SIGINT interrupts it (every guarded run in the process) instead
// of ending the program; a second Ctrl-C before that run has ended, or one when no model code
// runs, ends the program as before. Also installs the guard's other handlers at once: call it
// before anything compiles, so that LLVM's handlers, installed later, hand signals on to them.
void interruptModelCodeOnSigint();
// What that Ctrl-C does, for a program's own SIGINT handler (the REPL's): every guarded run in
// progress stops, interrupted. False when none runs. Async-signal-safe.
bool interruptEveryRun();

// Stand-ins for operator new, new[], malloc, calloc and realloc in JIT'd model code (linked by
// name, see hostFunctions()): they throw ModelStop when the run has been asked to stop, so that a
// model allocating in a loop unwinds (and frees what it holds) instead of being jumped out of.
// And one for __cxa_throw, which notes where model code threw (Fault::callers). And what emitting
// a module checks: lcjit_stops_asked (how many runs have a stop asked for) and lcjit_checkpoint.
void addModelCodeHooks(std::vector<std::pair<std::string, void*>>& symbols);

// A size as lcjit's limit messages give it: "8.0 KB", "4.00 MB", "11.77 GB".
std::string sizeInWords(uint64_t bytes);

}  // namespace lcjit::runtime
