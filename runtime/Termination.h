// What must be undone even when lcjit is ended by a signal: child processes and the system-wide
// things they share with it (semaphores, shared memory, files) outlive a process that dies.
#pragma once

namespace lcjit::runtime {

// Registers `cleanup` to run when lcjit is ended by SIGTERM, SIGHUP, SIGQUIT, a second Ctrl-C
// (interruptModelCodeOnSigint) or a crash outside model code. It runs in a signal handler: only
// async-signal-safe calls. The first registration installs handlers for SIGTERM, SIGHUP and
// SIGQUIT unless they are ignored: they clean up, then hand the signal to what handled it before
// (LLVM's handlers, the default end). At most 8.
void atTermination(void (*cleanup)());

// Installs those handlers now (lcjit does at start, before anything compiles), and puts them
// back where another handler has taken the signal since (ModelGuard does before each run).
void installTerminationHandlers();
void reclaimTerminationSignals();

// Runs the registered cleanups, once (the handlers above call it; so do lcjit's own SIGINT and
// crash handlers before they let the signal end the process). Async-signal-safe.
void runTerminationCleanups();

}  // namespace lcjit::runtime
