// The rewriter's shared parts (Rewriter.cpp: the pass and rewrite(); RewriterChecks.cpp: the
// checks before parsing; RewriterStatements.cpp: the top-level statements; RewriterRules.cpp:
// productions, bodies and module lists; RewriterTables.cpp: the generated code and tables): the
// module table's entries, the error a rewrite stops with, the Emitter that writes C++ under #line
// directives, and the Rewriter's state. Internal to the rewriter, as imgui_internal.h is to
// Dear ImGui.
#pragma once
#include <algorithm>
#include <cctype>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "frontend/lc/Lexer.h"
#include "frontend/lc/Rewriter.h"
#include "runtime/include/lcjit/abi.h"

namespace lcjit::frontend::detail {

struct ModuleEntry {
  int id;
  std::vector<std::string> paramTypes;
};

// The predefined modules' table (Rewriter.cpp).
std::unordered_map<std::string, ModuleEntry> predefinedModules();

struct RewriteError {
  Token at;
  std::string message;
};

inline bool isIdentChar(char c) { return std::isalnum((unsigned char)c) || c == '_'; }

// The nesting, bracket and name limits, and unpaired brackets (RewriterChecks.cpp): throws the
// first limit passed; returns the first unpaired bracket, reported only when rewriting finds
// nothing else.
std::optional<RewriteError> checkBeforeParsing(const Lexed& lx);

// Module ids stop here (`module X = N;`); above them, kAxiomCall marks where a large axiom's
// table has a function of calls (Rewriter::axiomTable).
constexpr long kMaxModuleId = 60000;
constexpr int kAxiomCall = 0xFFFF;
// The most modules an axiom compiles as one function of calls; above it, Rewriter::axiomTable,
// with at most this many calls a function.
constexpr size_t kAxiomPart = 1024;

// A large axiom's parameter as its table's element, or nullopt (RewriterTables.cpp).
std::optional<std::string> tableLiteral(const Token* sign, const Token& number, const std::string& type);

// Writes C++ while tracking the source position it corresponds to, so that user tokens keep
// their line (and, where possible, column) under #line directives.
class Emitter {
 public:
  explicit Emitter(const Lexed& l) : lexed_(l) {}

  void token(const Token& t) {
    moveTo(t, /*exactColumn=*/true);
    put(t.text);
  }
  // Generated text placed at a token's position (so diagnostics about it point there).
  void glueAt(const Token& t, const std::string& s) {
    moveTo(t);
    put(s);
  }
  // Generated text standing for a token, starting at its exact column: Clang's errors about the
  // generated call or declaration (`__lc_emit_A(…)`) point at the module's name in the .l file.
  void replaceAt(const Token& t, const std::string& s) {
    moveTo(t, /*exactColumn=*/true);
    put(s);
  }
  // Generated text continuing the current position.
  void glue(const std::string& s) {
    if (!out_.empty() && !s.empty() && isIdentChar(out_.back()) && isIdentChar(s.front())) put(" ");
    put(s);
  }
  // Generated lines outside any user position.
  void generated(const std::string& s) {
    if (col_ > 1) newline();
    out_ += s;
    if (!s.empty() && s.back() != '\n') out_ += '\n';
    file_ = -1;
    col_ = 1;
  }
  void directive(const std::string& d) {
    if (col_ > 1) newline();
    out_ += d;
    out_ += '\n';
    ++line_;
    col_ = 1;
  }
  std::string take() { return std::move(out_); }
  size_t size() const { return out_.size(); }

 private:
  void newline() {
    out_ += '\n';
    ++line_;
    col_ = 1;
  }
  void put(const std::string& s) {
    out_ += s;
    col_ += (int)s.size();
  }
  // With `exactColumn` (user tokens), generated text that pushed the output past the token's
  // column starts a fresh line under #line, so that Clang's column numbers match the .l file.
  // Columns past kMaxPaddedColumn are not kept: each fresh line would repeat the padding, and a
  // 200,000-character axiom line grew to gigabytes of spaces.
  static constexpr int kMaxPaddedColumn = 4096;
  void moveTo(const Token& t, bool exactColumn = false) {
    bool drifted = exactColumn && file_ == t.file && t.line == line_ && t.col < col_ && t.col <= kMaxPaddedColumn;
    if (file_ != t.file || t.line < line_ || t.line > line_ + 8 || drifted) {
      if (col_ > 1) newline();
      std::string name;
      for (char c : lexed_.files[t.file]) {
        if (c == '\\' || c == '"') name += '\\';
        name += c;
      }
      out_ += "#line " + std::to_string(t.line) + " \"" + name + "\"\n";
      file_ = t.file;
      line_ = t.line;
      col_ = 1;
    }
    while (line_ < t.line) newline();
    if (t.col > col_ && (col_ > 1 || t.col <= kMaxPaddedColumn)) {
      out_.append(t.col - col_, ' ');
      col_ = t.col;
    } else if (!out_.empty() && out_.back() != '\n' &&
               ((t.spaceBefore && !(exactColumn && t.col == col_)) || (isIdentChar(out_.back()) && isIdentChar(t.text.front())))) {
      put(" ");  // (not when the text before ends just at the token's column: the space would move it)
    }
  }

  const Lexed& lexed_;
  std::string out_;
  int file_ = -1, line_ = 0, col_ = 1;
};

struct PatternModule {
  Token name;
  const ModuleEntry* module;
  std::vector<Token> params;
};

struct RuleEntry {
  int kind;
  int groupKind;
  std::string group;   // C++ expression
  std::string vgroup;  // C++ expression
  int counts[5];
  int filter;
  std::vector<int> ids;
  std::string body;
  int line;
  std::string predecessor;  // as written, e.g. "A(x) < B": names the rule in fault messages
  std::string file;         // the file of the predecessor (an #include'd one, or the model)
};

struct FilterEntry {
  bool consider;
  std::vector<int> ids;
};

class Rewriter {
 public:
  Rewriter(Lexed l) : lx_(std::move(l)), out_(lx_), modules_(predefinedModules()) {}

  Rewritten run();  // Rewriter.cpp

 private:
  // ---- token access
  const Token& cur() const { return lx_.tokens[pos_]; }
  const Token& peek(int k = 1) const {
    size_t i = std::min(pos_ + k, lx_.tokens.size() - 1);
    return lx_.tokens[i];
  }
  bool at(Token::Kind k) const { return cur().kind == k; }
  bool atText(const char* s) const { return cur().is(s); }
  const Token& next() {
    const Token& t = lx_.tokens[pos_];
    if (t.kind != Token::End) ++pos_;
    return t;
  }
  const Token& expect(const char* s, const char* what) {
    if (!atText(s)) throw RewriteError{std::string_view(s) == ";" ? justAfterPrevious() : cur(),
                                       std::string("expected '") + s + "' " + what};
    return next();
  }
  [[noreturn]] void fail(const Token& t, std::string msg) { throw RewriteError{t, std::move(msg)}; }
  // Where a missing ';' is reported: just after the statement's last token, where clang and g++
  // point too, not where the reading stopped (often the next line, or a section later).
  Token justAfterPrevious() const {
    Token at = pos_ > 0 ? lx_.tokens[pos_ - 1] : cur();
    at.col += (int)at.text.size();
    return at;
  }
  // A statement that ran into the next one (atNextStatement).
  [[noreturn]] void failMissingSemicolon(const std::string& after) {
    fail(justAfterPrevious(), "expected ';' after the " + after);
  }
  bool atNextStatement() const;

  const ModuleEntry* findModule(const std::string& name) const {
    auto it = modules_.find(name);
    return it == modules_.end() ? nullptr : &it->second;
  }
  const ModuleEntry& requireModule(const Token& t) {
    if (t.kind != Token::Identifier) fail(t, "expected a module name, found '" + t.text + "'");
    const ModuleEntry* m = findModule(t.text);
    if (!m) fail(t, "undeclared module '" + t.text + "'");
    return *m;
  }

  // ---- top level (RewriterStatements.cpp)
  void topLevelItem();
  bool isLabel(const char* word) const { return cur().is(word) && peek().is(":") && !peek(2).is(":"); }
  bool lsystemStatement();
  bool looksLikePredecessor() const;
  void refuseParameterName(const Token& module, const std::vector<Token>& type);
  void moduleDeclaration();
  void expressionFunction(const std::string& head, const char* what);

  // ---- productions and rules (RewriterRules.cpp)
  PatternModule patternModule();
  void rule();
  std::string ruleKindName() const { return kind_ == 0 ? "a production" : kind_ == 1 ? "a decomposition rule" : "an interpretation rule"; }
  void block(bool rule);
  enum class Where { Rule, Control, Function };
  bool produceStatement(Where where);
  void inContext(const Token& kw, int side);
  // In a rule it searches the rule's predecessor; elsewhere (a control statement, a function)
  // that of the rule running when it is called, or the string between steps.
  void inString(const Token& kw, bool rule);
  void bindParams(const PatternModule& m, const std::string& record);
  void successorList(const char* terminator, const char* statement);
  // A module list as parsed: each module's name and each of its parameters as tokens of lx_.
  struct ModuleCall {
    size_t name;  // the module's name: lx_.tokens[name]
    const ModuleEntry* module;
    size_t firstArg, nargs;  // its parameters: ModuleList::args[firstArg, firstArg + nargs)
  };
  struct ModuleList {
    std::vector<ModuleCall> calls;
    std::vector<std::pair<size_t, size_t>> args;  // a parameter's tokens, lx_.tokens[first, second)
  };
  void parseModuleList(const char* terminator, const char* statement, ModuleList& list);

  // ---- generated code (RewriterTables.cpp)
  void emitModule(const Token& at, const Token& nameToken, int id, const std::vector<std::string>& types,
                  const std::vector<std::vector<Token>>& typeTokens);
  void axiomTable(const ModuleList& list, const Token& semi);
  void emitCall(const ModuleList& list, const ModuleCall& c);

  // ---- the model description (RewriterTables.cpp; includesLpfgall: Rewriter.cpp)
  static std::string cString(const std::string& text);
  void emitTables();
  static bool includesLpfgall(const std::string& directive);

  Lexed lx_;
  size_t pos_ = 0;
  size_t lsystemFrom_ = 0;  // the first token of L+C: the one after lpfgall.h's #include
  Emitter out_;
  std::unordered_map<std::string, ModuleEntry> modules_;
  std::vector<ModuleDecl> userModules_;
  int nextModuleId_ = __lc_FirstUserModule;
  int depth_ = 0;
  bool atStatementStart_ = true;
  int kind_ = 0;
  std::string group_ = "0", vgroup_ = "0";
  std::vector<std::string> vgroupsDeclared_;  // every `vgroup N:` (C++ expressions), for NumOfViews
  int groupChecks_ = 0;
  int groupKind_ = 0;
  int ruleGroupKind_ = 0;
  int filter_ = -1;
  std::vector<FilterEntry> filters_;
  std::vector<int> verify_;  // VerifyString:
  std::vector<RuleEntry> rules_;
  std::vector<std::pair<size_t, size_t>> ruleSpans_;  // rules_[i]'s function in the output
  std::set<std::string> controls_;
  Token derivationLengthAt_;  // the first derivation length statement
  bool haveAxiom_ = false, haveDerivationLength_ = false, haveRing_ = false, haveDecompDepth_ = false,
       haveInterpDepth_ = false;
};

}  // namespace lcjit::frontend::detail
