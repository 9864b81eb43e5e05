// The rewriter's top-level statements: C++ passed through, and the L+C statements at namespace
// scope (module declarations, axiom, derivation length, ring L-system, maximum depth, ignore and
// consider, Start/StartEach/EndEach/End, section headers, groups and view groups, VerifyString),
// each written as C++ at its own line. Productions and rule bodies are RewriterRules.cpp's; the
// module structs and the axiom's code, RewriterTables.cpp's.
//
// Sections, in order (each begins with a `// ----` rule): Statement boundaries (atNextStatement)
// · The top level (topLevelItem, lsystemStatement, looksLikePredecessor) · Module declarations
// (refuseParameterName, moduleDeclaration) · Expressions (expressionFunction).
#include <map>
#include <set>

#include "frontend/lc/RewriterImpl.h"

namespace lcjit::frontend::detail {

// ---------------------------------------------------------------------------------------------
// Statement boundaries

// Whether the current token begins the next statement rather than continuing this one: a C++
// statement keyword or `produce`; or, first on its line, a label (`production:`, `Start:`,
// `axiom:`) or a word only an L+C statement begins with. Module lists and L+C's expressions
// hold none of them.
bool Rewriter::atNextStatement() const {
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

// ---------------------------------------------------------------------------------------------
// The top level

void Rewriter::topLevelItem() {
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
  if (depth_ > 0 && pos_ >= lsystemFrom_ && t.is("InString") && peek().is("(")) {
    const Token kw = t;
    next();
    inString(kw, /*rule=*/false);
    return;
  }
  // C++ passes through; statement boundaries are only recognised at namespace scope.
  out_.token(t);
  next();
  if (t.is("{") || t.is("(") || t.is("[")) ++depth_;
  if (t.is("}") || t.is(")") || t.is("]")) --depth_;
  atStatementStart_ = depth_ == 0 && (t.is(";") || t.is("}"));
}

bool Rewriter::lsystemStatement() {
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
bool Rewriter::looksLikePredecessor() const {
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

// ---------------------------------------------------------------------------------------------
// Module declarations

// `module A(float y);`: module parameters have no names (§2.3.1: "illegal"). Without this the
// name became part of the type, and the compile failed in generated code. A type's last identifier is a parameter name when what
// comes before it ends a type: a type name or keyword (`float y`), `*`, `&` or `>`.
void Rewriter::refuseParameterName(const Token& module, const std::vector<Token>& type) {
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

void Rewriter::moduleDeclaration() {
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

// ---------------------------------------------------------------------------------------------
// Expressions

// `KEYWORD: expression ;` → a function returning the expression.
void Rewriter::expressionFunction(const std::string& head, const char* what) {
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

}  // namespace lcjit::frontend::detail
