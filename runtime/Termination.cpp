// The termination handlers: run the cleanups, then let the signal do what it did before.
#include "runtime/Termination.h"

#include <atomic>
#include <csignal>
#include <mutex>

namespace lcjit::runtime {

namespace {

constexpr int kMaxCleanups = 8;
std::atomic<void (*)()> gCleanups[kMaxCleanups];
std::atomic<bool> gRan{false};
std::atomic<bool> gInstalled{false};

constexpr int kSignals[] = {SIGTERM, SIGHUP, SIGQUIT};
struct sigaction gPrevious[3];

void onTerminate(int sig) {
  runTerminationCleanups();
  for (int i = 0; i < 3; ++i)
    if (kSignals[i] == sig) sigaction(sig, &gPrevious[i], nullptr);
  // Blocked until this handler returns, then what the signal did before: by default the end,
  // with the signal as the status a shell reports.
  raise(sig);
}

}  // namespace

void installTerminationHandlers() {
  static std::once_flag installed;
  std::call_once(installed, [] {
    for (int i = 0; i < 3; ++i) sigaction(kSignals[i], nullptr, &gPrevious[i]);
    gInstalled = true;
  });
  reclaimTerminationSignals();
}

void reclaimTerminationSignals() {
  if (!gInstalled.load()) return;
  for (int i = 0; i < 3; ++i) {
    // Ignored (nohup) stays ignored. A handler there before (LLVM's, which removes its
    // temporary files) runs after ours: onTerminate puts it back and raises the signal again.
    if (!(gPrevious[i].sa_flags & SA_SIGINFO) && gPrevious[i].sa_handler == SIG_IGN) continue;
    struct sigaction now {};
    sigaction(kSignals[i], nullptr, &now);
    if (!(now.sa_flags & SA_SIGINFO) && now.sa_handler == onTerminate) continue;
    struct sigaction sa {};
    sa.sa_handler = onTerminate;
    sigemptyset(&sa.sa_mask);
    sigaction(kSignals[i], &sa, nullptr);
  }
}

void atTermination(void (*cleanup)()) {
  installTerminationHandlers();
  for (auto& slot : gCleanups) {
    void (*expected)() = nullptr;
    if (slot.load() == cleanup || slot.compare_exchange_strong(expected, cleanup)) return;
  }
}

void runTerminationCleanups() {
  if (gRan.exchange(true)) return;
  for (auto& slot : gCleanups)
    if (auto fn = slot.load()) fn();
}

}  // namespace lcjit::runtime
