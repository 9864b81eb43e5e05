// The REPL's input (see LineReader.h).
//
// libedit's callback interface (rl_callback_handler_install / rl_callback_read_char) reads one
// key per call and calls a handler with each whole line. libedit leaves raw mode before calling
// the handler, so a command runs — and prints — with the terminal as usual, and it shows the next
// prompt only after the handler returns.
#include "repl/LineReader.h"

// clang-format off
#include <cstdio>  // editline/readline.h uses FILE without including it
#include <editline/readline.h>
// clang-format on
#include <poll.h>
#include <signal.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <system_error>
#include <vector>

#include "runtime/Engine.h"
#include "runtime/ModelGuard.h"

namespace lcjit::repl {
namespace {

LineReader* active = nullptr;          // libedit's callbacks are plain functions
std::vector<std::string> candidates;   // of the completion in progress
bool lineHandled = false;              // the handler ran during the last rl_callback_read_char
std::atomic<bool> interrupted{false};
std::atomic<runtime::Engine*> interruptible{nullptr};
struct sigaction previousInterrupt;

void onInterrupt(int) {
  interrupted = true;
  if (runtime::Engine* e = interruptible.load()) e->cancelStep();
  // And any other model code running: Start, an interpretation, the initializer of a global
  // typed at the prompt or of a model being loaded.
  runtime::interruptEveryRun();
}

char wordBreaks[64];  // libedit wants a char*, not a const one

}  // namespace

struct LineReaderCallbacks {
  static void line(char* text) {
    LineReader& r = *active;
    lineHandled = true;
    if (!text) {
      r.end_ = true;
      return;
    }
    std::string s(text);
    std::free(text);
    if (s.find_first_not_of(" \t") != std::string::npos) {
      add_history(s.c_str());
      write_history(r.history_.c_str());
    }
    r.onLine_(s);
  }

  static char* next(const char*, int state) {
    static size_t i;
    if (state == 0) i = 0;
    return i < candidates.size() ? strdup(candidates[i++].c_str()) : nullptr;
  }

  static char** attempt(const char* text, int, int end) {
    rl_attempted_completion_over = 1;  // no file names unless complete() gives them
    std::string line = rl_line_buffer ? rl_line_buffer : "";
    if ((size_t)end > line.size()) line = text, end = (int)line.size();  // libedit did not say
    candidates = active->complete_(line, (size_t)end).candidates;
    if (candidates.empty()) return nullptr;
    // A folder is not finished: no space after it.
    rl_completion_append_character = candidates.size() == 1 && candidates[0].back() == '/' ? '\0' : ' ';
    return rl_completion_matches(text, next);
  }
};

LineReader::LineReader(LineHandler onLine, Completer complete)
    : onLine_(std::move(onLine)), complete_(std::move(complete)) {
  interactive_ = isatty(STDIN_FILENO) && isatty(STDOUT_FILENO);
  // Ctrl-C interrupts what runs, whatever drives the REPL: a person at a terminal, or a script,
  // an editor or a notebook kernel through a pipe (a kernel sends SIGINT for its Interrupt).
  // No SA_RESTART on a terminal: Ctrl-C must end more()'s wait for a key. Through a pipe, with
  // SA_RESTART, a write to a full stdout is not cut short (poll() wakes either way).
  struct sigaction sa {};
  sa.sa_handler = onInterrupt;
  sa.sa_flags = interactive_ ? 0 : SA_RESTART;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, &previousInterrupt);
  if (!interactive_) return;
  active = this;
  history_ = historyFile();
  std::error_code ec;
  std::filesystem::create_directories(std::filesystem::path(history_).parent_path(), ec);
  rl_readline_name = "lcjit";  // for ~/.editrc
  std::snprintf(wordBreaks, sizeof wordBreaks, "%s", kWordBreaks);
  rl_basic_word_break_characters = wordBreaks;
  rl_completer_word_break_characters = wordBreaks;
  rl_attempted_completion_function = LineReaderCallbacks::attempt;
  using_history();
  stifle_history(1000);
  read_history(history_.c_str());
}

LineReader::~LineReader() {
  sigaction(SIGINT, &previousInterrupt, nullptr);
  interruptible = nullptr;
  if (!interactive_) return;
  if (installed_) {
    rl_callback_handler_remove();
    std::fputs("\r\033[K", stdout);  // the prompt shown after the last command
    std::fflush(stdout);
  }
  active = nullptr;
}

void LineReader::setPrompt(const std::string& prompt) {
  prompt_ = prompt;
  if (interactive_) rl_set_prompt(prompt_.c_str());
}

LineReader::Status LineReader::poll(int timeoutMs) {
  return interactive_ ? pollTerminal(timeoutMs) : pollPlain(timeoutMs);
}

LineReader::Status LineReader::pollTerminal(int timeoutMs) {
  using Clock = std::chrono::steady_clock;
  if (!installed_) {
    rl_callback_handler_install(prompt_.c_str(), LineReaderCallbacks::line);
    installed_ = true;
  }
  auto deadline = Clock::now() + std::chrono::milliseconds(std::max(timeoutMs, 0));
  for (;;) {
    if (interrupted.exchange(false)) {
      // Ctrl-C at the prompt: drop the line; the next poll shows a fresh prompt.
      rl_callback_handler_remove();
      installed_ = false;
      std::fputs("\n", stdout);
      std::fflush(stdout);
      return Status::Interrupted;
    }
    int wait = -1;
    if (timeoutMs >= 0)
      wait = (int)std::max<long>(0, std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count());
    pollfd p{STDIN_FILENO, POLLIN, 0};
    int n = ::poll(&p, 1, wait);
    if (n < 0 && errno == EINTR) continue;
    if (n == 0) return Status::Ok;
    if (n < 0) end_ = true;
    else {
      lineHandled = false;
      rl_callback_read_char();
    }
    if (end_) {
      rl_callback_handler_remove();
      installed_ = false;
      std::fputs("\n", stdout);
      std::fflush(stdout);
      return Status::End;
    }
    if (lineHandled) {
      // Some libedit versions show the next prompt only on the next key: show it now.
      rl_callback_handler_install(prompt_.c_str(), LineReaderCallbacks::line);
      return Status::Ok;
    }
  }
}

LineReader::Status LineReader::pollPlain(int timeoutMs) {
  for (;;) {
    // Ctrl-C with nothing running (or after what it interrupted had ended) is spent here, as at
    // a terminal's prompt, and the session goes on: C++ waiting for its closing brackets is
    // dropped (Repl), but no line is, since none is being typed: what a script sent stays sent.
    if (interrupted.exchange(false)) return Status::Interrupted;
    size_t nl = pending_.find('\n');
    if (nl != std::string::npos || (end_ && !pending_.empty())) {
      std::string line = pending_.substr(0, nl);
      pending_.erase(0, nl == std::string::npos ? nl : nl + 1);
      if (!line.empty() && line.back() == '\r') line.pop_back();
      onLine_(line);
      return Status::Ok;
    }
    if (end_) return Status::End;
    pollfd p{STDIN_FILENO, POLLIN, 0};
    int n = ::poll(&p, 1, timeoutMs);
    if (n < 0 && errno == EINTR) continue;
    if (n == 0) return Status::Ok;
    char buffer[4096];
    ssize_t got = n < 0 ? -1 : ::read(STDIN_FILENO, buffer, sizeof buffer);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) end_ = true;
    else pending_.append(buffer, (size_t)got);
    timeoutMs = 0;  // what was read may hold a whole line; do not wait for more
  }
}

void LineReader::interject(const std::function<void()>& print) {
  if (!interactive_ || !installed_) {
    print();
    std::fflush(stdout);
    return;
  }
  std::fputs("\r\033[K", stdout);
  std::fflush(stdout);
  print();
  std::fflush(stdout);
  std::fflush(stderr);
  rl_forced_update_display();
}

bool LineReader::more() {
  std::fputs("-- more: Enter shows the next page, q stops -- ", stdout);
  std::fflush(stdout);
  std::string answer;
  char c;
  ssize_t got;
  while ((got = ::read(STDIN_FILENO, &c, 1)) == 1 && c != '\n') answer += c;
  if (got < 0) {
    interrupted = false;  // Ctrl-C answered the question
    std::fputs("\n", stdout);
    return false;
  }
  std::fputs("\033[A\r\033[K", stdout);  // the question goes: the pages join up
  return got == 1 && (answer.empty() || (answer[0] != 'q' && answer[0] != 'Q'));
}

int LineReader::screenRows() const {
  winsize w{};
  if (ioctl(STDOUT_FILENO, TIOCGWINSZ, &w) == 0 && w.ws_row > 2) return w.ws_row;
  return 24;
}

bool LineReader::takeInterrupt() { return interrupted.exchange(false); }

void LineReader::setInterruptible(runtime::Engine* engine) { interruptible = engine; }

std::string LineReader::historyFile() {
  if (const char* state = std::getenv("XDG_STATE_HOME"); state && *state) return std::string(state) + "/lcjit/history";
  const char* home = std::getenv("HOME");
  return std::string(home ? home : ".") + "/.lcjit_history";
}

}  // namespace lcjit::repl
