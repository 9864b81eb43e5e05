// The REPL's text handling that needs neither a terminal nor a model, so that it can be tested
// alone: splitting a command line into words, telling whether typed C++ is complete, and the
// candidates Tab completes to.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include <llvm/Support/Error.h>

namespace lcjit::repl {

// Splits a command's arguments on blanks; "double quotes" keep blanks (file names).
llvm::Expected<std::vector<std::string>> splitWords(std::string_view line);

// Whether C++ typed so far closes every (, [ and { it opens, outside literals and comments, and
// does not end inside a /* comment or with a line-continuing backslash. The REPL reads more lines
// (prompt `...>`) until it does. Too many closing brackets count as complete: the compiler says
// what is wrong.
bool isCompleteCpp(std::string_view text);

// The characters that end a word for completion (and for libedit, which must agree): C++
// punctuation and blanks, but not `:` (commands), `/`, `.` or `-` (file names and options).
inline constexpr const char* kWordBreaks = " \t\n\"'()[]{},;<>=+*%&|!^~?";

struct CompletionSources {
  std::vector<std::string> commands;    // ":load", ":step", …
  std::vector<std::string> modules;     // the loaded model's modules and lpfg's built-in ones
  std::vector<std::string> parameters;  // .vset parameters, for :set
};

struct Completion {
  size_t start = 0;                     // where the completed word begins in the line
  std::vector<std::string> candidates;  // whole words, sorted; directories end with '/'
};

// What the word ending at `cursor` may complete to: a command name in a line's first word that
// starts with ':'; file names after :load and :save; module names after `:string --module`,
// .vset parameters after :set, on/off/close where a command takes them; module names in C++.
Completion complete(std::string_view line, size_t cursor, const CompletionSources& sources);

// Files and folders whose path starts with `prefix` (relative to the working folder unless it is
// absolute); hidden ones only when the name part starts with '.'.
std::vector<std::string> completeFileName(std::string_view prefix);

}  // namespace lcjit::repl
