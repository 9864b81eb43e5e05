// Step 1 of an L+C build: run Clang's preprocessor in-process on the .l file (like lpfg's
// `g++ -E`). Every include is resolved and its macros apply; system headers (the standard
// library's, lcjit's runtime headers) are kept as `#include` lines for the later C++ compile.
#pragma once

#include "frontend/ModelCpp.h"

#include <llvm/ADT/StringRef.h>
#include <llvm/Support/Error.h>

#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace lcjit::frontend {

struct PreprocessOptions {
  // Searched for `#include "x"` after the including file's own directory, and for `#include <x>`
  // first; their headers are the model's own: expanded in the output.
  std::vector<std::string> includeDirs;
  // lcjit's model API headers (<lpfgall.h>): a system directory, searched after includeDirs.
  std::string runtimeIncludeDir;
  // Where the macro image of <lpfgall.h> is kept (Preprocess.cpp); empty: the real header is
  // preprocessed every time (correct, ~25 ms slower).
  std::string cacheDir;
  // Where the build left a macro image (read only), used when the cache folder has none that is
  // current: a new user's first run does not make one (jit::CompilerConfig::prebuiltDir).
  std::string prebuiltDir;
  // (name, value) pairs, like -Dname=value; an empty value defines the macro as 1 (like -Dname).
  std::vector<std::pair<std::string, std::string>> defines;
  // -std= of the model's C++ (as the compile's: __cplusplus and what headers declare).
  std::string languageStandard = kDefaultLanguageStandard;
  // Line markers without their include flags: the output is C++ that clang compiles as it is
  // (a model's own .cpp), rather than input to the rewriter.
  bool plainMarkers = false;
  // -D NAME=VALUE of lcjit's command line (one run of a sweep, docs/sweeps.md): every `#define
  // NAME …` in the model's own files (the main file's folder and includeDirs, not system
  // headers) reads `#define NAME VALUE` instead, on the same line. A name no such file defines
  // is an error listing those it defines, unless it is one of `overridableElsewhere` (the
  // .vset's values and .tset's timelines, which the caller sets). The preprocessed text of such a run is not kept.
  std::vector<std::pair<std::string, std::string>> overrides;
  std::vector<std::string> overridableElsewhere;
  // When set, the text of the main file instead of what is on disk (the file need not exist;
  // its directory is still where quoted includes are looked up first): C++ typed at the REPL.
  std::optional<std::string> mainText;
};

// Returns the preprocessed text: comments removed, macros/conditionals/quoted includes applied,
// GNU line markers (`# LINE "FILE" FLAGS`) wherever the line sequence jumps or the file changes,
// original indentation kept, and every active include of a system header left as an `#include`
// line. A header that is not found is an error at the #include.
// Errors: `FILE:LINE:COL: error: MESSAGE` lines (plus notes).
llvm::Expected<std::string> preprocess(const std::string& lsystemPath, const PreprocessOptions& options);

// Where a column of the preprocessed text is in the file as written. Expanding a macro or
// dropping a comment moves the rest of its line (`F(LENGTH) + bad` becomes `F(2.5) + bad`), and
// the compile, the rewriter and the line tables count columns in the preprocessed text. A line
// that differs from its original is aligned with it (common start and end, then the longest
// common runs between, as a diff would): text in both keeps its place, a macro's argument in its
// expansion is where it was written, and the rest of an expansion is at the macro's name. Keeps the preprocessed
// text; the map is made from it and the files on disk when an error or a fault first needs it
// (thread-safe: faults are reported from the worker).
class OriginalColumns {
public:
  explicit OriginalColumns(std::string preprocessed) : text_(std::move(preprocessed)) {}
  // `column` (1-based) of `line` in `file` (any spelling of its path) as written; unchanged
  // where the line is as written or the file cannot be read.
  unsigned column(llvm::StringRef file, unsigned line, unsigned column) const;
  // The `FILE:LINE:COL:` that starts diagnostic lines, mapped.
  std::string diagnostics(llvm::StringRef text) const;

private:
  void build() const;
  struct Lines {
    std::string original, printed;
  };
  std::string text_;
  mutable std::once_flag built_;
  mutable std::map<std::pair<std::string, unsigned>, Lines> changed_;  // (file, line): lines that differ
};

} // namespace lcjit::frontend
