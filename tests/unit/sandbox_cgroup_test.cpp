// A sandboxed run's cgroup (app/sandbox/SandboxCgroup.h): the kernel counts memory that is neither the
// process's address space nor its resident size (a file in memory), refuses tasks past the limit,
// and killAll ends every process in it, one in a session of its own too. Skipped where this
// machine gives lcjit no cgroup (an ordinary user without a delegated one): the sandbox then
// falls back to rlimits, which tests/security checks.
#include <gtest/gtest.h>
#include <pthread.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>

#include "app/sandbox/SandboxCgroup.h"

using lcjit::app::RunCgroup;

namespace {

std::unique_ptr<RunCgroup> makeOrSkip(uint64_t memory, uint64_t tasks, std::string& why) {
  return RunCgroup::create(memory, tasks, why);
}

#define CGROUP_OR_SKIP(g, memory, tasks)                              \
  std::string why;                                                    \
  auto g = makeOrSkip(memory, tasks, why);                            \
  if (!g) GTEST_SKIP() << "no cgroup for a run here: " << why;

// Forks a child that joins the cgroup and runs `body`; its wait status.
template <class F>
int inCgroup(const RunCgroup& g, F body) {
  pid_t pid = fork();
  if (pid == 0) {
    if (!lcjit::app::joinCgroups(g.joinFds())) _exit(100);
    _exit(body());
  }
  int status = 0;
  waitpid(pid, &status, 0);
  return status;
}

void* sleeper(void*) {
  for (;;) pause();
  return nullptr;
}

}  // namespace

TEST(RunCgroup, CountsMemoryOutsideTheAddressSpace) {
  CGROUP_OR_SKIP(g, 64ull << 20, 0);
  int status = inCgroup(*g, [] {
    // 256 MB in a file in memory, never mapped: RLIMIT_AS and the resident size miss it.
    int fd = (int)syscall(SYS_memfd_create, "hold", 0);
    if (fd < 0) return 101;
    static char chunk[1 << 20];
    memset(chunk, 'm', sizeof chunk);
    for (int i = 0; i < 256; ++i)
      if (write(fd, chunk, sizeof chunk) != (ssize_t)sizeof chunk) return 102;  // refused: also held
    return 0;  // held 256 MB past a 64 MB limit
  });
  EXPECT_FALSE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "the child held 256 MB under a 64 MB limit";
  if (WIFSIGNALED(status)) {
    EXPECT_EQ(WTERMSIG(status), SIGKILL);
    EXPECT_TRUE(g->memoryLimitReached());
  }
}

TEST(RunCgroup, RefusesTasksPastItsLimit) {
  CGROUP_OR_SKIP(g, 0, 20);
  int status = inCgroup(*g, [] {
    pthread_attr_t at;
    pthread_attr_init(&at);
    pthread_attr_setstacksize(&at, 16384);
    int made = 0;
    for (; made < 100; ++made) {
      pthread_t t;
      if (pthread_create(&t, &at, sleeper, nullptr) != 0) break;
    }
    return made;
  });
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_LT(WEXITSTATUS(status), 20);  // the first task is the child itself
  EXPECT_GE(WEXITSTATUS(status), 10);
  EXPECT_TRUE(g->taskLimitReached());
}

TEST(RunCgroup, KillAllEndsEveryProcessInIt) {
  CGROUP_OR_SKIP(g, 0, 0);
  prctl(PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0);  // the grandchild comes back to us when its parent dies
  int fds[2];
  ASSERT_EQ(pipe(fds), 0);
  pid_t child = fork();
  if (child == 0) {
    if (!lcjit::app::joinCgroups(g->joinFds())) _exit(100);
    pid_t grandchild = fork();
    if (grandchild == 0) {
      setsid();  // out of the child's process group and session: a group kill would miss it
      for (;;) pause();
    }
    (void)!write(fds[1], &grandchild, sizeof grandchild);
    for (;;) pause();
  }
  pid_t grandchild = -1;
  ASSERT_EQ(read(fds[0], &grandchild, sizeof grandchild), (ssize_t)sizeof grandchild);
  g->killAll();
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
  ASSERT_EQ(waitpid(grandchild, &status, 0), grandchild);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
}

TEST(RunCgroup, ALeftRunOfAGoneLcjitIsKilledAndRemoved) {
  std::string why;
  if (!RunCgroup::create(0, 0, why)) GTEST_SKIP() << "no cgroup for a run here: " << why;
  prctl(PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0);
  int fds[2];
  ASSERT_EQ(pipe(fds), 0);
  // An "lcjit" that makes a run's cgroup, puts a process in it and is killed outright: its
  // destructors never run, the cgroup and the process stay.
  pid_t lcjit = fork();
  if (lcjit == 0) {
    std::string w;
    auto g = RunCgroup::create(0, 0, w);
    if (!g) _exit(100);
    pid_t run = fork();
    if (run == 0) {
      if (!lcjit::app::joinCgroups(g->joinFds())) _exit(101);
      for (;;) pause();
    }
    (void)!write(fds[1], &run, sizeof run);
    for (;;) pause();
  }
  pid_t run = -1;
  ASSERT_EQ(read(fds[0], &run, sizeof run), (ssize_t)sizeof run);
  // The run is in its cgroup once it has written to cgroup.procs: wait for that, not for a time.
  std::string cgroupFile = "/proc/" + std::to_string(run) + "/cgroup";
  for (int i = 0; i < 60000; ++i) {
    std::ifstream in(cgroupFile);
    std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (all.find("lcjit-run-" + std::to_string(lcjit)) != std::string::npos) break;
    usleep(1000);
  }
  kill(lcjit, SIGKILL);
  int status = 0;
  ASSERT_EQ(waitpid(lcjit, &status, 0), lcjit);
  // The next lcjit's first run finds it and ends it.
  auto next = RunCgroup::create(0, 0, why);
  ASSERT_TRUE(next);
  pid_t ended = 0;
  for (int i = 0; i < 60000 && (ended = waitpid(run, &status, WNOHANG)) == 0; ++i) usleep(1000);
  if (ended == 0) kill(run, SIGKILL), waitpid(run, &status, 0);
  ASSERT_EQ(ended, run) << "the left run is still there";
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
}
