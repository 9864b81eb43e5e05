// The termination handlers: run the cleanups, then let the signal do what it did before.
#include "Termination.h"

#include <atomic>
#include <csignal>
#include <mutex>

namespace lcjit::runtime {

namespace {

constexpr int kMaxCleanups = 8;
std::atomic<void (*)()> gCleanups[kMaxCleanups];
std::atomic<bool> gRan{false};

constexpr int kSignals[] = {SIGTERM, SIGHUP, SIGQUIT};
struct sigaction gPrevious[3];

void onTerminate(int sig) {
  runTerminationCleanups();
  for (int i = 0; i < 3; ++i)
    if (kSignals[i] == sig) sigaction(sig, &gPrevious[i], nullptr);
  // Blocked until this handler returns, then the default action: the end, with the signal as
  // the status a shell reports.
  raise(sig);
}

}  // namespace

void atTermination(void (*cleanup)()) {
  static std::once_flag installed;
  std::call_once(installed, [] {
    for (int i = 0; i < 3; ++i) {
      struct sigaction sa {};
      sa.sa_handler = onTerminate;
      sigemptyset(&sa.sa_mask);
      sigaction(kSignals[i], nullptr, &gPrevious[i]);
      // Only where the signal ends the process: ignored (nohup) stays ignored, and a handler
      // someone else installed decides for itself.
      if ((gPrevious[i].sa_flags & SA_SIGINFO) || gPrevious[i].sa_handler != SIG_DFL) continue;
      sigaction(kSignals[i], &sa, &gPrevious[i]);
    }
  });
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
