// A control group of its own for one sandboxed run (docs/security.md, "Limits"): the kernel then
// counts all the memory the run holds — resident pages, files in memory (tmpfs, memfd), System V
// shared memory, the kernel's own for it — against one limit, bounds how many tasks (threads) it
// may have, and lets the parent kill every process of the run at once. rlimits cannot do any of
// the three: RLIMIT_AS is address space, RLIMIT_NPROC does not hold for root.
//
// Made where the machine lets lcjit make one: cgroup v2 (the unified hierarchy, where lcjit's own
// cgroup is delegated to it: `systemd-run --user --scope -p Delegate=yes lcjit …`, or a service with
// Delegate=yes) or cgroup v1's memory and pids hierarchies (writable by root). Elsewhere the
// sandbox falls back to its rlimits and seccomp filter, and says why once.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace lcjit::app {

class RunCgroup {
 public:
  // A new cgroup under lcjit's own, with memory.max = `memoryMax` bytes and pids.max = `tasksMax`
  // (0: no limit of that kind). Null, with `why` set, where none can be made. Runs' cgroups that an
  // lcjit no longer there left behind are killed and removed first.
  static std::unique_ptr<RunCgroup> create(uint64_t memoryMax, uint64_t tasksMax, std::string& why);
  ~RunCgroup();  // kills what is left in it and removes it

  // Descriptors of the cgroup.procs files, open for writing: a child writes "0" to each between
  // fork and exec (async-signal-safe), so that it and all it starts are in the cgroup from their
  // first instruction. Close-on-exec.
  const std::vector<int>& joinFds() const { return join_; }
  // Sends SIGKILL to every process in it until none is left (v2: cgroup.kill).
  void killAll();
  // Whether the kernel refused the run memory (an OOM kill in it) or a task (pids.max reached).
  bool memoryLimitReached() const;
  bool taskLimitReached() const;
  uint64_t memoryMax() const { return memoryMax_; }
  uint64_t tasksMax() const { return tasksMax_; }
  const char* kind() const { return v2_ ? "cgroup v2" : "cgroup v1"; }

 private:
  RunCgroup() = default;
  bool v2_ = false;
  uint64_t memoryMax_ = 0, tasksMax_ = 0;
  std::vector<std::string> dirs_;  // the run's cgroup folders: one (v2) or memory's and pids' (v1)
  std::string memoryDir_, pidsDir_;
  std::vector<int> join_;
};

// Joins the cgroups whose cgroup.procs `fds` are open (RunCgroup::joinFds): for the child between
// fork and exec. False if a write failed.
bool joinCgroups(const std::vector<int>& fds);

}  // namespace lcjit::app
