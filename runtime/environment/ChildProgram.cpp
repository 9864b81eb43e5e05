// The child-process link. The protocol facts (who creates what, the semaphores' turn-taking, the
// chunking of long transmissions, the exit request) follow vlab's libs/comm, whose slave side
// the programs link; docs/environment.md describes them.
#include "runtime/environment/ChildProgram.h"

#include <atomic>
#include <climits>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <mutex>
#include <optional>
#include <sstream>

#include <fcntl.h>
#include <poll.h>
#include <sys/ipc.h>
#include <sys/sem.h>
#include <sys/shm.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "runtime/Termination.h"
#include "support/InputFile.h"

namespace lcjit::runtime {

namespace {

// vlab's control line flags (libs/comm/communication.h).
constexpr int kFirstChunk = 1, kLastChunk = 4, kExit = 8;
// The shared segment of the memory transport: requests in the first 50 000 bytes, answers in
// the next 10 000 (libs/comm's shared_memory_type).
constexpr size_t kToField = 50000, kFromField = 10000;

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::string seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g s", s);
  return buf;
}

// A `Control: FLAGS STEP` line ends a transmission: its flags; nothing for any other line.
std::optional<int> controlFlags(const std::string& line) {
  if (line.compare(0, 7, "Control") != 0) return std::nullopt;
  return std::atoi(line.c_str() + std::min<size_t>(8, line.size()));
}

std::string describeStatus(int status) {
  if (WIFEXITED(status)) return "exited with status " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status)) return std::string("was killed by signal ") + strsignal(WTERMSIG(status));
  return "stopped";
}

union SemArg {
  int val;
  struct semid_ds* buf;
  unsigned short* array;
};

// The programs alive, for the termination handlers (a killed lcjit must not leave a program
// running, nor the semaphores, the segment or the files, which outlive it): plain values a
// signal handler may read. A slot is filled before it is marked live, and freed after stop().
struct LiveChild {
  std::atomic<int> state{0};  // 0 free, 1 being filled, 2 live
  std::atomic<pid_t> pid{-1};
  std::atomic<int> semId{-1}, shmId{-1};
  std::atomic<bool> hasFiles{false};
  char toFile[PATH_MAX], fromFile[PATH_MAX];  // absolute: the handler must not depend on the folder
};
LiveChild gLive[16];

void killLiveChildren() {
  for (LiveChild& c : gLive) {
    if (c.state.load() != 2) continue;
    if (pid_t pid = c.pid.load(); pid > 0) {
      kill(-pid, SIGKILL);  // its process group: what it started too
      kill(pid, SIGKILL);
      waitpid(pid, nullptr, 0);
    }
    if (c.hasFiles.load()) {
      unlink(c.toFile);
      unlink(c.fromFile);
    }
    if (int id = c.shmId.load(); id >= 0) shmctl(id, IPC_RMID, nullptr);
    if (int id = c.semId.load(); id >= 0) semctl(id, 0, IPC_RMID);
  }
}

// A free slot, or nullptr when 16 programs live (they are then not cleaned up by a signal).
LiveChild* claimLiveSlot() {
  static std::once_flag registered;
  std::call_once(registered, [] { atTermination(killLiveChildren); });
  for (LiveChild& c : gLive) {
    int expected = 0;
    if (c.state.compare_exchange_strong(expected, 1)) {
      c.pid = -1;
      c.semId = c.shmId = -1;
      c.hasFiles = false;
      c.state = 2;
      return &c;
    }
  }
  return nullptr;
}

void setLiveFiles(LiveChild* c, const std::string& to, const std::string& from) {
  if (!c) return;
  char cwd[PATH_MAX];
  if (!getcwd(cwd, sizeof cwd)) return;
  std::string a = std::string(cwd) + "/" + to, b = std::string(cwd) + "/" + from;
  if (a.size() >= PATH_MAX || b.size() >= PATH_MAX) return;
  c->hasFiles = false;
  std::memcpy(c->toFile, a.c_str(), a.size() + 1);
  std::memcpy(c->fromFile, b.c_str(), b.size() + 1);
  c->hasFiles = true;
}

class ChildLink final : public EnvironmentLink {
 public:
  ChildLink(CommSpec spec, ChildProgramOptions options) : spec_(std::move(spec)), options_(std::move(options)) {}
  ~ChildLink() override { stop(); }

  const CommSpec& spec() const override { return spec_; }

  llvm::Error start();
  llvm::Expected<std::string> exchange(const std::vector<std::string>& records, int step,
                                       const std::function<void()>& poll) override;

 private:
  using Transport = CommSpec::Transport;
  void log(const std::string& line) const {
    if (options_.log) options_.log(line);
  }
  std::string name() const { return "the environmental program " + program_; }
  // Whether the child has ended; its status then says how.
  bool ended();
  llvm::Error ipcSetup();
  llvm::Error waitReady();
  // Semaphore 0: "the request is there"; 1: "the answer is there".
  void post(int sem);
  llvm::Error waitAnswer(const std::function<void()>& poll, Clock::time_point since);
  llvm::Error send(const std::string& text);
  llvm::Expected<std::string> receive(int& flags);  // one answer chunk (files, memory)
  llvm::Expected<std::string> exchangePipes(const std::string& text, const std::function<void()>& poll);
  void stop();
  void removeIpc();

  CommSpec spec_;
  ChildProgramOptions options_;
  std::string program_;
  pid_t pid_ = -1;
  int status_ = 0;
  bool reaped_ = false;
  int key_ = 0, semId_ = -1, shmId_ = -1;
  char* shm_ = nullptr;
  std::string toFile_, fromFile_;
  LiveChild* live_ = nullptr;          // this program's entry for the termination handlers
  int toChild_ = -1, fromChild_ = -1;  // pipes
  std::string pending_;                // pipes: read past the last line handled
  // An exchange abandoned half way (a stop request) leaves the program out of step: the next
  // exchange starts it again.
  bool outOfStep_ = false;
};

bool ChildLink::ended() {
  if (reaped_) return true;
  if (pid_ <= 0) return true;
  pid_t r = waitpid(pid_, &status_, WNOHANG);
  if (r == pid_ || (r < 0 && errno == ECHILD)) reaped_ = true;
  return reaped_;
}

void ChildLink::post(int sem) {
  struct sembuf op {static_cast<unsigned short>(sem), 1, 0};
  semop(semId_, &op, 1);
}

llvm::Error ChildLink::ipcSetup() {
  // A key no other process uses: this process's id, and a counter for the links it starts. The
  // memory segment takes key − 1, as the programs' library expects.
  static int counter = 0;
  for (int attempt = 0; attempt < 64; ++attempt) {
    key_ = int(((unsigned(getpid()) & 0x3fffffu) << 8) + 4u * unsigned(1 + (counter++ % 62)));
    semId_ = semget(key_, 2, IPC_CREAT | IPC_EXCL | 0600);
    if (semId_ >= 0) break;
    if (errno != EEXIST) return spec_.error(std::string("cannot create the semaphores: ") + std::strerror(errno));
  }
  if (semId_ < 0) return spec_.error("cannot find a free semaphore key");
  if (live_) live_->semId = semId_;
  unsigned short initial[2] = {0, 1};  // the program sets semaphore 1 to 0 when it is ready
  SemArg arg;
  arg.array = initial;
  semctl(semId_, 0, SETALL, arg);
  if (spec_.transport == Transport::Memory) {
    shmId_ = shmget(key_ - 1, kToField + kFromField, IPC_CREAT | IPC_EXCL | 0600);
    if (shmId_ < 0) return spec_.error(std::string("cannot create the shared memory: ") + std::strerror(errno));
    if (live_) live_->shmId = shmId_;
    void* p = shmat(shmId_, nullptr, 0);
    if (p == reinterpret_cast<void*>(-1))
      return spec_.error(std::string("cannot attach the shared memory: ") + std::strerror(errno));
    shm_ = static_cast<char*>(p);
    std::memset(shm_, 0, kToField + kFromField);
  }
  if (spec_.transport == Transport::Files) {
    std::string ext = std::to_string(key_) + ".0";
    toFile_ = ".to_field" + ext;
    fromFile_ = ".from_field" + ext;
    setLiveFiles(live_, toFile_, fromFile_);
  }
  return llvm::Error::success();
}

llvm::Error ChildLink::start() {
  std::vector<std::string> argv = environmentArguments(spec_);
  if (argv.empty()) return spec_.error("'executable:' names no program");
  program_ = argv[0];
  if (!live_) live_ = claimLiveSlot();
  std::string path = findProgram(argv[0]);
  if (path.empty())
    return spec_.error("cannot start the environmental program '" + argv[0] + "' (line " +
                           std::to_string(spec_.executableLine) + "): not found" +
                           (argv[0].find('/') == std::string::npos ? " on PATH" : ""));
  if (spec_.transport != Transport::Pipes) {
    if (auto e = ipcSetup()) return e;
    std::vector<std::string> extra = {"-k", std::to_string(key_)};
    if (spec_.transport == Transport::Files) extra.insert(extra.end(), {"-ext", std::to_string(key_) + ".0"});
    argv.insert(argv.begin() + 1, extra.begin(), extra.end());
  }
  int in[2] = {-1, -1}, out[2] = {-1, -1}, report[2];
  if (spec_.transport == Transport::Pipes && (pipe2(in, O_CLOEXEC) || pipe2(out, O_CLOEXEC)))
    return spec_.error(std::string("cannot create pipes: ") + std::strerror(errno));
  if (pipe2(report, O_CLOEXEC)) return spec_.error(std::string("cannot create a pipe: ") + std::strerror(errno));
  std::vector<char*> args;
  for (auto& a : argv) args.push_back(a.data());
  args.push_back(nullptr);
  log("starting " + [&] {
    std::string s;
    for (auto& a : argv) s += (s.empty() ? "" : " ") + a;
    return s;
  }());
  pid_ = fork();
  if (pid_ < 0) return spec_.error(std::string("cannot start a process: ") + std::strerror(errno));
  if (pid_ > 0 && live_) live_->pid = pid_;
  if (pid_ == 0) {
    // Only async-signal-safe calls from here to exec. Its own process group: a Ctrl-C at the
    // terminal interrupts lcjit's model, not the program.
    setpgid(0, 0);
    if (spec_.transport == Transport::Pipes) {
      dup2(in[0], 0);
      dup2(out[1], 1);
    } else {
      int null = open("/dev/null", O_RDONLY);
      if (null >= 0) dup2(null, 0);
      dup2(2, 1);  // what it prints goes where lcjit's messages go, not into lcjit's output
    }
    execv(path.c_str(), args.data());
    int e = errno;
    ssize_t w = write(report[1], &e, sizeof e);
    (void)w;
    _exit(127);
  }
  close(report[1]);
  int execErrno = 0;
  ssize_t got = read(report[0], &execErrno, sizeof execErrno);
  close(report[0]);
  if (spec_.transport == Transport::Pipes) {
    close(in[0]);
    close(out[1]);
    toChild_ = in[1];
    fromChild_ = out[0];
    fcntl(toChild_, F_SETFL, fcntl(toChild_, F_GETFL) | O_NONBLOCK);
    // A program that dies while we write must be an error, not lcjit's end.
    std::signal(SIGPIPE, SIG_IGN);
  }
  if (got == sizeof execErrno) {
    waitpid(pid_, &status_, 0);
    reaped_ = true;
    return spec_.error("cannot start the environmental program '" + path + "': " + std::strerror(execErrno));
  }
  return waitReady();
}

// Files and memory: the program sets semaphore 1 to 0 once it has attached them. Pipes: it
// writes the byte 0x01.
llvm::Error ChildLink::waitReady() {
  const auto since = Clock::now();
  for (;;) {
    if (spec_.transport == Transport::Pipes) {
      struct pollfd p {fromChild_, POLLIN, 0};
      if (::poll(&p, 1, 10) > 0) {
        char c = 0;
        ssize_t n = read(fromChild_, &c, 1);
        if (n == 1 && c == 1) break;
        if (n == 1) return spec_.error(name() + " wrote something else than its ready signal (0x01) on its output");
        if (ended()) return spec_.error(name() + " " + describeStatus(status_) + " before it was ready");
        return spec_.error(name() + " closed its output before it was ready");
      }
    } else {
      if (semctl(semId_, 1, GETVAL) == 0) break;
      usleep(5000);
    }
    if (ended()) return spec_.error(name() + " " + describeStatus(status_) + " before it was ready");
    if (options_.startSeconds > 0 && secondsSince(since) > options_.startSeconds)
      return spec_.error(name() + " was not ready after " + seconds(options_.startSeconds));
  }
  log(name() + " is ready");
  return llvm::Error::success();
}

llvm::Error ChildLink::send(const std::string& text) {
  if (spec_.transport == Transport::Files) {
    std::ofstream f(toFile_, std::ios::binary | std::ios::trunc);
    f << text;
    f.close();
    if (!f) return spec_.error("cannot write " + toFile_);
  } else {
    std::memcpy(shm_, text.data(), text.size());
    if (text.size() < kToField) shm_[text.size()] = 0;
    std::memset(shm_ + kToField, 0, kFromField);
  }
  post(0);
  return llvm::Error::success();
}

llvm::Error ChildLink::waitAnswer(const std::function<void()>& poll, Clock::time_point since) {
  for (;;) {
    struct sembuf op {1, -1, 0};
    struct timespec slice {0, 20'000'000};
    if (semtimedop(semId_, &op, 1, &slice) == 0) return llvm::Error::success();
    if (errno != EAGAIN && errno != EINTR)
      return spec_.error(std::string("waiting for ") + name() + ": " + std::strerror(errno));
    if (ended()) return spec_.error(name() + " " + describeStatus(status_) + " without answering");
    if (options_.answerSeconds > 0 && secondsSince(since) > options_.answerSeconds)
      return spec_.error(name() + " did not answer within " + seconds(options_.answerSeconds));
    poll();
  }
}

// One answer chunk: its `ID E(…)` lines, and the flags of its control line.
llvm::Expected<std::string> ChildLink::receive(int& flags) {
  std::string text;
  if (spec_.transport == Transport::Files) {
    auto file = support::readInputFile(fromFile_, /*nullTerminated=*/false);
    if (!file) return spec_.error(name() + " wrote no answer file (" + fromFile_ + ": " + file.getError().message() + ")");
    text = (*file)->getBuffer().str();
  } else {
    text.assign(shm_ + kToField, strnlen(shm_ + kToField, kFromField));
  }
  std::string records;
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    std::string line = text.substr(start, end == std::string::npos ? std::string::npos : end - start);
    start = end == std::string::npos ? text.size() : end + 1;
    if (auto f = controlFlags(line)) {
      flags = *f;
      return records;
    }
    records += line;
    records += '\n';
  }
  return spec_.error(name() + "'s answer has no end (no 'Control:' line)");
}

llvm::Expected<std::string> ChildLink::exchange(const std::vector<std::string>& records, int step,
                                                const std::function<void()>& poll) {
  if (outOfStep_ || ended()) {
    // Out of step after an abandoned exchange, or gone: start it again, as a reload would.
    bool gone = ended() && !outOfStep_;
    int status = status_;
    stop();
    if (gone) return spec_.error(name() + " " + describeStatus(status) + " (it is started again when the model is reloaded)");
    outOfStep_ = false;
    reaped_ = false;
    if (auto e = start()) return std::move(e);
  }
  const auto since = Clock::now();
  const std::string control = "Control: " + std::to_string(kFirstChunk | kLastChunk) + " " + std::to_string(step) + "\n";
  outOfStep_ = true;  // until the whole answer is in
  std::string answers;
  if (spec_.transport == Transport::Pipes) {
    std::string text;
    for (auto& r : records) text += r;
    auto got = exchangePipes(text + control, poll);
    if (!got) return got.takeError();
    answers = std::move(*got);
  } else {
    // Memory: requests of more than the segment's 50 000 bytes go in chunks, each answered
    // before the next is sent; the program ends each with its own control line.
    size_t next = 0;
    bool first = true;
    for (;;) {
      std::string chunk;
      const size_t room = spec_.transport == Transport::Memory ? kToField - 64 : SIZE_MAX;
      while (next < records.size() && (chunk.empty() || chunk.size() + records[next].size() < room))
        chunk += records[next++];
      if (chunk.size() >= room) return spec_.error("one communication module's record is longer than the shared memory");
      const bool last = next == records.size();
      chunk += "Control: " + std::to_string((first ? kFirstChunk : 0) | (last ? kLastChunk : 0)) + " " +
               std::to_string(step) + "\n";
      first = false;
      if (auto e = send(chunk)) return std::move(e);
      for (;;) {
        if (auto e = waitAnswer(poll, since)) return std::move(e);
        int flags = 0;
        auto part = receive(flags);
        if (!part) return part.takeError();
        answers += *part;
        // The program splits what it answers to any chunk when it does not fit, marking all
        // but the final piece as not last; each piece waits for our turn to be read.
        if (flags & kLastChunk) break;
        post(0);
      }
      if (last) break;
    }
  }
  outOfStep_ = false;
  log(name() + ": step " + std::to_string(step) + ", " + std::to_string(records.size()) + " modules sent");
  return answers;
}

llvm::Expected<std::string> ChildLink::exchangePipes(const std::string& text, const std::function<void()>& poll) {
  const auto since = Clock::now();
  size_t written = 0;
  std::string answers;
  for (;;) {
    // Write and read together: a program that answers as it reads fills its pipe before ours
    // is empty.
    struct pollfd p[2] = {{fromChild_, POLLIN, 0}, {written < text.size() ? toChild_ : -1, POLLOUT, 0}};
    int r = ::poll(p, 2, 20);
    if (r < 0 && errno != EINTR) return spec_.error(std::string("waiting for ") + name() + ": " + std::strerror(errno));
    if (p[1].revents & (POLLOUT | POLLERR | POLLHUP)) {
      ssize_t n = write(toChild_, text.data() + written, text.size() - written);
      if (n < 0 && errno != EAGAIN && errno != EINTR)
        return spec_.error(name() + " stopped reading its input (" + std::strerror(errno) + ")");
      if (n > 0) written += size_t(n);
    }
    if (p[0].revents & (POLLIN | POLLHUP | POLLERR)) {
      char buf[65536];
      ssize_t n = read(fromChild_, buf, sizeof buf);
      if (n == 0) {
        // Its output closes as it dies: give it a moment to be gone, to say how.
        const auto closed = Clock::now();
        while (!ended() && secondsSince(closed) < 1.0) usleep(2000);
        if (ended()) return spec_.error(name() + " " + describeStatus(status_) + " without answering");
        return spec_.error(name() + " closed its output without answering");
      }
      if (n > 0) pending_.append(buf, size_t(n));
      size_t start = 0;
      for (size_t nl; (nl = pending_.find('\n', start)) != std::string::npos; start = nl + 1) {
        std::string line = pending_.substr(start, nl - start);
        if (auto flags = controlFlags(line)) {
          if ((*flags & kLastChunk) && written == text.size()) {
            pending_.erase(0, nl + 1);
            return answers;
          }
          continue;
        }
        answers += line;
        answers += '\n';
      }
      pending_.erase(0, start);
    }
    if (ended() && !(p[0].revents & POLLIN))
      return spec_.error(name() + " " + describeStatus(status_) + " without answering");
    if (options_.answerSeconds > 0 && secondsSince(since) > options_.answerSeconds)
      return spec_.error(name() + " did not answer within " + seconds(options_.answerSeconds));
    poll();
  }
}

// The exit request (`Control: 9`), a second for the program to go, then SIGKILL; the files, the
// semaphores and the segment are removed whatever happened.
void ChildLink::stop() {
  if (pid_ > 0 && !ended()) {
    const std::string bye = "Control: " + std::to_string(kFirstChunk | kExit) + " 0\n";
    if (!outOfStep_) {
      if (spec_.transport == Transport::Pipes) {
        ssize_t n = write(toChild_, bye.data(), bye.size());
        (void)n;
      } else if (semId_ >= 0) {
        llvm::consumeError(send(bye));  // it answers with its control line and leaves
      }
    }
    if (toChild_ >= 0) {
      close(toChild_);
      toChild_ = -1;
    }
    const auto since = Clock::now();
    while (!ended() && secondsSince(since) < 1.0) usleep(2000);
    if (!ended()) {
      kill(-pid_, SIGKILL);  // its process group: what it started too (as killLiveChildren does)
      kill(pid_, SIGKILL);
      waitpid(pid_, &status_, 0);
      reaped_ = true;
    }
    log(name() + " stopped");
  }
  if (toChild_ >= 0) close(toChild_);
  if (fromChild_ >= 0) close(fromChild_);
  toChild_ = fromChild_ = -1;
  pending_.clear();
  removeIpc();
  pid_ = -1;
  if (live_) {
    live_->state = 0;
    live_ = nullptr;
  }
}

void ChildLink::removeIpc() {
  if (!toFile_.empty()) {
    std::remove(toFile_.c_str());
    std::remove(fromFile_.c_str());
    toFile_.clear();
    fromFile_.clear();
  }
  if (shm_) {
    shmdt(shm_);
    shm_ = nullptr;
  }
  if (shmId_ >= 0) {
    shmctl(shmId_, IPC_RMID, nullptr);
    shmId_ = -1;
  }
  if (semId_ >= 0) {
    semctl(semId_, 0, IPC_RMID);
    semId_ = -1;
  }
}

}  // namespace

std::string findProgram(const std::string& program) {
  auto executable = [](const std::string& p) {
    struct stat st;
    return stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode) && access(p.c_str(), X_OK) == 0;
  };
  if (program.find('/') != std::string::npos) return executable(program) ? program : std::string();
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "/usr/local/bin:/usr/bin:/bin";
  size_t start = 0;
  for (;;) {
    size_t colon = dirs.find(':', start);
    std::string dir = dirs.substr(start, colon == std::string::npos ? std::string::npos : colon - start);
    std::string candidate = (dir.empty() ? std::string(".") : dir) + "/" + program;
    if (executable(candidate)) return candidate;
    if (colon == std::string::npos) return {};
    start = colon + 1;
  }
}

llvm::Expected<std::unique_ptr<EnvironmentLink>> startChildProgram(const CommSpec& spec,
                                                                   const ChildProgramOptions& options) {
  auto link = std::make_unique<ChildLink>(spec, options);
  if (auto e = link->start()) return std::move(e);
  return std::unique_ptr<EnvironmentLink>(std::move(link));
}

}  // namespace lcjit::runtime
