// Clang diagnostics as lcjit's error lines (see ClangDiagnostics.h).
#include "frontend/ClangDiagnostics.h"

#include "frontend/lc/Rewriter.h"

#include <clang/Basic/DiagnosticFrontend.h>
#include <clang/Basic/DiagnosticIDs.h>
#include <clang/Basic/SourceManager.h>
#include <llvm/ADT/SmallString.h>
#include <llvm/Support/raw_ostream.h>

#include <regex>

namespace lcjit::frontend {

namespace {
// Clang's words for the code the rewriter generates, in the model's: a module's parameter types
// are typedefs `__lc_P_A_N` and `produce A(…)` calls `__lc_emit_A(ctx, …)`.
std::string inModelTerms(std::string msg) {
  if (msg.find("__lc_") == std::string::npos) return msg;
  static const std::regex kAlias(R"('__lc_P_\w+' \(aka ('[^']*')\))");
  static const std::regex kCall(R"(^no matching function for call to '__lc_emit_(\w+)'$)");
  static const std::regex kCandidate(R"(^candidate function not viable: (.*) for (\d+)(st|nd|rd|th) argument$)");
  msg = std::regex_replace(msg, kAlias, "$1");
  std::smatch m;
  if (std::regex_match(msg, m, kCall)) return "the values given do not fit the parameters of module '" + m[1].str() + "'";
  if (std::regex_match(msg, m, kCandidate)) {
    int n = std::stoi(m[2].str()) - 1;  // the first argument is the derivation's context
    return "the module is declared here: " + m[1].str() + " for parameter " + std::to_string(n);
  }
  return msg;
}
}  // namespace

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
    if (pl.isValid()) {
      llvm::StringRef file = pl.getFilename();
      if (file.starts_with(kTablesFile)) {
        // The tables are right for any model that compiles up to them: an error in them follows
        // an earlier one, or C++ the model leaves unfinished at its end (Rewriter.h).
        if (level == clang::DiagnosticsEngine::Note || tablesReported_ || !text.empty()) {
          lastWasError_ = false;  // its notes would point into the tables too
          return;
        }
        tablesReported_ = true;
        lastWasError_ = false;
        llvm::StringRef end = file.drop_front(llvm::StringRef(kTablesFile).size()).drop_back().trim();
        os << (end.empty() ? "<model>" : end) << ": error: the model ends inside unfinished C++ (a declaration or "
           << "bracket that its text leaves open)\n";
        return;
      }
      os << file << ':' << pl.getLine() << ':' << pl.getColumn() << ": ";
    }
  }
  llvm::SmallString<256> msg;
  info.FormatDiagnostic(msg);
  os << kind << ": " << inModelTerms(msg.str().str()) << '\n';
}

}  // namespace lcjit::frontend
