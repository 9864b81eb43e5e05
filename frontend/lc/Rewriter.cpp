// L+C → C++ rewriting (see Rewriter.h). A single pass over the token stream: top-level L+C
// statements become functions and table entries, C++ passes through at its original position.
//
// Where each part lives (each section begins with a `// ----` rule):
//   This file: The predefined modules · The pass (Rewriter::run) · rewrite() (the checks, the
//     pass, and its errors as FILE:LINE:COL).
//   RewriterImpl.h: what the parts share: RewriteError, the Emitter (C++ text under #line
//     directives that keep the model's lines and columns), the Rewriter's state.
//   RewriterChecks.cpp: before parsing: Limits · checkBeforeParsing (nesting, brackets, names).
//   RewriterStatements.cpp: Statement boundaries · The top level · Module declarations ·
//     Expressions.
//   RewriterRules.cpp: Predecessors · Bodies (produce, propensity, InXContext) · Module lists.
//   RewriterTables.cpp: Modules (structs, emitting functions) · Large axioms · The model
//     description (the tables).
#include "frontend/lc/Rewriter.h"

#include <optional>

#include "frontend/lc/RewriterImpl.h"

namespace lcjit::frontend::detail {

// ---------------------------------------------------------------------------------------------
// The predefined modules

// The predefined modules (manual §5), from the same table the runtime header uses.
std::unordered_map<std::string, ModuleEntry> predefinedModules() {
  std::unordered_map<std::string, ModuleEntry> m;
#define LCJIT_MODULE(N, I, A, ...) m[#N] = ModuleEntry{I, splitTypes(#__VA_ARGS__)};
  auto splitTypes = [](std::string s) {
    std::vector<std::string> out;
    std::string cur;
    for (char c : s) {
      if (c == ',') {
        out.push_back(cur);
        cur.clear();
      } else if (c != ' ') {
        cur += c;
      }
    }
    if (!cur.empty()) out.push_back(cur);
    return out;
  };
#include "runtime/include/lcjit/stdmods.def"
#undef LCJIT_MODULE
  return m;
}

// ---------------------------------------------------------------------------------------------
// The pass

Rewritten Rewriter::run() {
  // lpfg's translator starts at lpfgall.h (its `#pragma L2C start`): what a model includes
  // before it is plain C++, whatever names it uses. Without lpfgall.h, all of it is L+C.
  for (size_t i = 0; i < lx_.tokens.size(); ++i)
    if (lx_.tokens[i].kind == Token::Directive && includesLpfgall(lx_.tokens[i].text)) {
      lsystemFrom_ = i + 1;
      break;
    }
  while (!at(Token::End)) topLevelItem();
  if (!haveAxiom_) throw RewriteError{cur(), "the model has no 'axiom:' statement"};
  if (!haveDerivationLength_) throw RewriteError{cur(), "the model has no 'derivation length:' statement"};
  size_t tablesAt = out_.size();
  emitTables();
  Rewritten r;
  r.cpp = out_.take();
  r.userModules = userModules_;
  r.ruleCount = (int)rules_.size();
  r.ruleSpans = ruleSpans_;
  r.tablesAt = tablesAt;
  return r;
}

bool Rewriter::includesLpfgall(const std::string& directive) {
  size_t i = directive.find_first_not_of(" \t", 1);
  if (i == std::string::npos || directive.compare(i, 7, "include") != 0) return false;
  i = directive.find_first_not_of(" \t", i + 7);
  return i != std::string::npos &&
         (directive.compare(i, 11, "<lpfgall.h>") == 0 || directive.compare(i, 11, "\"lpfgall.h\"") == 0);
}

}  // namespace lcjit::frontend::detail

namespace lcjit::frontend {

// ---------------------------------------------------------------------------------------------
// rewrite()

llvm::Expected<Rewritten> rewrite(const std::string& preprocessed, const std::string& mainFile) {
  Lexed lx = lex(preprocessed, mainFile);
  std::vector<std::string> files = lx.files;
  // What is missing at the end of the file is reported just after its last token (line 1 of an
  // empty file), not on a line past its end.
  Token endAt = lx.tokens.back();
  endAt.line = 1, endAt.col = 1;
  for (auto it = lx.tokens.rbegin(); it != lx.tokens.rend(); ++it)
    if (it->kind != Token::End && it->kind != Token::Directive && it->file == lx.tokens.back().file) {
      endAt.line = it->line, endAt.col = it->col + (int)it->text.size();
      break;
    }
  try {
    std::optional<detail::RewriteError> unpaired = detail::checkBeforeParsing(lx);
    detail::Rewriter r(std::move(lx));
    auto out = r.run();
    if (unpaired) throw *unpaired;
    return out;
  } catch (const detail::RewriteError& e) {
    const Token& at = e.at.kind == Token::End ? endAt : e.at;
    return llvm::createStringError(llvm::inconvertibleErrorCode(), "%s:%d:%d: error: %s", files[at.file].c_str(), at.line,
                                   at.col, e.message.c_str());
  }
}

}  // namespace lcjit::frontend
