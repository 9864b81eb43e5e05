// Step 1 of an L+C build: run Clang's preprocessor in-process on the .l file (like `g++ -E`),
// keeping angled includes (`#include <...>`) verbatim for the later C++ compile against the PCH.
#pragma once

#include <llvm/Support/Error.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace lcjit::frontend {

struct PreprocessOptions {
  // Searched for `#include "x"` after the including file's own directory.
  std::vector<std::string> includeDirs;
  // (name, value) pairs, like -Dname=value; an empty value defines the macro as 1 (like -Dname).
  std::vector<std::pair<std::string, std::string>> defines;
  // When set, the text of the main file instead of what is on disk (the file need not exist;
  // its directory is still where quoted includes are looked up first): C++ typed at the REPL.
  std::optional<std::string> mainText;
};

// Returns the preprocessed text: comments removed, macros/conditionals/quoted includes applied,
// GNU line markers (`# LINE "FILE" FLAGS`) wherever the line sequence jumps or the file changes,
// original indentation kept, and every active `#include <name>` left as a `#include <name>` line.
// Errors: `FILE:LINE:COL: error: MESSAGE` lines (plus notes).
llvm::Expected<std::string> preprocess(const std::string& lsystemPath, const PreprocessOptions& options);

} // namespace lcjit::frontend
