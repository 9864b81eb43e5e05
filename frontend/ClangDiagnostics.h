// Clang's diagnostics as lcjit reports them: the errors (and the notes attached to them) of one
// in-process Clang run, as `FILE:LINE:COL: error: MESSAGE` lines. Used by the preprocessor and the
// JIT's compiles alike, so that both report in one form.
#pragma once

#include <clang/Basic/Diagnostic.h>

#include <string>

namespace lcjit::frontend {

class DiagCollector : public clang::DiagnosticConsumer {
public:
  // PresumedLoc honours `#line`, so errors point at the user's .l file, not the generated C++.
  void HandleDiagnostic(clang::DiagnosticsEngine::Level level, const clang::Diagnostic& info) override;

  std::string text;
  // An error came from reading a precompiled header (stale or mismatched): the caller may retry
  // without it.
  bool pchProblem = false;

private:
  bool lastWasError_ = false;
  bool tablesReported_ = false;
};

}  // namespace lcjit::frontend
