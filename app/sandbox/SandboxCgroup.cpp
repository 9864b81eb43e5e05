// A sandboxed run's own control group (SandboxCgroup.h): finding lcjit's place in the cgroup
// hierarchies, making the run's cgroup there with its limits, killing and removing it.
#include "app/sandbox/SandboxCgroup.h"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string_view>

namespace lcjit::app {
namespace {

// Where a hierarchy is mounted, and the part of it that this mount shows (a container's cgroup
// namespace or bind mount shows a subtree: its root is not the hierarchy's).
struct Mount {
  std::string root, point;
};

// The cgroup2 mount ("unified") and the v1 mounts of `controller`, from /proc/self/mountinfo.
bool findMount(const std::string& controller, Mount& m) {
  std::ifstream in("/proc/self/mountinfo");
  for (std::string line; std::getline(in, line);) {
    std::istringstream f(line);
    std::string id, parent, dev, root, point, opts;
    f >> id >> parent >> dev >> root >> point >> opts;
    size_t dash = line.find(" - ");
    if (dash == std::string::npos) continue;
    std::istringstream rest(line.substr(dash + 3));
    std::string type, source, superOpts;
    rest >> type >> source >> superOpts;
    bool match = controller.empty() ? type == "cgroup2" : type == "cgroup" && ("," + superOpts + ",").find("," + controller + ",") != std::string::npos;
    if (match) {
      m = {root, point};
      return true;
    }
  }
  return false;
}

// lcjit's own cgroup in a hierarchy ("" for the unified one), from /proc/self/cgroup.
bool ownPath(const std::string& controller, std::string& path) {
  std::ifstream in("/proc/self/cgroup");
  for (std::string line; std::getline(in, line);) {
    size_t a = line.find(':'), b = a == std::string::npos ? a : line.find(':', a + 1);
    if (b == std::string::npos) continue;
    std::string list = line.substr(a + 1, b - a - 1);
    bool match = controller.empty() ? line.compare(0, a, "0") == 0 && list.empty()
                                    : ("," + list + ",").find("," + controller + ",") != std::string::npos;
    if (match) {
      path = line.substr(b + 1);
      return true;
    }
  }
  return false;
}

// The folder of lcjit's own cgroup in a hierarchy ("" where there is none to be seen).
std::string ownFolder(const std::string& controller) {
  Mount m;
  std::string path;
  if (!findMount(controller, m) || !ownPath(controller, path)) return "";
  if (m.root != "/") {
    if (path.compare(0, m.root.size(), m.root) != 0) return "";  // our cgroup is outside what the mount shows
    path = path.substr(m.root.size());
  }
  while (!path.empty() && path.back() == '/') path.pop_back();
  return m.point + path;
}

bool writeFile(const std::string& path, const std::string& text) {
  int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd < 0) return false;
  bool ok = ::write(fd, text.data(), text.size()) == (ssize_t)text.size();
  ::close(fd);
  return ok;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The number after `key` in a flat-keyed file (memory.events, pids.events, memory.oom_control).
uint64_t keyed(const std::string& path, std::string_view key) {
  std::istringstream in(readFile(path));
  for (std::string k; in >> k;) {
    uint64_t v = 0;
    in >> v;
    if (k == key) return v;
  }
  return 0;
}

bool hasWord(const std::string& list, std::string_view word) {
  std::istringstream in(list);
  for (std::string w; in >> w;)
    if (w == word) return true;
  return false;
}

// Every process in the cgroup `dir` killed, until none is left (v1, or a kernel before v2's
// cgroup.kill). A sandboxed run cannot start processes (seccomp), so the list only shrinks.
void killEvery(const std::string& dir) {
  for (int round = 0; round < 1000; ++round) {
    std::istringstream procs(readFile(dir + "/cgroup.procs"));
    bool any = false;
    for (pid_t pid; procs >> pid;) {
      ::kill(pid, SIGKILL);
      any = true;
    }
    if (!any) return;
    ::usleep(1000);
  }
}

// The runs' cgroups of an lcjit that is gone (killed outright, or by a signal with a run under
// way): what is left in them killed, the folders removed. Made by `lcjit-run-PID-N` and, for
// cgroup v2, lcjit's own leaf `lcjit-PID`.
void sweepStale(const std::string& parent) {
  DIR* d = ::opendir(parent.c_str());
  for (dirent* e; d && (e = ::readdir(d));) {
    std::string name = e->d_name;
    const char* digits = name.rfind("lcjit-run-", 0) == 0 ? name.c_str() + 10
                         : name.rfind("lcjit-", 0) == 0   ? name.c_str() + 6
                                                          : nullptr;
    if (!digits || *digits < '0' || *digits > '9') continue;
    pid_t owner = (pid_t)std::strtol(digits, nullptr, 10);
    if (owner <= 0 || ::kill(owner, 0) == 0 || errno != ESRCH) continue;
    std::string dir = parent + "/" + name;
    killEvery(dir);
    for (int i = 0; i < 200 && ::rmdir(dir.c_str()) != 0 && errno == EBUSY; ++i) ::usleep(1000);
  }
  if (d) ::closedir(d);
}

// A name no other run (of this lcjit or another) has.
std::string runName() {
  static int n = 0;
  return "lcjit-run-" + std::to_string(::getpid()) + "-" + std::to_string(++n);
}

// cgroup v2 allows controllers only in cgroups without processes of their own ("no internal
// processes"): where lcjit's own cgroup has them enabled for its children, or can enable them
// once lcjit has moved itself into a leaf beside its runs, the runs' cgroups go beside it.
std::string v2Parent(std::string& why) {
  static std::string parent, failed;
  if (!parent.empty() || !failed.empty()) return why = failed, parent;
  std::string own = ownFolder("");
  auto fail = [&](const std::string& w) { return failed = why = w, std::string(); };
  if (own.empty()) return fail("no cgroup v2 hierarchy");
  std::string available = readFile(own + "/cgroup.controllers");
  if (!hasWord(available, "memory") || !hasWord(available, "pids"))
    return fail("lcjit's cgroup " + own + " has no memory and pids controllers to give");
  if (::access((own + "/cgroup.subtree_control").c_str(), W_OK) != 0)
    return fail("lcjit's cgroup " + own + " is not delegated to it (run it in a scope with Delegate=yes)");
  std::string enabled = readFile(own + "/cgroup.subtree_control");
  if (!hasWord(enabled, "memory") || !hasWord(enabled, "pids")) {
    if (!writeFile(own + "/cgroup.subtree_control", "+memory +pids")) {
      if (errno != EBUSY) return fail(own + "/cgroup.subtree_control: " + std::strerror(errno));
      std::string leaf = own + "/lcjit-" + std::to_string(::getpid());
      if (::mkdir(leaf.c_str(), 0755) != 0 && errno != EEXIST) return fail(leaf + ": " + std::strerror(errno));
      if (!writeFile(leaf + "/cgroup.procs", "0") || !writeFile(own + "/cgroup.subtree_control", "+memory +pids"))
        return fail("cannot enable memory and pids in " + own + " (other processes in it?): " + std::strerror(errno));
    }
  }
  return parent = own;
}

}  // namespace

std::unique_ptr<RunCgroup> RunCgroup::create(uint64_t memoryMax, uint64_t tasksMax, std::string& why) {
  std::unique_ptr<RunCgroup> g(new RunCgroup());
  g->memoryMax_ = memoryMax;
  g->tasksMax_ = tasksMax;
  auto limit = [](uint64_t v) { return v ? std::to_string(v) : std::string("max"); };
  std::string v2why;
  if (std::string parent = v2Parent(v2why); !parent.empty()) {
    sweepStale(parent);
    std::string dir = parent + "/" + runName();
    if (::mkdir(dir.c_str(), 0755) == 0) {
      g->v2_ = true;
      g->dirs_ = {dir};
      g->memoryDir_ = g->pidsDir_ = dir;
      // No swap beyond the limit either, where swap is accounted (the file is there).
      if (::access((dir + "/memory.swap.max").c_str(), F_OK) == 0) writeFile(dir + "/memory.swap.max", "0");
      if (writeFile(dir + "/memory.max", limit(memoryMax)) && writeFile(dir + "/pids.max", limit(tasksMax))) {
        int fd = ::open((dir + "/cgroup.procs").c_str(), O_WRONLY | O_CLOEXEC);
        if (fd >= 0) {
          g->join_.push_back(fd);
          return g;
        }
      }
      v2why = dir + ": " + std::strerror(errno);
    } else {
      v2why = dir + ": " + std::strerror(errno);
    }
    g.reset(new RunCgroup());
    g->memoryMax_ = memoryMax;
    g->tasksMax_ = tasksMax;
  }
  // cgroup v1: a cgroup in the memory hierarchy and one in the pids hierarchy.
  std::string name = runName(), v1why;
  for (const char* controller : {"memory", "pids"}) {
    std::string own = ownFolder(controller);
    if (own.empty()) {
      v1why = std::string("no cgroup v1 ") + controller + " hierarchy";
      break;
    }
    sweepStale(own);
    std::string dir = own + "/" + name;
    if (::mkdir(dir.c_str(), 0755) != 0) {
      v1why = dir + ": " + std::strerror(errno);
      break;
    }
    g->dirs_.push_back(dir);
    bool ok;
    if (std::string(controller) == "memory") {
      g->memoryDir_ = dir;
      // memsw (memory and swap together) where swap is accounted: a run must not swap past its limit.
      ok = !memoryMax || writeFile(dir + "/memory.limit_in_bytes", std::to_string(memoryMax));
      if (ok && memoryMax && ::access((dir + "/memory.memsw.limit_in_bytes").c_str(), F_OK) == 0)
        writeFile(dir + "/memory.memsw.limit_in_bytes", std::to_string(memoryMax));
    } else {
      g->pidsDir_ = dir;
      ok = writeFile(dir + "/pids.max", limit(tasksMax));
    }
    int fd = ok ? ::open((dir + "/cgroup.procs").c_str(), O_WRONLY | O_CLOEXEC) : -1;
    if (fd < 0) {
      v1why = dir + ": " + std::strerror(errno);
      break;
    }
    g->join_.push_back(fd);
  }
  if (v1why.empty()) return g;
  why = v2why + "; " + v1why;
  return nullptr;  // ~RunCgroup removes what was made
}

RunCgroup::~RunCgroup() {
  killAll();
  for (int fd : join_) ::close(fd);
  // A killed process leaves its cgroup as it exits: the folders empty within moments.
  for (auto it = dirs_.rbegin(); it != dirs_.rend(); ++it)
    for (int i = 0; i < 2000 && ::rmdir(it->c_str()) != 0 && errno == EBUSY; ++i) ::usleep(1000);
}

void RunCgroup::killAll() {
  if (dirs_.empty()) return;
  if (v2_ && writeFile(dirs_[0] + "/cgroup.kill", "1")) return;
  killEvery(!pidsDir_.empty() ? pidsDir_ : dirs_[0]);
}

bool RunCgroup::memoryLimitReached() const {
  if (memoryDir_.empty() || !memoryMax_) return false;
  if (v2_) return keyed(memoryDir_ + "/memory.events", "oom_kill") > 0;
  return keyed(memoryDir_ + "/memory.oom_control", "oom_kill") > 0;
}

bool RunCgroup::taskLimitReached() const {
  return !pidsDir_.empty() && tasksMax_ && keyed(pidsDir_ + "/pids.events", "max") > 0;
}

bool joinCgroups(const std::vector<int>& fds) {
  bool ok = true;
  for (int fd : fds) ok = ::write(fd, "0", 1) == 1 && ok;
  return ok;
}

}  // namespace lcjit::app
