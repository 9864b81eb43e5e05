// Clang diagnostics as lcjit's error lines (see ClangDiagnostics.h).
#include "frontend/ClangDiagnostics.h"

#include <clang/Basic/DiagnosticFrontend.h>
#include <clang/Basic/DiagnosticIDs.h>
#include <clang/Basic/SourceManager.h>
#include <llvm/ADT/SmallString.h>
#include <llvm/Support/raw_ostream.h>

namespace lcjit::frontend {

void DiagCollector::HandleDiagnostic(clang::DiagnosticsEngine::Level level, const clang::Diagnostic& info) {
  clang::DiagnosticConsumer::HandleDiagnostic(level, info);
  const char* kind = nullptr;
  switch (level) {
  case clang::DiagnosticsEngine::Error:
  case clang::DiagnosticsEngine::Fatal:
    kind = "error";
    lastWasError_ = true;
    break;
  case clang::DiagnosticsEngine::Note:
    if (!lastWasError_) return;  // notes of warnings are dropped with their warnings
    kind = "note";
    break;
  default:
    lastWasError_ = false;
    return;
  }
  unsigned id = info.getID();
  if ((id >= clang::diag::DIAG_START_SERIALIZATION && id < clang::diag::DIAG_START_LEX) ||
      id == clang::diag::err_fe_unable_to_load_pch)
    pchProblem = true;

  llvm::raw_string_ostream os(text);
  if (info.getLocation().isValid() && info.hasSourceManager()) {
    const clang::SourceManager& sm = info.getSourceManager();
    clang::PresumedLoc pl = sm.getPresumedLoc(sm.getFileLoc(info.getLocation()));
    if (pl.isValid()) os << pl.getFilename() << ':' << pl.getLine() << ':' << pl.getColumn() << ": ";
  }
  llvm::SmallString<256> msg;
  info.FormatDiagnostic(msg);
  os << kind << ": " << msg << '\n';
}

}  // namespace lcjit::frontend
