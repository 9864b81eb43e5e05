// See LpfgMak.h.
#include "app/session/LpfgMak.h"

#include <clang/Basic/LangStandard.h>
#include <llvm/Support/CommandLine.h>
#include <llvm/Support/FileSystem.h>
#include <llvm/Support/Program.h>
#include <llvm/Support/StringSaver.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <climits>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <set>

#include <dirent.h>
#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include "runtime/Termination.h"
#include "support/InputFile.h"

extern char** environ;

namespace lcjit::app {
namespace fs = std::filesystem;

namespace {

// What lcjit reads of make: a real lpfg.mak prints a few compile commands (some KB). More is a
// makefile lcjit cannot use, and reading it whole would cost memory without a bound.
constexpr size_t kMaxOutput = 4 << 20;
constexpr size_t kMaxErrorText = 16 << 10;  // of make's messages, shown when it fails

// make -n has this long (LCJIT_MAKE_TIME_LIMIT seconds: the tests' way to wait less) to print
// its commands: a $(shell …) runs even with -n, and it may never end.
double timeLimitSeconds() {
  if (const char* e = std::getenv("LCJIT_MAKE_TIME_LIMIT"); e && std::atof(e) > 0) return std::atof(e);
  return 30;
}

// ---- The make step's process group and scratch folder, also for a signal that ends lcjit

// make runs in a process group of its own, with everything it starts ($(shell …) and their
// children): killing the group leaves nothing of the step behind. The handlers below read these
// (plain values: only async-signal-safe calls there).
std::atomic<pid_t> gGroup{0};
std::atomic<bool> gInterrupted{false};
std::atomic<bool> gScratchLive{false};
char gScratch[PATH_MAX];

void killGroup() {
  if (pid_t g = gGroup.load(); g > 0) kill(-g, SIGKILL);
}

// The scratch folder holds links and lsys.ii (and what a `+` recipe line wrote): removed with
// system calls alone, in a signal handler.
void removeScratchNow() {
  if (!gScratchLive.exchange(false)) return;
  int dir = open(gScratch, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir >= 0) {
    alignas(8) char buf[4096];
    for (long n; (n = syscall(SYS_getdents64, dir, buf, sizeof buf)) > 0;)
      for (long at = 0; at < n;) {
        struct Entry {
          uint64_t ino;
          int64_t off;
          unsigned short reclen;
          unsigned char type;
          char name[1];
        };
        const Entry* e = reinterpret_cast<const Entry*>(buf + at);
        at += e->reclen;
        if (std::strcmp(e->name, ".") == 0 || std::strcmp(e->name, "..") == 0) continue;
        if (unlinkat(dir, e->name, 0) != 0) unlinkat(dir, e->name, AT_REMOVEDIR);
      }
    close(dir);
  }
  rmdir(gScratch);
}

void endMakeStep() {
  killGroup();
  removeScratchNow();
}

// Ctrl-C at the terminal reaches lcjit's process group, no longer make's: while make runs, it
// ends make's group, then does what it did before (ends lcjit, or interrupts the REPL's command).
struct sigaction gPreviousSigint;

void onSigint(int sig, siginfo_t* info, void* context) {
  gInterrupted = true;
  killGroup();
  const struct sigaction& before = gPreviousSigint;
  if (before.sa_flags & SA_SIGINFO) {
    if (before.sa_sigaction) before.sa_sigaction(sig, info, context);
  } else if (before.sa_handler == SIG_DFL) {
    runtime::runTerminationCleanups();
    sigaction(SIGINT, &before, nullptr);
    raise(sig);  // blocked until this handler returns, then the default end
  } else if (before.sa_handler != SIG_IGN) {
    before.sa_handler(sig);
  }
}

// The text of make's two streams, each read up to its bound, and how make ended.
struct MakeRun {
  std::string out, err;
  bool outTooLong = false, timedOut = false, interrupted = false;
  int status = 0;
};

llvm::Expected<MakeRun> runMake(const std::string& make, const std::vector<std::string>& args, const std::string& makefile) {
  auto failure = [&](const std::string& why) { return llvm::createStringError(makefile + ": error: " + why); };
  static std::once_flag registered;
  std::call_once(registered, [] { runtime::atTermination(endMakeStep); });

  int out[2], err[2];
  if (pipe2(out, O_CLOEXEC) != 0) return failure(std::string("cannot read it with make: ") + std::strerror(errno));
  if (pipe2(err, O_CLOEXEC) != 0) {
    close(out[0]), close(out[1]);
    return failure(std::string("cannot read it with make: ") + std::strerror(errno));
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, out[1], 1);
  posix_spawn_file_actions_adddup2(&actions, err[1], 2);
  // A group of its own (POSIX_SPAWN_SETPGROUP, 0: its id is make's pid), and signals as a
  // fresh process has them: lcjit ignores SIGPIPE, which would make `yes | head` run for ever.
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  posix_spawnattr_setpgroup(&attr, 0);
  sigset_t none, defaults;
  sigemptyset(&none);
  sigemptyset(&defaults);
  for (int s : {SIGPIPE, SIGINT, SIGQUIT, SIGTERM, SIGHUP, SIGCHLD}) sigaddset(&defaults, s);
  posix_spawnattr_setsigmask(&attr, &none);
  posix_spawnattr_setsigdefault(&attr, &defaults);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);

  // onSigint from just before make starts; SIGINT held back until make's group is known (gGroup),
  // so that a Ctrl-C in between still ends it.
  gInterrupted = false;
  struct sigaction mine {};
  mine.sa_sigaction = onSigint;
  mine.sa_flags = SA_SIGINFO;
  sigemptyset(&mine.sa_mask);
  sigaction(SIGINT, nullptr, &gPreviousSigint);
  const bool forwardSigint = (gPreviousSigint.sa_flags & SA_SIGINFO) || gPreviousSigint.sa_handler != SIG_IGN;
  sigset_t blockInt, saved;
  sigemptyset(&blockInt);
  sigaddset(&blockInt, SIGINT);
  pthread_sigmask(SIG_BLOCK, &blockInt, &saved);
  if (forwardSigint) sigaction(SIGINT, &mine, nullptr);
  pid_t pid = 0;
  int failed = posix_spawn(&pid, make.c_str(), &actions, &attr, argv.data(), environ);
  if (!failed) gGroup = pid;
  pthread_sigmask(SIG_SETMASK, &saved, nullptr);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attr);
  close(out[1]), close(err[1]);
  auto restoreSigint = [&] {
    if (forwardSigint) sigaction(SIGINT, &gPreviousSigint, nullptr);
  };
  if (failed) {
    restoreSigint();
    close(out[0]), close(err[0]);
    return failure("cannot start make: " + std::string(std::strerror(failed)));
  }

  MakeRun run;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeLimitSeconds());
  pollfd fds[2] = {{out[0], POLLIN, 0}, {err[0], POLLIN, 0}};
  char buf[65536];
  while ((fds[0].fd >= 0 || fds[1].fd >= 0) && !run.outTooLong) {
    if (gInterrupted) {
      run.interrupted = true;
      break;
    }
    auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
    if (left <= 0) {
      run.timedOut = true;
      break;
    }
    if (poll(fds, 2, (int)std::min<long long>(left, 1000)) < 0 && errno != EINTR) break;
    for (int i = 0; i < 2; ++i) {
      if (fds[i].fd < 0 || !(fds[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
      ssize_t n = read(fds[i].fd, buf, sizeof buf);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        close(fds[i].fd);
        fds[i].fd = -1;
        continue;
      }
      std::string& text = i == 0 ? run.out : run.err;
      const size_t bound = i == 0 ? kMaxOutput : kMaxErrorText;
      text.append(buf, std::min<size_t>(n, bound - std::min(bound, text.size())));
      if (i == 0 && text.size() >= kMaxOutput) run.outTooLong = true;
    }
  }
  // make has printed all (or lcjit gives up on it): wait for its end without taking its status
  // (its pid, the group's id, stays taken until then), end what is left of its group, then reap.
  for (siginfo_t info; !run.timedOut && !run.interrupted && !run.outTooLong;) {
    info.si_pid = 0;
    if (waitid(P_PID, pid, &info, WEXITED | WNOWAIT | WNOHANG) == 0 && info.si_pid == pid) break;
    if (gInterrupted) run.interrupted = true;
    else if (std::chrono::steady_clock::now() >= deadline) run.timedOut = true;
    else poll(nullptr, 0, 10);
  }
  killGroup();
  gGroup = 0;
  while (waitpid(pid, &run.status, 0) < 0 && errno == EINTR) {
  }
  for (pollfd& f : fds)
    if (f.fd >= 0) close(f.fd);
  restoreSigint();
  run.interrupted = run.interrupted || gInterrupted.exchange(false);
  return run;
}

// ---- Where a flag came from, and whether lcjit can use it

// The recipe lines printed since make's last --trace line ("lpfg.mak:4: update target 'lsys.o'
// due to: lsys.ii") come from the rule there.
struct Origin {
  std::string file;  // as make names it, relative to the scratch folder; "" when not known
  int line = 0;
};

bool traceLine(llvm::StringRef line, Origin& origin) {
  // FILE:LINE: [update ]target '…  (make 4.x; "<builtin>: …" for make's own rules)
  size_t at = line.find(": update target '");
  if (at == llvm::StringRef::npos) at = line.find(": target '");
  if (at == llvm::StringRef::npos) return false;
  llvm::StringRef where = line.take_front(at);
  if (where == "<builtin>") {
    origin = {};
    return true;
  }
  auto [file, number] = where.rsplit(':');
  int n = 0;
  if (file.empty() || number.getAsInteger(10, n) || n <= 0) return false;
  origin = {file.str(), n};
  return true;
}

// FILE:LINE of a flag: the line of `makefile` where the flag is written, when it is written on
// exactly one (comments aside); else the line of the rule whose command printed it (as make
// names a recipe in its own errors, "make: *** [lpfg.mak:4: lsys.o] Error 1"); else the file.
std::string placeOf(const std::string& flag, const Origin& origin, const fs::path& makefile, const fs::path& dir) {
  std::ifstream in(makefile);
  int number = 0, found = 0, count = 0;
  for (std::string line; std::getline(in, line);) {
    ++number;
    size_t text = line.find_first_not_of(" \t");
    if (text != std::string::npos && line[text] != '#' && line.find(flag) != std::string::npos) found = number, ++count;
  }
  if (count == 1) return makefile.string() + ":" + std::to_string(found);
  if (!origin.file.empty()) {
    fs::path file = fs::path(origin.file).is_absolute() ? fs::path(origin.file) : dir / origin.file;
    return file.lexically_normal().string() + ":" + std::to_string(origin.line);
  }
  return makefile.string();
}

// The C++ model code compiles as after a compile command's -std=VALUE, given `current`: ""
// for lpfg's C++11 or C++14 (lcjit compiles C++14 anyway: kDefaultLanguageStandard), VALUE for
// a newer C++; a C standard (for C sources, which lcjit does not compile; g++ ignores it on C++)
// changes nothing. nullopt for a standard Clang does not know as C++ or C.
std::optional<std::string> standardAfter(const std::string& value, const std::string& current) {
  using clang::LangStandard;
  LangStandard::Kind kind = LangStandard::getLangKind(value);
  if (kind == LangStandard::lang_unspecified) return std::nullopt;
  const LangStandard& s = LangStandard::getLangStandardForKind(kind);
  if (s.getLanguage() == clang::Language::C) return current;
  if (s.getLanguage() != clang::Language::CXX) return std::nullopt;
  return s.isCPlusPlus17() ? value : "";
}

std::string knownStandards() {
  using clang::LangStandard;
  std::string names;
  for (int k = 0; k < LangStandard::lang_unspecified; ++k) {
    const LangStandard& s = LangStandard::getLangStandardForKind(LangStandard::Kind(k));
    if (s.getLanguage() == clang::Language::CXX) names += (names.empty() ? "" : ", ") + std::string(s.getName());
  }
  return names;
}

// -DNAME, -DNAME=VALUE, -D'NAME(ARGS)=VALUE': why NAME is no macro name g++ would take, or "".
std::string badMacroName(llvm::StringRef name) {
  auto identifier = [](llvm::StringRef s) {
    if (s.empty() || !(std::isalpha((unsigned char)s[0]) || s[0] == '_')) return false;
    for (char c : s)
      if (!(std::isalnum((unsigned char)c) || c == '_')) return false;
    return true;
  };
  if (name.empty()) return "no macro name";
  auto [head, parameters] = name.split('(');
  if (!identifier(head)) return "a macro's name is an identifier (a letter or _, then letters, digits and _)";
  if (head.size() < name.size() && !parameters.ends_with(")"))
    return "a macro's parameters end with ')'";
  return "";
}

}  // namespace

bool isCppSource(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  return ext == ".cpp" || ext == ".cc" || ext == ".cxx" || ext == ".C" || ext == ".c++";
}

llvm::Expected<std::optional<LpfgMakBuild>> readLpfgMak(const std::string& modelDir) {
  fs::path dir = fs::absolute(modelDir.empty() ? "." : modelDir).lexically_normal();
  fs::path makefile = dir / "lpfg.mak";
  if (!fs::exists(makefile)) return std::nullopt;
  const std::string name = makefile.string();
  auto failure = [&](const std::string& where, const std::string& why) {
    return llvm::createStringError(where + ": error: " + why);
  };
  // make would wait for ever on a FIFO (and read /dev/zero until its time is up).
  if (auto readable = support::readInputFile(name); !readable)
    return failure(name, "cannot read it: " + readable.getError().message());
  auto make = llvm::sys::findProgramByName("make");
  if (!make) return failure(name, "lcjit reads lpfg.mak with make, which is not installed");

  // make -n in a scratch folder that links everything of the model's and has the lsys.ii lpfg's
  // translator would have made: -B prints every command, up to date or not.
  llvm::SmallString<128> scratch;
  if (auto ec = llvm::sys::fs::createUniqueDirectory("lcjit-lpfgmak", scratch))
    return failure(name, "no scratch folder to read it in: " + ec.message());
  if (scratch.size() >= sizeof gScratch) {
    fs::remove(scratch.str().str());
    return failure(name, "no scratch folder to read it in: its path is too long");
  }
  std::memcpy(gScratch, scratch.c_str(), scratch.size() + 1);
  gScratchLive = true;
  struct Cleanup {
    std::string dir;
    ~Cleanup() {
      if (!gScratchLive.exchange(false)) return;  // a signal's cleanup took it
      std::error_code ec;
      fs::remove_all(dir, ec);
    }
  } cleanup{scratch.str().str()};
  // The dummy lsys.ii first, and no link where it is: writing through a link to the model's own
  // lsys.ii (left by lpfg) would change the user's file.
  std::ofstream(fs::path(cleanup.dir) / "lsys.ii") << "\n";
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    fs::path link = fs::path(cleanup.dir) / entry.path().filename();
    if (!fs::exists(fs::symlink_status(link))) fs::create_symlink(entry.path(), link, ec);
  }
  // --trace names the rule of every command (GNU make 4.0 on); an older make is asked without it.
  std::vector<std::string> args = {*make, "-n", "-B", "-s", "--trace", "-C", cleanup.dir, "-f", "lpfg.mak", "lsys.so"};
  auto run = runMake(*make, args, name);
  if (run && !run->interrupted && !run->timedOut && run->status != 0 &&
      (run->err.find("trace") != std::string::npos || run->err.find("option") != std::string::npos)) {
    args.erase(args.begin() + 4);
    run = runMake(*make, args, name);
  }
  if (!run) return run.takeError();
  if (run->interrupted) return failure(name, "make -n was interrupted");
  if (run->timedOut) {
    char limit[32];
    std::snprintf(limit, sizeof limit, "%g s", timeLimitSeconds());
    return failure(name, std::string("make -n did not finish within ") + limit +
                             " (a $(shell …) that does not end?); lcjit stopped it and what it started");
  }
  if (run->outTooLong) {
    // A line as long as half of what was read: the long line, not many short ones.
    const size_t last = run->out.size() - (run->out.rfind('\n') + 1);  // rfind: npos + 1 is 0
    return failure(name, std::string(last * 2 > kMaxOutput ? "make -n printed a command line longer than" : "make -n printed more than") +
                             " lcjit reads of it (" + std::to_string(kMaxOutput >> 20) + " MB; an lpfg.mak's compile commands are far shorter)");
  }
  if (run->status != 0) {
    std::string why = WIFSIGNALED(run->status) ? std::string("make was killed by signal ") + strsignal(WTERMSIG(run->status))
                                               : "make -n could not read it";
    if (!run->err.empty()) why += ":\n" + run->err + (run->err.size() >= kMaxErrorText ? "\n…" : "");
    return failure(name, why);
  }

  LpfgMakBuild build;
  auto absolute = [&](const std::string& p) { return (fs::path(p).is_absolute() ? fs::path(p) : dir / p).lexically_normal().string(); };
  std::set<std::string> seen;  // of every list below, tagged by its first letter
  auto addOnce = [&](char list, auto& to, const std::string& key, auto item) {
    if (seen.insert(list + key).second) to.push_back(std::move(item));
  };
  Origin origin;
  llvm::StringRef rest = run->out;
  while (!rest.empty()) {
    // One command, its lines continued by a backslash joined (as sh reads them).
    std::string command;
    do {
      auto [line, next] = rest.split('\n');
      rest = next;
      if (command.empty() && traceLine(line, origin)) break;
      command += line.str();
      if (command.empty() || command.back() != '\\') break;
      command.pop_back();
    } while (!rest.empty());
    if (command.empty()) continue;
    // The words of the command as sh reads them (quotes, backslashes).
    llvm::BumpPtrAllocator arena;
    llvm::StringSaver saver(arena);
    llvm::SmallVector<const char*, 32> words;
    llvm::cl::TokenizeGNUCommandLine(command, saver, words);
    bool compiles = false;
    for (const char* w : words) compiles = compiles || llvm::StringRef(w) == "-c";
    if (!compiles) continue;  // the link, or anything else: nothing for lcjit
    for (size_t i = 1; i < words.size(); ++i) {
      const llvm::StringRef w = words[i];
      if (w == "-I" && i + 1 < words.size()) {
        std::string d = absolute(words[++i]);
        addOnce('I', build.includeDirs, d, d);
      } else if (w.starts_with("-I")) {
        std::string d = absolute(w.drop_front(2).str());
        addOnce('I', build.includeDirs, d, d);
      } else if (w.starts_with("-D")) {
        // -DNAME[=VALUE], or -D NAME[=VALUE] as g++ takes it too.
        llvm::StringRef d = w.size() > 2 || i + 1 == words.size() ? w.drop_front(2) : llvm::StringRef(words[++i]);
        auto [macro, value] = d.split('=');
        if (std::string why = badMacroName(macro); !why.empty())
          return failure(placeOf(w.size() > 2 ? w.str() : d.str(), origin, makefile, dir),
                         "-D" + d.str() + ": " + why);
        addOnce('D', build.defines, d.str(), std::make_pair(macro.str(), value.str()));
      } else if (w.starts_with("-std=")) {
        std::optional<std::string> standard = standardAfter(w.drop_front(5).str(), build.languageStandard);
        if (!standard)
          return failure(placeOf(w.str(), origin, makefile, dir),
                         w.str() + ": Clang does not know this C++ standard (it knows " + knownStandards() + ")");
        build.languageStandard = *standard;
      } else if (w == "-o" || w == "-MF" || w == "-include") {
        ++i;  // an argument that is no source
      } else if (isCppSource(w.str())) {
        std::string s = absolute(w.str());
        addOnce('S', build.sources, s, s);
      }
    }
  }
  return build;
}

}  // namespace lcjit::app
