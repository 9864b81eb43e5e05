// The REPL's input. From a terminal: libedit's line editor (history kept in a file, Tab
// completion through a given function), driven one key at a time through its callback interface
// so that the REPL's one thread can draw the :view window and watch files while a line is being
// typed. From anything else (a script, a pipe): plain lines, with no prompt, editing or history,
// so that a script's output is only what its commands print. From both, SIGINT (Ctrl-C, or a
// notebook's Interrupt) stops what runs and never ends the REPL.
#pragma once
#include <functional>
#include <string>
#include <string_view>

#include "repl/ReplText.h"

namespace lcjit::runtime {
class Engine;
}

namespace lcjit::repl {

class LineReader {
 public:
  using LineHandler = std::function<void(const std::string& line)>;
  using Completer = std::function<Completion(std::string_view line, size_t cursor)>;
  // `onLine` runs for every whole line, from within poll(). One LineReader at a time (libedit's
  // readline interface is global).
  LineReader(LineHandler onLine, Completer complete);
  ~LineReader();
  LineReader(const LineReader&) = delete;
  LineReader& operator=(const LineReader&) = delete;

  bool interactive() const { return interactive_; }
  // The prompt of the next line (shown on a terminal only). May be called from onLine.
  void setPrompt(const std::string& prompt);

  enum class Status { Ok, Interrupted, End };
  // Reads the input there is, waiting at most `timeoutMs` (< 0: until some arrives), and calls
  // onLine for each whole line. Interrupted: Ctrl-C (SIGINT) came while nothing ran; on a
  // terminal it dropped the line being typed. End: end of input (Ctrl-D).
  Status poll(int timeoutMs);
  // For output that comes while a prompt is shown (a watched file was reloaded): the prompt line
  // is cleared, `print` runs, and the prompt and the text typed so far are drawn again below.
  void interject(const std::function<void()>& print);

  // Paging (terminal only): after a screenful, asks whether to show more; false to stop.
  bool more();
  // The terminal's height in lines (24 when it cannot be told).
  int screenRows() const;

  // Ctrl-C (SIGINT, from a terminal or sent to the process) while a command runs: true once per
  // press. `engine`'s derivation step in progress is cancelled by it (Engine::cancelStep); null:
  // none. Any other model code running is interrupted (runtime::interruptEveryRun).
  static bool takeInterrupt();
  static void setInterruptible(runtime::Engine* engine);

  // $XDG_STATE_HOME/lcjit/history when XDG_STATE_HOME is set, else ~/.lcjit_history.
  static std::string historyFile();

 private:
  Status pollTerminal(int timeoutMs);
  Status pollPlain(int timeoutMs);

  LineHandler onLine_;
  Completer complete_;
  bool interactive_ = false;
  std::string prompt_;
  bool installed_ = false;      // libedit is reading a line (the prompt is shown)
  bool end_ = false;
  std::string pending_;         // plain input read but not yet a whole line
  std::string history_;
  friend struct LineReaderCallbacks;
};

}  // namespace lcjit::repl
