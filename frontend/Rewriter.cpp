// L+C → C++ rewriting (see Rewriter.h). A single pass over the token stream: top-level L+C
// statements become functions and table entries, C++ passes through at its original position.
#include "frontend/Rewriter.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <set>
#include <optional>
#include <unordered_map>

#include "frontend/Lexer.h"
#include "runtime/include/lcjit/abi.h"

namespace lcjit::frontend {
namespace {

struct ModuleEntry {
  int id;
  std::vector<std::string> paramTypes;
};

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

struct RewriteError {
  Token at;
  std::string message;
};

bool isIdentChar(char c) { return std::isalnum((unsigned char)c) || c == '_'; }

// Clang's parser (and this rewriter) recurse once per bracket, per operator in prefix position,
// per right-associative operator (=, ?:) and per statement inside a statement (if, else if,
// while, for…). A model nested deeper than the compiling thread's stack allows would end lcjit,
// and with it a live session (2,000 '!' in one expression, 8,000 nested ifs). So
// before anything parses, each statement's nesting is measured token by token: the depth is the
// open brackets plus, at every bracket level, the nesting operators and statements since that
// level's last ';' or ','. Deeper than kMaxNesting is an error at the token that goes too deep;
// clang managed ~1,500 nested '!' on an 8 MB stack, so 1,000 leaves room for the rest.
// checkBeforeParsing does that, and refuses directive lines the compiler would meet before any
// line of the model.
constexpr int kMaxBrackets = 256;  // clang's -fbracket-depth default
constexpr int kMaxNesting = 1000;
// Clang's typo correction of an unknown name costs its length times every candidate's: 100,000
// characters took a minute. No model's names come near this.
constexpr size_t kMaxIdentifier = 1024;

bool isNestingKeyword(const std::string& s) {
  static const std::set<std::string> kWords = {"if", "while", "for", "do", "switch", "case", "default",
                                               "return", "sizeof", "alignof", "new", "delete", "throw", "co_await",
                                               "co_yield", "co_return", "typeid", "noexcept", "decltype"};
  return kWords.count(s) != 0;
}
bool isPrefixOperator(const std::string& s) {
  static const std::set<std::string> kOps = {"!", "~", "-", "+", "*", "&", "++", "--", "&&", "::"};
  return kOps.count(s) != 0;
}
bool isRightAssociative(const std::string& s) {
  static const std::set<std::string> kOps = {"=", "+=", "-=", "*=", "/=", "%=", "&=", "|=", "^=", "<<=", ">>=", "?", ":"};
  return kOps.count(s) != 0;
}

// Also pairs the brackets: one left open (or a stray closer) would swallow or cut the generated
// code that follows the model's text, and Clang's errors would land there, in lcjit's tables,
// instead of at the bracket. The first unpaired one is returned, not thrown: the
// rewriter's own errors ("expected ')' to close the parameter list of module 'A'") say more
// where they apply, so it is reported only when rewriting finds nothing.
std::optional<RewriteError> checkBeforeParsing(const Lexed& lx) {
  struct Level {
    int chain = 0;      // nesting tokens since this level's last ';' or ','
    int lastChain = 0;  // the chain its last ';' ended: an 'else' continues it
    const Token* open = nullptr;  // its bracket
  };
  std::optional<RewriteError> unpaired;
  auto closing = [](const std::string& b) { return std::string(b == "(" ? ")" : b == "[" ? "]" : "}"); };
  std::vector<Level> levels(1);
  int depth = 0;  // the sum of the open levels' chains and the brackets
  const Token* prev = nullptr;
  auto deeper = [&](const Token& t) {
    ++levels.back().chain;
    if (++depth > kMaxNesting)
      throw RewriteError{t, "this nests more than " + std::to_string(kMaxNesting) +
                                " operators, brackets or statements inside one another: too deep to compile"};
  };
  for (const Token& t : lx.tokens) {
    if (t.kind == Token::End) break;
    if (t.kind == Token::Directive) {
      // What the preprocessor leaves is '#pragma …' or a kept '#include <…>'; a line that starts
      // with '#' and no directive name ('##include', a doubled '#') would reach the compiler
      // before any line of the model, as an error in a '.l.cpp' file.
      size_t k = 1;
      while (k < t.text.size() && (t.text[k] == ' ' || t.text[k] == '\t')) ++k;
      if (k < t.text.size() && !std::isalpha((unsigned char)t.text[k]))
        throw RewriteError{t, "'" + t.text.substr(0, k + 1) + "' starts no preprocessor directive (a directive is '#' and its name: #include, #define…)"};
      continue;
    }
    const std::string& s = t.text;
    // The literal takes in the rest of its line, brackets and all: said as Clang (and g++) say
    // it, at the literal, rather than as a bracket it swallowed that is never closed.
    if (t.unterminated) {
      size_t quote = s.find_first_of("\"'");
      if (t.kind == Token::Char) throw RewriteError{t, "missing terminating ' character"};
      if (quote == 0 || s[quote - 1] != 'R') throw RewriteError{t, "missing terminating '\"' character"};
      std::string delimiter = s.substr(quote + 1, s.find('(', quote) - quote - 1);
      throw RewriteError{t, "raw string missing terminating delimiter )" + delimiter + "\""};
    }
    if (t.kind == Token::Identifier && s.size() > kMaxIdentifier)
      throw RewriteError{t, "an identifier of " + std::to_string(s.size()) + " characters: lcjit takes names of up to " +
                                std::to_string(kMaxIdentifier)};
    const bool punct = t.kind == Token::Punct;
    if (punct && (s == "(" || s == "[" || s == "{")) {
      if ((int)levels.size() > kMaxBrackets)
        throw RewriteError{t, "brackets nest more than " + std::to_string(kMaxBrackets) + " deep"};
      deeper(t);
      levels.emplace_back().open = &t;
    } else if (punct && (s == ")" || s == "]" || s == "}")) {
      if (!unpaired && levels.size() == 1) unpaired = RewriteError{t, "'" + s + "' closes no bracket"};
      if (!unpaired && levels.size() > 1 && closing(levels.back().open->text) != s) {
        const Token& o = *levels.back().open;
        unpaired = RewriteError{t, "'" + s + "' does not close the '" + o.text + "' at line " + std::to_string(o.line) +
                                       ", column " + std::to_string(o.col)};
      }
      if (levels.size() > 1) {
        depth -= levels.back().chain + 1;
        levels.pop_back();
        --levels.back().chain;  // the bracket itself
      }
      if (s == "}") {  // a compound statement ends a statement as ';' does
        levels.back().lastChain = levels.back().chain;
        depth -= levels.back().chain;
        levels.back().chain = 0;
      }
    } else if (punct && (s == ";" || s == ",")) {
      levels.back().lastChain = s == ";" ? levels.back().chain : 0;
      depth -= levels.back().chain;
      levels.back().chain = 0;
    } else if (t.kind == Token::Identifier && s == "else") {
      depth += levels.back().lastChain - levels.back().chain;  // back inside its if
      levels.back().chain = levels.back().lastChain;
    } else if ((t.kind == Token::Identifier && isNestingKeyword(s)) || (punct && isRightAssociative(s))) {
      deeper(t);
    } else if (punct && isPrefixOperator(s)) {
      // In prefix position: after an operator or an opening bracket, or at the start.
      bool prefix = !prev || (prev->kind == Token::Punct && prev->text != ")" && prev->text != "]" && prev->text != "}") ||
                    (prev->kind == Token::Identifier && isNestingKeyword(prev->text));
      if (prefix) deeper(t);
    }
    prev = &t;
  }
  if (!unpaired && levels.size() > 1) {
    const Token& o = *levels.back().open;
    unpaired = RewriteError{o, "'" + o.text + "' is never closed (no '" + closing(o.text) + "' matches it)"};
  }
  return unpaired;
}

// Module ids stop here (`module X = N;`); above them, kAxiomCall marks where a large axiom's
// table has a function of calls (Rewriter::axiomTable).
constexpr long kMaxModuleId = 60000;
constexpr int kAxiomCall = 0xFFFF;
// The most modules an axiom compiles as one function of calls; above it, Rewriter::axiomTable,
// with at most this many calls a function.
constexpr size_t kAxiomPart = 1024;

// A parameter of a large axiom's module goes in its table (Rewriter::axiomTable) only where it
// means there exactly what it means in the call: converted to the parameter's type, the same value
// and no error either way (an array's initializer refuses the narrowing conversions a call
// takes). So: a plain decimal literal (no suffix but f, no digit separators), maybe signed, for a
// parameter of an arithmetic type that holds its value. An integer in the type's range (exactly
// representable in a float or double); a floating literal in a float or double without overflow
// or underflow. The table's element is then the literal as written; nullopt: keep the call.
std::optional<std::string> tableLiteral(const Token* sign, const Token& number, const std::string& type) {
  static const std::map<std::string, std::pair<long long, long long>> kIntegers = {
      {"int", {INT32_MIN, INT32_MAX}},   {"short", {INT16_MIN, INT16_MAX}},  {"unsigned short", {0, UINT16_MAX}},
      {"unsigned", {0, UINT32_MAX}},     {"unsigned int", {0, UINT32_MAX}},  {"long", {INT64_MIN, INT64_MAX}},
      {"long long", {INT64_MIN, INT64_MAX}}, {"unsigned long", {0, INT64_MAX}}, {"unsigned long long", {0, INT64_MAX}},
      {"float", {-(1LL << 24), 1LL << 24}}, {"double", {-(1LL << 53), 1LL << 53}}};
  const std::string& s = number.text;
  if (number.kind != Token::Number || s.empty()) return std::nullopt;
  const bool negative = sign && sign->text == "-";
  const std::string text = (sign ? sign->text : "") + s;
  // An integer: decimal digits, without a leading 0 (octal); up to 18 of them fit a long long.
  if (std::all_of(s.begin(), s.end(), [](char c) { return std::isdigit((unsigned char)c); })) {
    if ((s.size() > 1 && s[0] == '0') || s.size() > 18) return std::nullopt;
    long long v = std::stoll(s) * (negative ? -1 : 1);
    auto range = kIntegers.find(type);
    if (range == kIntegers.end() || v < range->second.first || v > range->second.second) return std::nullopt;
    return text;
  }
  // A floating literal: digits with a '.' or an exponent or both, and maybe an f.
  if (type != "float" && type != "double") return std::nullopt;
  size_t i = 0, digits = 0;
  while (i < s.size() && std::isdigit((unsigned char)s[i])) ++i, ++digits;
  bool point = i < s.size() && s[i] == '.', exponent = false;
  if (point)
    for (++i; i < s.size() && std::isdigit((unsigned char)s[i]); ++i) ++digits;
  if (digits == 0) return std::nullopt;
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    size_t e = ++i;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) e = ++i;
    while (i < s.size() && std::isdigit((unsigned char)s[i])) ++i;
    if (i == e) return std::nullopt;
    exponent = true;
  }
  const bool isFloat = i < s.size() && (s[i] == 'f' || s[i] == 'F');
  if (i + isFloat != s.size() || !(point || exponent)) return std::nullopt;
  errno = 0;
  double d = std::strtod(s.substr(0, i).c_str(), nullptr);
  if (errno == ERANGE) return std::nullopt;
  if (isFloat || type == "float") {
    errno = 0;
    if (std::fabs(d) > FLT_MAX) return std::nullopt;
    float f = isFloat ? std::strtof(s.substr(0, i).c_str(), nullptr) : (float)d;
    if (errno == ERANGE || !std::isfinite(f) || (f == 0) != (d == 0) || (f != 0 && std::fabs(f) < FLT_MIN)) return std::nullopt;
  } else if (d != 0 && std::fabs(d) < DBL_MIN) {
    return std::nullopt;
  }
  return text;
}

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

  Rewritten run() {
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
  // Whether the current token begins the next statement rather than continuing this one: a C++
  // statement keyword or `produce`; or, first on its line, a label (`production:`, `Start:`,
  // `axiom:`) or a word only an L+C statement begins with. Module lists and L+C's expressions
  // hold none of them.
  bool atNextStatement() const {
    const Token& t = cur();
    if (t.kind != Token::Identifier || pos_ == 0) return false;
    static const std::set<std::string> statements = {"else",  "if",       "for",  "while",   "do",
                                                     "switch", "return",  "break", "continue", "goto",
                                                     "case",  "default",  "produce", "nproduce"};
    if (statements.count(t.text)) return true;
    // After a token that can end a statement (not `?` in `c ?\n a : b`), and first on its line.
    const Token& before = lx_.tokens[pos_ - 1];
    bool canEnd = before.kind == Token::Identifier || before.kind == Token::Number || before.kind == Token::String ||
                  before.kind == Token::Char || before.is(")") || before.is("]");
    if (!canEnd || before.line == t.line) return false;
    static const std::set<std::string> starts = {"module",   "derivation", "maximum", "group", "endgroup",
                                                 "vgroup",   "ggroup",     "ring",    "consider", "ignore"};
    return peek().is(":") || starts.count(t.text) > 0;
  }

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

  // ---- top level
  void topLevelItem() {
    const Token& t = cur();
    if (t.kind == Token::Directive) {
      out_.directive(t.text);
      next();
      atStatementStart_ = true;
      return;
    }
    if (atStatementStart_ && t.kind == Token::Identifier && pos_ >= lsystemFrom_ && lsystemStatement()) {
      atStatementStart_ = true;
      return;
    }
    // produce/nproduce inside C++ functions (lpfg's translator takes them anywhere): they write
    // to the successor of the rule running, which the function was called from.
    if (depth_ > 0 && pos_ >= lsystemFrom_ && produceStatement(Where::Function)) return;
    // C++ passes through; statement boundaries are only recognised at namespace scope.
    out_.token(t);
    next();
    if (t.is("{") || t.is("(") || t.is("[")) ++depth_;
    if (t.is("}") || t.is(")") || t.is("]")) --depth_;
    atStatementStart_ = depth_ == 0 && (t.is(";") || t.is("}"));
  }

  bool isLabel(const char* word) const { return cur().is(word) && peek().is(":") && !peek(2).is(":"); }

  bool lsystemStatement() {
    const Token& t = cur();
    const std::string& w = t.text;
    if (w == "module" && peek().kind == Token::Identifier) return moduleDeclaration(), true;
    if (w == "derivation" && peek().is("length") && peek(2).is(":")) {
      if (haveDerivationLength_)  // a C++ redefinition of lcjit's own name, before
        fail(t, "'derivation length:' is given twice (first on line " + std::to_string(derivationLengthAt_.line) + ")");
      derivationLengthAt_ = t;
      next(), next(), next();
      haveDerivationLength_ = true;
      expressionFunction("static int __lc_derivation_length() { return (int)(", "derivation length");
      return true;
    }
    if ((w == "axiom" || w == "Axiom") && peek().is(":")) {
      next(), next();
      if (haveAxiom_) fail(t, "the model has more than one axiom");
      haveAxiom_ = true;
      ModuleList list;
      parseModuleList(";", "axiom", list);
      const Token& semi = expect(";", "after the axiom");
      if (list.calls.size() > kAxiomPart) return axiomTable(list, semi), true;
      // Runs once: optimising it gains nothing and cost seconds on a 32,000-module axiom.
      out_.glueAt(t, "__attribute__((optnone, noinline)) static void __lc_axiom(__lc_Ctx* __lc_ctx) {");
      for (const ModuleCall& c : list.calls) emitCall(list, c);
      out_.glue("}");
      return true;
    }
    if (w == "ring" && peek().is("L") && peek(2).is("-") && peek(3).is("system") && peek(4).is(":")) {
      for (int i = 0; i < 5; ++i) next();
      haveRing_ = true;
      expressionFunction("static int __lc_ring_lsystem() { return (int)(", "ring L-system");
      return true;
    }
    if (w == "maximum" && peek().is("depth") && peek(2).is(":")) {
      next(), next(), next();
      if (atText("-") && peek().kind == Token::Number) fail(cur(), "the maximum depth must be at least 0");
      bool interp = kind_ == 2;
      (interp ? haveInterpDepth_ : haveDecompDepth_) = true;
      expressionFunction(interp ? "static int __lc_interpretation_depth() { return (int)("
                                : "static int __lc_decomposition_depth() { return (int)(",
                         "maximum depth");
      return true;
    }
    if ((w == "ignore" || w == "consider") && peek().is(":")) {
      next(), next();
      FilterEntry f{w == "consider", {}};
      while (!atText(";")) {
        if (at(Token::End)) fail(cur(), "expected ';' after the module list");
        const Token& m = next();
        f.ids.push_back(requireModule(m).id);
      }
      next();
      if (f.ids.empty() && !f.consider) {
        filter_ = -1;  // `ignore: ;` cancels
      } else {
        filters_.push_back(std::move(f));
        filter_ = (int)filters_.size() - 1;
      }
      return true;
    }
    static const std::map<std::string, std::string> control = {
        {"Start", "__lc_start"}, {"StartEach", "__lc_start_each"}, {"EndEach", "__lc_end_each"}, {"End", "__lc_end"}};
    if (auto it = control.find(w); it != control.end() && peek().is(":") && peek(2).is("{")) {
      next(), next();
      if (!controls_.insert(it->second).second) fail(t, "'" + w + ":' appears more than once");
      out_.glueAt(t, "static void " + it->second + "()");
      block(/*rule=*/false);
      return true;
    }
    // A section header does not end a group or a view group (lpfg's translator keeps both).
    if ((w == "production" || w == "decomposition" || w == "interpretation" || w == "homomorphism") && isLabel(w.c_str())) {
      next(), next();
      kind_ = w == "production" ? 0 : w == "decomposition" ? 1 : 2;
      return true;
    }
    // lpfg's translator also spells vgroup `window`, and endvgroup `endwindow`.
    if ((w == "group" || w == "ggroup" || w == "vgroup" || w == "window") && peek(2).is(":") &&
        (peek().kind == Token::Number || peek().kind == Token::Identifier)) {
      next();
      const Token& number = next();
      std::string id = number.text;
      // A number as C++ reads it (0x…, 0… octal) that fits an int: else the error would come from
      // the generated tables, with no line of the model.
      int value = 0;
      if (number.kind == Token::Number && llvm::StringRef(id).getAsInteger(0, value))
        fail(number, "'" + id + "' is not a " + w + " number (an int: decimal, 0x… or 0… octal)");
      // A named group number goes into the tables too: check it here, at its line.
      if (number.kind == Token::Identifier) {
        out_.glueAt(number, "enum : int {" + std::string(" __lc_group_number_") + std::to_string(groupChecks_++) + " =");
        out_.token(number);
        out_.glue("};");
      }
      next();
      if (w == "vgroup" || w == "window") {
        vgroup_ = id;
        vgroupsDeclared_.push_back(id);
      } else {
        group_ = id;
        groupKind_ = w == "group" ? 0 : 1;
      }
      return true;
    }
    if (w == "endgroup" || w == "endvgroup" || w == "endwindow") {
      next();
      if (atText(";")) next();
      if (w == "endgroup") {
        group_ = "0";
        groupKind_ = 0;
      } else {
        vgroup_ = "0";
      }
      return true;
    }
    if (w == "VerifyString" && peek().is(":")) {  // manual §10.4: checked after a batch run
      next(), next();
      while (!atText(";")) {
        if (at(Token::End)) fail(cur(), "expected ';' after the module list");
        verify_.push_back(requireModule(next()).id);
      }
      next();
      return true;
    }
    if (findModule(w)) return rule(), true;
    if (looksLikePredecessor()) fail(t, "undeclared module '" + w + "'");
    return false;
  }

  // A namespace-scope statement made only of names, parenthesised groups and context operators
  // up to a single ':' is no C++ (a declaration with a ':' starts with a class-key or has '::',
  // '=' or '?' first): it is a predecessor whose first module was never declared. Without this
  // check Clang would report "unknown type name".
  bool looksLikePredecessor() const {
    static const std::set<std::string> keywords = {
        "struct", "class", "union", "enum", "template", "typedef", "using", "namespace", "static", "extern", "inline",
        "constexpr", "consteval", "constinit", "const", "volatile", "alignas", "friend", "final", "typename", "decltype",
        "public", "private", "protected", "case", "default", "virtual", "thread_local", "export", "concept", "requires",
        "operator", "explicit", "mutable", "register", "static_assert", "asm", "__attribute__", "__declspec"};
    int depth = 0;
    for (int k = 0;; ++k) {
      const Token& p = peek(k);
      if (p.kind == Token::End || p.kind == Token::Directive || p.is(";") || p.is("{") || p.is("}")) return false;
      if (p.is("(")) {
        ++depth;
        continue;
      }
      if (p.is(")")) {
        if (--depth < 0) return false;
        continue;
      }
      if (depth > 0) continue;
      if (p.is(":")) return k > 0 && !peek(k + 1).is(":");
      if (p.kind == Token::Identifier) {
        if (keywords.count(p.text)) return false;
        continue;
      }
      if (!(p.is("<") || p.is(">") || p.is("<<") || p.is(">>"))) return false;
    }
  }

  // `module A(float y);`: module parameters have no names (§2.3.1: "illegal"). Without this the
  // name became part of the type, and the compile failed in generated code. A type's last identifier is a parameter name when what
  // comes before it ends a type: a type name or keyword (`float y`), `*`, `&` or `>`.
  void refuseParameterName(const Token& module, const std::vector<Token>& type) {
    static const std::set<std::string> typeWords = {"int", "char", "double", "float", "long", "short", "unsigned",
                                                    "signed", "bool", "void", "wchar_t", "char16_t", "char32_t"};
    static const std::set<std::string> beforeATypeName = {"struct", "class", "enum", "union", "const", "volatile", "typename"};
    if (type.size() < 2) return;
    const Token& last = type.back();
    const Token& before = type[type.size() - 2];
    if (last.kind != Token::Identifier || typeWords.count(last.text)) return;
    const bool endsAType = before.kind == Token::Identifier ? !beforeATypeName.count(before.text)
                                                            : before.is("*") || before.is("&") || before.is(">");
    if (endsAType)
      fail(last, "module parameters have no names: remove '" + last.text + "' from the declaration of '" + module.text +
                     "', or make it a comment (/*" + last.text + "*/); the productions name the parameters");
  }

  void moduleDeclaration() {
    const Token& kw = next();
    for (;;) {
      const Token& name = next();
      if (name.kind != Token::Identifier) fail(name, "expected a module name after 'module'");
      if (auto* m = findModule(name.text))
        fail(name, "module '" + name.text + "' is already declared" + (m->id < __lc_FirstUserModule ? " (it is a predefined module)" : ""));
      std::vector<std::string> types;
      std::vector<std::vector<Token>> typeTokens;  // each type as written, for emitModule
      if (atText("(")) {
        next();
        std::string type;
        std::vector<Token> tokens;
        int depth = 0;
        while (!(depth == 0 && atText(")"))) {
          if (at(Token::End) || atText(";")) fail(cur(), "expected ')' to close the parameter list of module '" + name.text + "'");
          const Token& t = next();
          if (t.is("(") || t.is("<")) ++depth;
          if (t.is(")") || t.is(">")) --depth;
          if (depth == 0 && t.is(",")) {
            if (type.empty()) fail(t, "missing parameter type in module '" + name.text + "'");
            refuseParameterName(name, tokens);
            types.push_back(type);
            typeTokens.push_back(std::move(tokens));
            type.clear();
            tokens.clear();
            continue;
          }
          if (!type.empty() && isIdentChar(type.back()) && isIdentChar(t.text.front())) type += ' ';
          type += t.text;
          tokens.push_back(t);
        }
        next();
        if (!type.empty()) {
          refuseParameterName(name, tokens);
          types.push_back(type);
          typeTokens.push_back(std::move(tokens));
        } else if (!types.empty()) {
          fail(cur(), "missing parameter type in module '" + name.text + "'");
        }
        if (types.size() == 1 && types[0] == "void") {
          types.clear();
          typeTokens.clear();
        }
      }
      // `module X(...) = N;` as lpfg's translator takes it: this module is N, the next N+1.
      if (atText("=")) {
        next();
        const Token& n = next();
        long v = n.kind == Token::Number ? std::strtol(n.text.c_str(), nullptr, 10) : -1;
        if (n.kind != Token::Number || v < 0) fail(n, "expected a module id (a number) after '='");
        if (v < nextModuleId_)
          fail(n, "module id " + n.text + " is taken: " +
                      (v < __lc_FirstUserModule ? std::string("ids below 103 are the predefined modules'")
                               : "ids up to " + std::to_string(nextModuleId_ - 1) + " are given already"));
        if (v > kMaxModuleId) fail(n, "module id " + n.text + " is too large (at most " + std::to_string(kMaxModuleId) + ")");
        nextModuleId_ = (int)v;
      }
      int id = nextModuleId_++;
      modules_[name.text] = ModuleEntry{id, types};
      userModules_.push_back(ModuleDecl{name.text, id, types});
      emitModule(kw, name, id, types, typeTokens);
      if (atText(",")) {
        next();
        continue;
      }
      break;
    }
    expect(";", "after the module declaration");
  }

  // Each parameter type is written once, as a typedef with the user's tokens at their own columns,
  // and the generated code names the alias: a misspelt type is one error at the type in the .l
  // file, not one per generated use at columns past the line's end.
  void emitModule(const Token& at, const Token& nameToken, int id, const std::vector<std::string>& types,
                  const std::vector<std::vector<Token>>& typeTokens) {
    const std::string& name = nameToken.text;
    std::vector<std::string> alias(types.size());
    for (size_t i = 0; i < types.size(); ++i) {
      alias[i] = "__lc_P_" + name + "_" + std::to_string(i);
      // A typedef whose type is unknown still declares the name (as invalid), which keeps Clang
      // quiet about its uses; an alias-declaration would not. Types with declarators (function
      // pointers, arrays) need the alias form.
      bool declarator = false;
      for (const Token& t : typeTokens[i]) declarator |= t.is("(") || t.is("[");
      out_.glueAt(typeTokens[i].front(), declarator ? "using " + alias[i] + " =" : "typedef");
      for (const Token& t : typeTokens[i]) out_.token(t);
      out_.glue(declarator ? ";" : " " + alias[i] + ";");
    }
    std::string R = "__lc_R_" + name;
    std::string s = "struct " + R + " { __lc_ModuleId id;";
    for (size_t i = 0; i < types.size(); ++i) s += " " + alias[i] + " p" + std::to_string(i) + ";";
    s += " __lc_ModuleId id2; }; enum : __lc_ModuleId { __lc_id_" + name + " = " + std::to_string(id) + " }; ";
    // The emitting function is placed at the module's name, for Clang's errors about it; its
    // code gets no lines of its own (nodebug): inlined, it takes the line of the produce or
    // nproduce that calls it, and called, its frame is passed over for the caller's. A fault or
    // a stop inside it (the string growing) is then named at the statement that was running,
    // not at the declaration with a column of the generated text past the line's end.
    s += "static inline __attribute__((__nodebug__)) void";
    out_.glueAt(at, s);
    s = "__lc_emit_" + name + "(__lc_Ctx* c";
    for (size_t i = 0; i < types.size(); ++i) s += ", " + alias[i] + " a" + std::to_string(i);
    s += ") { " + R + " r; __builtin_memset(&r, 0, sizeof r); r.id = r.id2 = " + std::to_string(id) + ";";
    for (size_t i = 0; i < types.size(); ++i) s += " r.p" + std::to_string(i) + " = a" + std::to_string(i) + ";";
    s += " __lc_put(c, &r, sizeof r); }";
    out_.replaceAt(nameToken, s);
    s = " static const __lc_Field __lc_fields_" + name + "[" + std::to_string(std::max<size_t>(types.size(), 1)) + "] = {";
    for (size_t i = 0; i < types.size(); ++i) {
      std::string quoted;
      for (char c : types[i]) quoted += c == '"' ? std::string("\\\"") : std::string(1, c);
      s += "{(uint32_t)__builtin_offsetof(" + R + ", p" + std::to_string(i) + "), (uint32_t)sizeof(" + alias[i] + "), __lc_kind_of<" +
           alias[i] + ">(), \"" + quoted + "\"},";
    }
    s += "};";
    out_.glue(s);
  }

  // `KEYWORD: expression ;` → a function returning the expression.
  void expressionFunction(const std::string& head, const char* what) {
    out_.glueAt(cur(), head);
    int depth = 0;
    while (!(depth == 0 && atText(";"))) {
      if (at(Token::End)) fail(cur(), std::string("expected ';' after the ") + what + " expression");
      if (depth == 0 && atNextStatement()) failMissingSemicolon(std::string(what) + " expression");
      const Token& t = next();
      if (t.is("(") || t.is("{") || t.is("[")) ++depth;
      if (t.is(")") || t.is("}") || t.is("]")) --depth;
      out_.token(t);
    }
    next();
    out_.glue("); }");
  }

  // ---- productions and rules
  PatternModule patternModule() {
    const Token& name = next();
    const ModuleEntry& m = requireModule(name);
    PatternModule pm{name, &m, {}};
    if (atText("(")) {
      next();
      while (!atText(")")) {
        const Token& p = next();
        if (p.kind != Token::Identifier)
          fail(p, "expected a parameter name in the predecessor module '" + name.text + "'");
        pm.params.push_back(p);
        if (atText(",")) next();
        else if (!atText(")")) fail(cur(), "expected ',' or ')' in the predecessor module '" + name.text + "'");
      }
      next();
    }
    if (pm.params.size() != m.paramTypes.size())
      fail(name, "module '" + name.text + "' has " + std::to_string(m.paramTypes.size()) + " parameter" +
                     (m.paramTypes.size() == 1 ? "" : "s") + ", the predecessor gives " + std::to_string(pm.params.size()));
    return pm;
  }

  void rule() {
    const Token& first = cur();
    std::vector<std::vector<PatternModule>> segs(1);
    std::vector<std::string> ops;
    std::string predecessor;
    while (!atText(":")) {
      if (at(Token::End) || atText(";") || atText("{"))
        fail(cur(), "expected ':' after the predecessor of " + ruleKindName());
      if (!predecessor.empty()) predecessor += ' ';
      if (atText("<<") || atText("<") || atText(">") || atText(">>")) {
        ops.push_back(next().text);
        predecessor += ops.back();
        segs.emplace_back();
        continue;
      }
      segs.back().push_back(patternModule());
      const PatternModule& pm = segs.back().back();
      predecessor += pm.name.text;
      for (size_t i = 0; i < pm.params.size(); ++i) predecessor += (i ? "," : "(") + pm.params[i].text;
      if (!pm.params.empty()) predecessor += ')';
    }
    next();
    // Assign the segments: newLeft << left < strict > right >> newRight.
    static const char* order[] = {"<<", "<", ">", ">>"};
    bool hasNewLeft = std::count(ops.begin(), ops.end(), "<<") > 0;
    bool hasLeft = std::count(ops.begin(), ops.end(), "<") > 0;
    std::vector<PatternModule> parts[5];
    int last = -1;
    for (size_t i = 0; i < segs.size(); ++i) {
      int part;
      if (i == 0) {
        part = hasNewLeft ? 0 : hasLeft ? 1 : 2;
      } else {
        int oi = 0;
        while (ops[i - 1] != order[oi]) ++oi;
        if (oi <= last) fail(first, "context operators in the wrong order in this predecessor");
        last = oi;
        part = oi == 0 ? (hasLeft ? 1 : 2) : oi == 1 ? 2 : oi == 2 ? 3 : 4;
      }
      if (segs[i].empty()) fail(first, "empty module list in the predecessor");
      parts[part] = std::move(segs[i]);
    }
    if (parts[2].empty()) fail(first, "the predecessor has no strict predecessor");

    RuleEntry r;
    r.kind = kind_;
    r.groupKind = groupKind_;
    r.group = group_;
    r.vgroup = vgroup_;
    r.filter = filter_;
    r.line = first.line;
    r.predecessor = predecessor;
    r.file = first.file < (int)lx_.files.size() ? lx_.files[first.file] : "";
    std::string fn = "__lc_rule_" + std::to_string(rules_.size());
    r.body = fn;
    size_t begin = out_.size();
    out_.glueAt(first, "static void " + fn + "(__lc_Ctx* __lc_ctx, const char* const* __lc_m) {");
    int k = 0;
    for (int p = 0; p < 5; ++p) {
      r.counts[p] = (int)parts[p].size();
      for (auto& pm : parts[p]) {
        r.ids.push_back(pm.module->id);
        if (!pm.params.empty()) {
          std::string rec = "__lc_r" + std::to_string(k);
          out_.glueAt(pm.name, "__lc_R_" + pm.name.text + " " + rec + "; __builtin_memcpy(&" + rec + ", __lc_m[" + std::to_string(k) + "], sizeof " + rec + ");");
          for (size_t i = 0; i < pm.params.size(); ++i) {
            out_.glue("auto");
            out_.token(pm.params[i]);
            out_.glue(" = " + rec + ".p" + std::to_string(i) + ";");
          }
        }
        ++k;
      }
    }
    ruleGroupKind_ = groupKind_;
    if (atText("{")) {
      block(/*rule=*/true);
    } else {
      // lpfg also takes a single produce statement as the body: `A(t) : produce A(t+dt);`.
      out_.glueAt(cur(), "{");
      if (!produceStatement(Where::Rule))
        fail(cur(), "expected '{' or 'produce' to start the body of " + ruleKindName());
      out_.glue("}");
    }
    out_.glue("}");
    ruleSpans_.emplace_back(begin, out_.size());
    if (atText(";")) next();
    rules_.push_back(std::move(r));
  }

  std::string ruleKindName() const { return kind_ == 0 ? "a production" : kind_ == 1 ? "a decomposition rule" : "an interpretation rule"; }

  // A `{ ... }` body, with produce/nproduce/propensity/InXContext rewritten when in a rule.
  void block(bool rule) {
    const Token& open = next();
    out_.token(open);
    int depth = 1;
    while (depth > 0) {
      const Token& t = cur();
      if (t.kind == Token::End) fail(open, "unterminated '{'");
      if (t.kind == Token::Directive) {
        out_.directive(t.text);
        next();
        continue;
      }
      if (t.kind == Token::Identifier) {
        if (produceStatement(rule ? Where::Rule : Where::Control)) continue;
        static const std::map<std::string, int> sides = {
            {"InLeftContext", 0}, {"InRightContext", 1}, {"InNewLeftContext", 2}, {"InNewRightContext", 3}};
        if (auto it = sides.find(t.text); it != sides.end() && peek().is("(")) {
          if (!rule) fail(t, "'" + t.text + "' can only be used in a production or rule body");
          next();
          inContext(t, it->second);
          continue;
        }
      }
      if (t.is("{")) ++depth;
      if (t.is("}")) --depth;
      out_.token(t);
      next();
    }
  }

  enum class Where { Rule, Control, Function };
  // A produce, nproduce or propensity statement at the current token (false if there is none).
  // In a rule body the successor goes to the rule's context; in a function it goes to the rule
  // running when the function is called (lcjit_current_ctx), and in a control statement (Start,
  // EndEach ...) nproduce goes nowhere: no rule is running.
  bool produceStatement(Where where) {
    const Token& t = cur();
    if (t.kind != Token::Identifier) return false;
    bool final = t.is("produce");
    if (final || t.is("nproduce")) {
      // Elsewhere than in a rule, only as a statement: `produce` followed by a module list.
      if (where != Where::Rule && !(peek().is(";") || peek().is("(") || findModule(peek().text))) return false;
      if (final && where == Where::Control) fail(t, "'produce' can only be used in a production or rule body");
      next();
      out_.glueAt(t, where == Where::Rule ? "{" : "{ __lc_Ctx* __lc_ctx = lcjit_current_ctx();");
      successorList(";", "successor");
      const Token& semi = expect(";", "after the successor");
      out_.glueAt(semi, final ? "__lc_ctx->produced = 1; return; }" : "}");
      return true;
    }
    if (t.is("propensity") && where == Where::Rule) {
      if (ruleGroupKind_ != 1) fail(t, "'propensity' can only be used in a ggroup (Gillespie group) production");
      next();
      out_.glueAt(t, "{ __lc_emit_Propensity(__lc_ctx, (");
      int d = 0;
      while (!(d == 0 && atText("produce"))) {
        if (at(Token::End) || (d == 0 && atText(";"))) fail(cur(), "expected 'produce' after the propensity expression");
        const Token& e = next();
        if (e.is("(") || e.is("[") || e.is("{")) ++d;
        if (e.is(")") || e.is("]") || e.is("}")) --d;
        out_.token(e);
      }
      const Token& p = next();
      out_.glueAt(p, "));");
      successorList(";", "successor");
      const Token& semi = expect(";", "after the successor");
      out_.glueAt(semi, "__lc_ctx->produced = 1; }");
      return true;
    }
    if (t.is("propensity") && where == Where::Control) fail(t, "'propensity' can only be used in a production body");
    return false;
  }

  void inContext(const Token& kw, int side) {
    expect("(", ("after " + kw.text).c_str());
    std::vector<PatternModule> mods;
    while (!atText(")")) {
      if (at(Token::End) || atText(";")) fail(cur(), "expected ')' to close " + kw.text);
      mods.push_back(patternModule());
    }
    const Token& close = next();
    if (mods.empty()) fail(kw, kw.text + " needs at least one module");
    std::string n = std::to_string(mods.size());
    std::string s = "([&]() -> bool { static const __lc_ModuleId __lc_ids[] = {";
    for (auto& m : mods) s += std::to_string(m.module->id) + ",";
    s += "}; const char* __lc_p[" + n + "]; if (!lcjit_in_context(__lc_ctx, " + std::to_string(side) + ", __lc_ids, " + n +
         ", __lc_p)) return false;";
    out_.glueAt(kw, s);
    for (size_t i = 0; i < mods.size(); ++i) {
      auto& m = mods[i];
      if (m.params.empty()) continue;
      std::string tmp = "__lc_v" + std::to_string(i);
      out_.glueAt(m.name, "{ __lc_R_" + m.name.text + " __lc_q; __builtin_memcpy(&__lc_q, __lc_p[" + std::to_string(i) + "], sizeof __lc_q);");
      for (size_t j = 0; j < m.params.size(); ++j) {
        out_.token(m.params[j]);
        out_.glue(" = __lc_q.p" + std::to_string(j) + ";");
      }
      out_.glue("}");
    }
    out_.glueAt(close, "return true; }())");
  }

  // A module list in an axiom or successor (`statement`: which), up to (not including)
  // `terminator` at depth 0, written as calls.
  void successorList(const char* terminator, const char* statement) {
    ModuleList list;
    parseModuleList(terminator, statement, list);
    for (const ModuleCall& c : list.calls) emitCall(list, c);
  }

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

  // Parses a module list (see successorList) into `list`; groups `( A B )` are transparent.
  void parseModuleList(const char* terminator, const char* statement, ModuleList& list) {
    while (!atText(terminator)) {
      const Token& t = cur();
      if (t.kind == Token::End) fail(t, std::string("expected '") + terminator + "' after the module list");
      if (terminator[0] == ';' && (t.is("}") || atNextStatement())) failMissingSemicolon(statement);
      if (t.is("(")) {  // produce( A B ); groups are transparent
        next();
        parseModuleList(")", statement, list);
        next();
        continue;
      }
      if (t.kind != Token::Identifier) fail(t, "expected a module name in the module list, found '" + t.text + "'");
      const ModuleEntry& m = requireModule(t);
      ModuleCall call{pos_, &m, list.args.size(), 0};
      next();
      if (atText("(")) {
        next();
        int depth = 0;
        bool startArg = true;
        while (!(depth == 0 && atText(")"))) {
          if (at(Token::End) || (depth == 0 && atText(";")))
            fail(cur(), "expected ')' to close the parameters of module '" + t.text + "'");
          size_t at = pos_;
          const Token& a = next();
          if (depth == 0 && a.is(",")) {
            if (startArg) fail(a, "missing parameter of module '" + t.text + "'");
            startArg = true;
            continue;
          }
          if (startArg) {
            list.args.emplace_back(at, at);
            ++call.nargs;
            startArg = false;
          }
          if (a.is("(") || a.is("[") || a.is("{")) ++depth;
          if (a.is(")") || a.is("]") || a.is("}")) --depth;
          list.args.back().second = at + 1;
        }
        if (startArg && call.nargs > 0) fail(cur(), "missing parameter of module '" + t.text + "'");
        next();
      }
      if (call.nargs != m.paramTypes.size())
        fail(t, "module '" + t.text + "' has " + std::to_string(m.paramTypes.size()) + " parameter" +
                    (m.paramTypes.size() == 1 ? "" : "s") + ", " + std::to_string(call.nargs) + " given");
      list.calls.push_back(call);
    }
  }

  // A large axiom is data (a model of a million modules is a 10 MB axiom), but as one function
  // of calls its code generation grew faster than its length: 32,000 modules compiled in 2 s,
  // 128,000 in 15 s, a million not in minutes. So an axiom of more than kAxiomPart modules is a
  // table read by a loop: the module ids in order, and the parameters that are plain numbers
  // (tableLiteral) in one array per type. A module with any other parameter (an expression, a
  // constant's name, a call with side effects) keeps its call, at its own line and column, in a
  // part: a function of at most kAxiomPart such calls, where each run of them (consecutive in the
  // axiom) is one case of a switch. The ids say kAxiomCall where a run stands, and the loop calls
  // its case there. Every module is written in its place and every expression evaluated in the
  // axiom's order, as in the one function; each compiled function is bounded, and there are few
  // of them (ORC's linking grows faster than their number), so the whole is linear in the axiom.
  void axiomTable(const ModuleList& list, const Token& semi) {
    std::vector<std::string> types, values;  // the value arrays: each one's type and elements
    auto typeIndex = [&](const std::string& type) {
      auto it = std::find(types.begin(), types.end(), type);
      if (it != types.end()) return (size_t)(it - types.begin());
      types.push_back(type);
      values.emplace_back();
      return types.size() - 1;
    };
    std::map<int, std::string> cases;  // the loop's case of each module id in the table
    // The ids as a string, one character each: a million of them lex as one token, where an
    // array's initializer makes and checks an expression for each.
    std::string ids;
    auto hex = [](int id) {
      char b[8];
      std::snprintf(b, sizeof b, "\\x%x", id);
      return std::string(b);
    };
    std::vector<std::string> literals;
    size_t parts = 0, calls = 0, runs = 0;  // the parts so far; the calls and the runs in the open one
    bool inRun = false;                     // the module before was a call
    auto closePart = [&] { out_.glue("break; } return __lc_k == " + std::to_string(runs - 1) + "; }"); };
    for (const ModuleCall& c : list.calls) {
      const ModuleEntry& m = *c.module;
      const Token& name = lx_.tokens[c.name];
      literals.clear();
      for (size_t k = 0; k < c.nargs; ++k) {
        auto [first, end] = list.args[c.firstArg + k];
        const bool sign = end - first == 2 && (lx_.tokens[first].is("-") || lx_.tokens[first].is("+"));
        std::optional<std::string> v;
        if (end - first == 1 + sign) v = tableLiteral(sign ? &lx_.tokens[first] : nullptr, lx_.tokens[end - 1], m.paramTypes[k]);
        if (!v) break;
        literals.push_back(std::move(*v));
      }
      if (literals.size() == c.nargs) {
        inRun = false;
        ids += hex(m.id);
        std::map<size_t, int> taken;  // per value array, this module's elements
        std::string args;
        for (size_t k = 0; k < c.nargs; ++k) {
          size_t v = typeIndex(m.paramTypes[k]);
          values[v] += literals[k] + ",";
          args += ", __lc_v" + std::to_string(v) + "[" + std::to_string(taken[v]++) + "]";
        }
        if (!cases.count(m.id)) {
          std::string& s = cases[m.id];
          s = "case " + std::to_string(m.id) + ": __lc_emit_" + name.text + "(__lc_ctx" + args + ");";
          for (auto [v, count] : taken) s += " __lc_v" + std::to_string(v) + " += " + std::to_string(count) + ";";
          s += " break; ";
        }
        continue;
      }
      if (calls == kAxiomPart) {
        closePart();
        calls = 0;
        inRun = false;
      }
      if (calls == 0) {
        out_.glueAt(name, "__attribute__((optnone, noinline)) static bool __lc_axiom_part_" + std::to_string(parts++) +
                              "(__lc_Ctx* __lc_ctx, unsigned __lc_k) { switch (__lc_k) {");
        runs = 0;
      }
      if (!inRun) {
        ids += hex(kAxiomCall);
        out_.glueAt(name, (runs > 0 ? "break; case " : "case ") + std::to_string(runs) + ":");
        ++runs;
        inRun = true;
      }
      emitCall(list, c);
      ++calls;
    }
    if (calls > 0) closePart();
    // One line, that of the axiom's ';': anything said about the table belongs there.
    std::string s = "static const char16_t __lc_axiom_ids[] = u\"" + ids + "\";";
    for (size_t v = 0; v < types.size(); ++v)
      s += "static const " + types[v] + " __lc_axiom_values_" + std::to_string(v) + "[] = {" + values[v] + "};";
    if (parts > 0) {
      s += "static bool (*const __lc_axiom_parts[])(__lc_Ctx*, unsigned) = {";
      for (size_t p = 0; p < parts; ++p) s += "__lc_axiom_part_" + std::to_string(p) + ",";
      s += "};";
    }
    s += "static void __lc_axiom(__lc_Ctx* __lc_ctx) {";
    for (size_t v = 0; v < types.size(); ++v)
      s += "const " + types[v] + "* __lc_v" + std::to_string(v) + " = __lc_axiom_values_" + std::to_string(v) + ";";
    if (parts > 0) s += "unsigned __lc_part = 0, __lc_run = 0;";
    s += "for (unsigned __lc_i = 0; __lc_i < sizeof __lc_axiom_ids / 2 - 1; ++__lc_i) switch (__lc_axiom_ids[__lc_i]) {";
    for (auto& [id, c] : cases) s += c;
    if (parts > 0) s += "default: if (__lc_axiom_parts[__lc_part](__lc_ctx, __lc_run++)) ++__lc_part, __lc_run = 0;";
    s += "}}";
    out_.glueAt(semi, s);
  }

  // `__lc_emit_A(__lc_ctx, <the parameters' tokens>);`, the name at the module's column.
  void emitCall(const ModuleList& list, const ModuleCall& c) {
    const Token& name = lx_.tokens[c.name];
    out_.replaceAt(name, "__lc_emit_" + name.text + "(__lc_ctx");
    for (size_t k = 0; k < c.nargs; ++k) {
      out_.glue(",");
      auto [first, end] = list.args[c.firstArg + k];
      for (size_t i = first; i < end; ++i) out_.token(lx_.tokens[i]);
    }
    out_.glue(");");
  }

  // ---- the model description
  static std::string cString(const std::string& text) {
    std::string q = "\"";
    for (char c : text) {
      if (c == '\\' || c == '"') q += '\\';
      q += c;
    }
    return q + '"';
  }

  void emitTables() {
    // The tables compile whatever the model says, except after C++ the model leaves unfinished
    // (`template<`, a declaration without its ';'): the name carries where the model's text ends,
    // for DiagCollector to report that instead of errors inside the tables.
    std::string end;
    for (size_t i = lx_.tokens.size(); i-- > 0;) {
      const Token& t = lx_.tokens[i];
      if (t.kind == Token::End || t.kind == Token::Directive) continue;
      end = lx_.files[t.file] + ":" + std::to_string(t.line) + ":" + std::to_string(t.col + (int)t.text.size());
      break;
    }
    std::string s = "#line 1 " + cString(std::string(kTablesFile) + (end.empty() ? "" : " " + end) + ">") + "\n";
    s += "static const __lc_ModuleInfo __lc_user_modules[] = {";
    // One entry per id from the first user module's; ids skipped by `module X = N;` are
    // nameless and never used. userModules_ is in id order: ids only grow.
    int id = __lc_FirstUserModule;
    for (const ModuleDecl& m : userModules_) {
      for (; id < m.id; ++id) s += "{\"\", 4, 0, nullptr},";
      s += "{\"" + m.name + "\", " + "(uint32_t)sizeof(__lc_R_" + m.name + ")" + ", " +
           std::to_string(m.paramTypes.size()) + ", __lc_fields_" + m.name + "},";
      id = m.id + 1;
    }
    for (; id < nextModuleId_; ++id) s += "{\"\", 4, 0, nullptr},";
    if (userModules_.empty()) s += "{nullptr, 0, 0, nullptr}";
    s += "};\n";
    for (size_t i = 0; i < rules_.size(); ++i) {
      s += "static const __lc_ModuleId __lc_pattern_" + std::to_string(i) + "[] = {";
      for (int id : rules_[i].ids) s += std::to_string(id) + ",";
      s += "};\n";
    }
    for (size_t i = 0; i < filters_.size(); ++i) {
      s += "static const __lc_ModuleId __lc_filter_" + std::to_string(i) + "[] = {";
      for (int id : filters_[i].ids) s += std::to_string(id) + ",";
      if (filters_[i].ids.empty()) s += "0";
      s += "};\n";
    }
    s += "static const __lc_Filter __lc_filters[] = {";
    for (size_t i = 0; i < filters_.size(); ++i)
      s += "{" + std::to_string(filters_[i].consider ? 1 : 0) + ", " + std::to_string(filters_[i].ids.size()) + ", __lc_filter_" +
           std::to_string(i) + "},";
    if (filters_.empty()) s += "{0, 0, nullptr}";
    s += "};\n";
    s += "static const __lc_Rule __lc_rules[] = {";
    for (size_t i = 0; i < rules_.size(); ++i) {
      auto& r = rules_[i];
      s += "{" + std::to_string(r.kind) + ", " + std::to_string(r.groupKind) + ", (int16_t)(" + r.group + "), (int16_t)(" +
           r.vgroup + ")";
      for (int c : r.counts) s += ", " + std::to_string(c);
      s += ", " + std::to_string(r.filter) + ", __lc_pattern_" + std::to_string(i) + ", " + r.body + ", " + std::to_string(r.line) +
           ", " + cString(r.predecessor) + ", " + cString(r.file) + "},\n";
    }
    if (rules_.empty()) s += "{}";
    s += "};\n";
    auto fnOrNull = [&](bool have, const char* name) { return have ? std::string(name) : std::string("nullptr"); };
    std::string main = lx_.files.empty() ? "" : lx_.files[0];
    s += "static const __lc_ModuleId __lc_verify[] = {";
    for (int id : verify_) s += std::to_string(id) + ",";
    if (verify_.empty()) s += "0";
    s += "};\n";
    // NumOfViews: lpfg's translator counts the view groups declared, whether or not they hold rules.
    s += "static int __lc_num_of_views() { int n = 0;";
    for (const std::string& id : vgroupsDeclared_) s += " if ((int)(" + id + ") > n) n = (int)(" + id + ");";
    s += " return n + 1; }\n";
    s += "static const __lc_Model __lc_the_model = {" + std::to_string(__lc_AbiVersion) + ", " + std::to_string(nextModuleId_ - __lc_FirstUserModule) +
         ", __lc_user_modules, " + std::to_string(rules_.size()) + ", __lc_rules, " + std::to_string(filters_.size()) +
         ", __lc_filters, __lc_axiom, __lc_derivation_length, " + fnOrNull(haveRing_, "__lc_ring_lsystem") + ", " +
         fnOrNull(haveDecompDepth_, "__lc_decomposition_depth") + ", " + fnOrNull(haveInterpDepth_, "__lc_interpretation_depth") +
         ", " + fnOrNull(controls_.count("__lc_start"), "__lc_start") + ", " +
         fnOrNull(controls_.count("__lc_start_each"), "__lc_start_each") + ", " +
         fnOrNull(controls_.count("__lc_end_each"), "__lc_end_each") + ", " + fnOrNull(controls_.count("__lc_end"), "__lc_end") +
         ", " + cString(main) + ", " + std::to_string(verify_.size()) + ", __lc_verify, __lc_num_of_views};\n";
    s += "extern \"C\" const __lc_Model* __lc_model() { return &__lc_the_model; }\n";
    out_.generated(s);
  }

  static bool includesLpfgall(const std::string& directive) {
    size_t i = directive.find_first_not_of(" \t", 1);
    if (i == std::string::npos || directive.compare(i, 7, "include") != 0) return false;
    i = directive.find_first_not_of(" \t", i + 7);
    return i != std::string::npos &&
           (directive.compare(i, 11, "<lpfgall.h>") == 0 || directive.compare(i, 11, "\"lpfgall.h\"") == 0);
  }

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

}  // namespace

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
    std::optional<RewriteError> unpaired = checkBeforeParsing(lx);
    Rewriter r(std::move(lx));
    auto out = r.run();
    if (unpaired) throw *unpaired;
    return out;
  } catch (const RewriteError& e) {
    const Token& at = e.at.kind == Token::End ? endAt : e.at;
    return llvm::createStringError(llvm::inconvertibleErrorCode(), "%s:%d:%d: error: %s", files[at.file].c_str(), at.line,
                                   at.col, e.message.c_str());
  }
}

}  // namespace lcjit::frontend
