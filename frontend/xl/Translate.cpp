// XL → L+C (Translate.h). A model is read whole into declarations and rule blocks, then written
// as L+C in the order lpfg's language wants it: the modules, the derivation length, the axiom
// (init()'s `Axiom ==> …`), the productions (the step method's rules), the interpretation rules
// (how a module that extends one of GroIMP's turtle commands, and the turtle commands lcjit has
// under another name, are drawn). What lcjit does not run yet is an error at the construct.
#include "frontend/xl/Translate.h"

#include <cctype>
#include <optional>
#include <set>
#include <string_view>
#include <vector>

#include "frontend/xl/Tokens.h"
#include "frontend/xl/Turtle.h"

namespace lcjit::frontend::xl {

namespace {

using Range = std::pair<size_t, size_t>;  // tokens [first, last)

struct Param {
  size_t at;  // its name's token
  std::string type, name;
  bool inherited = false;  // `super.length`: the base's field, set by the module's argument
};

struct Module {
  size_t keyword = 0, name = 0;
  std::vector<Param> params;
  std::optional<size_t> base;  // after `extends`
  std::vector<Range> baseArgs;
};

// A module on a rule's side: `A`, `A()`, `A(x, y)`; or a bracket ([ or ]) on the right.
struct Node {
  size_t name = 0;
  bool parens = false;
  std::vector<Range> args;  // on the left, each one identifier
  bool bracket = false;
};

struct Rule {
  Node left;
  std::optional<Range> condition;  // `( … )`, its parentheses included
  size_t arrow = 0, end = 0;       // `==>`, `;`
  std::vector<Node> right;
};

struct Method {
  size_t name = 0;
  std::vector<Rule> rules;
};

// The L+C being written. Each token of the user's text goes at its own line and column; what the
// translation adds goes where the writing is (after the token before it).
class Writer {
public:
  explicit Writer(const std::vector<Token>& tokens) : t_(tokens) {}
  // `text` at token `at`'s place.
  void at(size_t at, std::string_view text) {
    // Two names written together (`X]` is `X EB`) would be one: the second starts a line of its own.
    bool joined = !text.empty() && word(text.front()) && !out_.empty() && word(out_.back()) && t_[at].file == file_ &&
                  t_[at].line == line_ && col_ == t_[at].col;
    if (joined) file_.clear();
    moveTo(t_[at]);
    put(text);
  }
  void token(size_t i) { at(i, spelled(t_[i])); }
  void tokens(Range r) {
    for (size_t i = r.first; i < r.second; ++i) token(i);
  }
  void add(std::string_view text) {
    if (!out_.empty() && out_.back() != '\n') put(" ");
    put(text);
  }
  std::string take() { return std::move(out_) + "\n"; }

private:
  static bool word(char c) { return std::isalnum((unsigned char)c) || c == '_'; }
  void put(std::string_view s) {
    out_ += s;
    col_ += (int)s.size();
  }
  void moveTo(const Token& t) {
    if (t.file == file_ && t.line == line_ && col_ <= t.col) {
    } else if (t.file == file_ && t.line == line_ + 1) {
      out_ += '\n', ++line_, col_ = 1;
    } else {
      if (!out_.empty() && out_.back() != '\n') out_ += '\n';
      out_ += "# " + std::to_string(t.line) + " \"" + t.file + "\"\n";
      file_ = t.file, line_ = t.line, col_ = 1;
    }
    if (col_ < t.col) out_.append(t.col - col_, ' '), col_ = t.col;
  }
  // Java's numbers as C++'s: `1.5d` is a double without its suffix.
  static std::string spelled(const Token& t) {
    std::string s = t.text;
    bool hex = s.size() > 1 && (s[1] == 'x' || s[1] == 'X');
    if (t.kind == Token::Number && !hex && (s.back() == 'd' || s.back() == 'D')) s.pop_back();
    return s;
  }
  const std::vector<Token>& t_;
  std::string out_, file_;
  int line_ = 0, col_ = 1;
};

std::string javaType(std::string_view type) {
  if (type == "boolean") return "bool";
  if (type == "int" || type == "float" || type == "double" || type == "long" || type == "short" || type == "char") {
    return std::string(type);
  }
  if (type == "byte") return "signed char";
  return "";
}

// The fields of GroIMP's turtle commands a module's `super.NAME` parameter can set.
struct Field {
  std::string_view command, name, type;
};
constexpr Field kFields[] = {{"F", "length", "float"}, {"F", "diameter", "float"}, {"F", "color", "int"},
                             {"M", "length", "float"}, {"RU", "angle", "float"},   {"RL", "angle", "float"},
                             {"RH", "angle", "float"}};

class Translator {
public:
  Translator(std::vector<Token> tokens) : t_(std::move(tokens)) {}

  std::string run() {
    while (cur().kind != Token::End) topLevel();
    if (!init_) throw XlError{t_[p_], "the model has no `protected void init() [ Axiom ==> … ; ]`: the axiom"};
    return write();
  }

private:
  // ---- reading ----
  const Token& cur() const { return t_[p_]; }
  bool accept(const char* s) {
    if (!cur().is(s)) return false;
    ++p_;
    return true;
  }
  void expect(const char* s, const std::string& where) {
    if (!accept(s)) throw XlError{cur(), "expected '" + std::string(s) + "' " + where};
  }
  size_t identifier(const std::string& what) {
    if (cur().kind != Token::Identifier) throw XlError{cur(), "expected " + what};
    return p_++;
  }
  [[noreturn]] void notYet(const Token& at, const std::string& what) {
    throw XlError{at, what + " is not supported yet by lcjit's XL (docs/xl.md)"};
  }
  // From `(` to its `)`, both included; p_ after it.
  Range balanced() {
    size_t first = p_;
    int depth = 0;
    do {
      if (cur().kind == Token::End) throw XlError{t_[first], "this '" + t_[first].text + "' is not closed"};
      if (cur().is("(") || cur().is("[") || cur().is("{")) ++depth;
      if (cur().is(")") || cur().is("]") || cur().is("}")) --depth;
      ++p_;
    } while (depth > 0);
    return {first, p_};
  }
  // `( a, b(c, d), e )` → the arguments' ranges; p_ after the `)`.
  std::vector<Range> arguments() {
    Range all = balanced();
    std::vector<Range> args;
    size_t from = all.first + 1;
    int depth = 0;
    for (size_t i = all.first + 1; i + 1 < all.second; ++i) {
      if (t_[i].is("(") || t_[i].is("[") || t_[i].is("{")) ++depth;
      if (t_[i].is(")") || t_[i].is("]") || t_[i].is("}")) --depth;
      if (depth == 0 && t_[i].is(",")) {
        if (i == from) throw XlError{t_[i], "expected an argument before ','"};
        args.push_back({from, i});
        from = i + 1;
      }
    }
    if (from < all.second - 1) args.push_back({from, all.second - 1});
    else if (!args.empty()) throw XlError{t_[all.second - 1], "expected an argument before ')'"};
    return args;
  }

  void topLevel() {
    if (cur().is("module")) return module();
    if (cur().is("import") || cur().is("package")) notYet(cur(), "'" + cur().text + "'");
    bool modifiers = false;
    while (cur().is("public") || cur().is("protected") || cur().is("private") || cur().is("static") || cur().is("final"))
      ++p_, modifiers = true;
    if (!cur().is("void")) {
      if (modifiers || cur().kind == Token::Identifier)
        notYet(cur(), "a Java declaration other than `module` and a method of rules");
      throw XlError{cur(), "expected a module declaration (`module A;`) or a method of rules (`public void run() [ … ]`)"};
    }
    ++p_;
    Method m;
    m.name = identifier("the method's name");
    expect("(", "after the method's name");
    if (!accept(")")) notYet(cur(), "a method with parameters");
    if (cur().is("{")) notYet(cur(), "a method of Java statements (`{ … }`)");
    expect("[", "to begin the method's rules (`public void run() [ A ==> B; ]`)");
    while (!accept("]")) m.rules.push_back(rule());
    const std::string& name = t_[m.name].text;
    if (name == "init") {
      for (const Rule& r : m.rules)
        if (!t_[r.left.name].is("Axiom") || r.left.parens || r.condition)
          notYet(t_[r.left.name], "a rule in init() other than `Axiom ==> …`");
      if (m.rules.size() != 1) throw XlError{t_[m.name], "init() should have the one rule `Axiom ==> …;`"};
      init_ = std::move(m);
    } else {
      if (step_)
        notYet(t_[m.name], "a second method of rules (lcjit derives with one, here '" + t_[step_->name].text + "')");
      step_ = std::move(m);
    }
  }

  void module() {
    Module m;
    m.keyword = p_++;
    m.name = identifier("the module's name");
    if (accept("(")) {
      while (!accept(")")) {
        if (!m.params.empty()) expect(",", "between the module's parameters");
        Param param;
        if (accept("super")) {
          expect(".", "after 'super'");
          param.at = identifier("the name of the inherited field");
          param.inherited = true;
        } else {
          size_t type = identifier("a parameter's type");
          param.type = javaType(t_[type].text);
          if (param.type.empty()) notYet(t_[type], "a parameter of type '" + t_[type].text + "'");
          param.at = identifier("the parameter's name");
        }
        param.name = t_[param.at].text;
        m.params.push_back(param);
      }
    }
    if (accept("extends")) {
      m.base = identifier("the module it extends");
      if (cur().is("(")) m.baseArgs = arguments();
    }
    if (cur().is("{")) notYet(cur(), "a module with a body");
    if (cur().is("==>")) notYet(cur(), "an instantiation rule");
    if (cur().is("implements")) notYet(cur(), "'implements'");
    expect(";", "at the end of the module declaration");
    for (Param& param : m.params) {
      if (!param.inherited) continue;
      for (const Field& f : kFields)
        if (m.base && t_[*m.base].text == f.command && f.name == param.name) param.type = f.type;
      if (param.type.empty())
        throw XlError{t_[param.at], "'super." + param.name + "': the module does not extend a turtle command with a field '" +
                                        param.name + "'"};
    }
    for (const Module& other : modules_)
      if (t_[other.name].text == t_[m.name].text) throw XlError{t_[m.name], "a second module '" + t_[m.name].text + "'"};
    // lcjit's own modules (lpfg's) keep their names in L+C: a model's module cannot take one.
    static const std::set<std::string> predefined = {
#define LCJIT_MODULE(Name, ...) #Name,
#include "runtime/include/lcjit/stdmods.def"
#undef LCJIT_MODULE
    };
    if (predefined.count(t_[m.name].text))
      notYet(t_[m.name], "a module named as one of lcjit's own ('" + t_[m.name].text + "', lpfg's)");
    modules_.push_back(std::move(m));
  }

  Rule rule() {
    Rule r;
    if (cur().is("(*")) notYet(cur(), "a context `(* … *)`");
    if (cur().kind == Token::Identifier && t_[p_ + 1].is(":")) notYet(cur(), "a label (`a:A`)");
    if (cur().is("{")) notYet(cur(), "a block of Java statements among the rules");
    r.left.name = identifier("a rule (`A ==> B;`)");
    if (cur().is("(")) {
      r.left.parens = true;
      r.left.args = arguments();
      for (Range a : r.left.args)
        if (a.second != a.first + 1 || t_[a.first].kind != Token::Identifier)
          notYet(t_[a.first], "a pattern's argument other than a name");
    }
    if (accept(",")) {
      if (!cur().is("(")) throw XlError{cur(), "expected '(' to begin the rule's condition"};
      r.condition = balanced();
    }
    if (cur().is("==>>")) notYet(cur(), "an SPO rule (`==>>`)");
    if (cur().is("::>")) notYet(cur(), "an update rule (`::>`)");
    if (cur().kind == Token::Identifier || cur().is("[")) notYet(cur(), "a rule of more than one node on its left side");
    if (!cur().is("==>")) throw XlError{cur(), "expected '==>' after the rule's left side"};
    r.arrow = p_++;
    int depth = 0;
    while (!cur().is(";")) {
      Node n;
      if (cur().kind == Token::End || (cur().is("]") && depth == 0)) throw XlError{cur(), "expected ';' at the end of the rule"};
      if (cur().is("[") || cur().is("]")) {
        depth += cur().is("[") ? 1 : -1;
        n.bracket = true;
        n.name = p_++;
      } else if (cur().kind == Token::Identifier) {
        n.name = p_++;
        if (cur().is("(")) n.parens = true, n.args = arguments();
      } else if (cur().is("{")) {
        notYet(cur(), "a block of Java statements in a rule (`{ … }`)");
      } else {
        throw XlError{cur(), "expected a module, '[' or ']' on the rule's right side"};
      }
      r.right.push_back(n);
    }
    if (depth > 0) throw XlError{cur(), "expected ']' before the end of the rule"};
    r.end = p_++;
    return r;
  }

  // ---- writing ----
  const Module* userModule(const std::string& name) const {
    for (const Module& m : modules_)
      if (t_[m.name].text == name) return &m;
    return nullptr;
  }
  // GroIMP's turtle command `name` with `arity` arguments; a default argument when it has none.
  const TurtleCommand* turtle(size_t at, int arity, std::string_view* defaultArgument) {
    const std::string& name = t_[at].text;
    for (const TurtleDefault& d : kTurtleDefaults)
      if (arity == 0 && d.name == name) *defaultArgument = d.argument, arity = 1;
    bool known = false;
    for (const TurtleCommand& c : kTurtleCommands) {
      known = known || c.name == name;
      if (c.name == name && c.arity == arity) return &c;
    }
    if (known) throw XlError{t_[at], "GroIMP's " + name + " with " + std::to_string(arity) + " arguments is not supported yet"};
    return nullptr;
  }
  // A node as the module of lcjit's string it is: the user's, or a turtle command's.
  void node(const Node& n, bool left) {
    int arity = (int)n.args.size();
    std::string_view defaultArgument;
    if (const Module* m = userModule(t_[n.name].text)) {
      int params = (int)m->params.size();
      if (n.parens && arity != params)
        throw XlError{t_[n.name], "'" + t_[n.name].text + "' has " + std::to_string(params) + " parameter" +
                                      (params == 1 ? "" : "s") + ", given " + std::to_string(arity)};
      if (!n.parens && params > 0 && !left)
        throw XlError{t_[n.name], "'" + t_[n.name].text + "' needs its " + std::to_string(params) + " argument" +
                                      (params == 1 ? "" : "s")};
      w_.token(n.name);
      if (n.parens && params > 0) arguments(n);
      else if (left && params > 0) anyArguments(params);
      return;
    }
    const TurtleCommand* c = turtle(n.name, arity, &defaultArgument);
    if (!c)
      throw XlError{t_[n.name], "no module '" + t_[n.name].text + "': declare it (`module " + t_[n.name].text +
                                    ";`); of GroIMP's turtle commands lcjit has F, F0, M, RU, RL, RH and Null"};
    used_.insert(c);
    if (!defaultArgument.empty()) {
      if (left) notYet(t_[n.name], "a pattern '" + t_[n.name].text + "' without its parameter");
      w_.at(n.name, std::string(c->module) + "(" + std::string(defaultArgument) + ")");
      return;
    }
    w_.at(n.name, c->module);
    if (n.parens && arity > 0) arguments(n);
  }
  void arguments(const Node& n) {
    w_.token(n.args.front().first - 1);  // (
    for (size_t i = 0; i < n.args.size(); ++i) {
      if (i) w_.token(n.args[i].first - 1);  // ,
      w_.tokens(n.args[i]);
    }
    w_.token(n.args.back().second);  // )
  }
  void anyArguments(int count) {
    std::string s = "(";
    for (int i = 0; i < count; ++i) s += (i ? ", __xl_" : "__xl_") + std::to_string(i);
    w_.add(s + ")");
  }
  void right(const Rule& r) {
    for (const Node& n : r.right) {
      if (n.bracket) w_.at(n.name, t_[n.name].is("[") ? "SB" : "EB");  // L+C's names of XL's [ ]
      else node(n, false);
    }
  }
  std::string text(Range r) const {
    std::string s;
    for (size_t i = r.first; i < r.second; ++i) s += (i > r.first ? " " : "") + t_[i].text;
    return s;
  }
  // How a command with these arguments is drawn (lpfg's modules).
  static std::string drawn(std::string_view pattern, const std::vector<std::string>& args) {
    std::string s;
    for (size_t i = 0; i < pattern.size(); ++i) {
      if (pattern[i] == '$' && i + 1 < pattern.size() && std::isdigit((unsigned char)pattern[i + 1])) {
        s += "(" + args[pattern[i + 1] - '1'] + ")";
        ++i;
      } else {
        s += pattern[i];
      }
    }
    return s;
  }

  std::string write() {
    // The body (axiom, productions, interpretation rules) first: it says which of GroIMP's turtle
    // commands the model uses, declared in the head after the user's modules.
    Writer head(t_);
    for (const Module& m : modules_) {
      std::string decl = "module " + t_[m.name].text;
      if (!m.params.empty()) {
        decl += "(";
        for (size_t i = 0; i < m.params.size(); ++i) decl += (i ? ", " : "") + m.params[i].type;
        decl += ")";
      }
      head.at(m.keyword, decl + ";");
    }
    const Rule& axiom = init_->rules.front();
    w_.at(axiom.left.name, "derivation length: 0;");
    w_.add("axiom:");
    right(axiom);
    w_.at(axiom.end, ";");
    if (step_)
      for (const Rule& r : step_->rules) {
        node(r.left, true);
        w_.add(":");
        w_.add("{");
        if (r.condition) {
          w_.add("if");
          w_.tokens(*r.condition);
        }
        w_.at(r.arrow, "produce");
        right(r);
        w_.at(r.end, ";");
        w_.add("}");
      }
    std::vector<std::pair<size_t, std::string>> interpretation;  // (at, rule)
    for (const Module& m : modules_) {
      if (!m.base) continue;
      std::string_view defaultArgument;
      if (userModule(t_[*m.base].text)) notYet(t_[*m.base], "a module extending one of the model's modules");
      const TurtleCommand* c = turtle(*m.base, (int)m.baseArgs.size(), &defaultArgument);
      if (!c) throw XlError{t_[*m.base], "no turtle command '" + t_[*m.base].text + "' to extend (lcjit has F, F0, M, RU, RL, RH and Null)"};
      std::vector<std::string> args;
      for (Range a : m.baseArgs) args.push_back(text(a));
      if (!defaultArgument.empty()) args.push_back(std::string(defaultArgument));
      std::string pattern = c->own ? std::string(c->module) + "($1)" : std::string(c->drawn);
      if (pattern.empty()) continue;
      std::string rule = t_[m.name].text;
      if (!m.params.empty()) {
        rule += "(";
        for (size_t i = 0; i < m.params.size(); ++i) rule += (i ? ", " : "") + m.params[i].name;
        rule += ")";
      }
      interpretation.push_back({m.name, rule + " : { produce " + drawn(pattern, args) + "; }"});
    }
    std::string turtleDecls;
    for (const TurtleCommand& c : kTurtleCommands) {
      if (!used_.count(&c) || c.own) continue;
      bool twice = false;  // one declaration per module
      for (const TurtleCommand& d : kTurtleCommands)
        twice = twice || (&d < &c && d.module == c.module && used_.count(&d));
      if (twice) continue;
      turtleDecls += "module " + std::string(c.module) + (c.declared.empty() ? "" : "(" + std::string(c.declared) + ")") + "; ";
      if (c.drawn.empty()) continue;
      std::vector<std::string> args;
      std::string rule = std::string(c.module);
      if (c.arity > 0) {
        rule += "(";
        for (int i = 0; i < c.arity; ++i) {
          args.push_back("__xl_" + std::to_string(i));
          rule += (i ? ", " : "") + args.back();
        }
        rule += ")";
      }
      interpretation.push_back({init_->name, rule + " : { produce " + drawn(c.drawn, args) + "; }"});
    }
    if (!interpretation.empty()) {
      w_.add("interpretation:");
      for (const auto& [at, rule] : interpretation) w_.at(at, rule);
    }
    if (!turtleDecls.empty()) head.at(init_->name, turtleDecls);
    return "#include <lpfgall.h>\n" + head.take() + w_.take();
  }

  std::vector<Token> t_;
  size_t p_ = 0;
  std::vector<Module> modules_;
  std::optional<Method> init_, step_;
  std::set<const TurtleCommand*> used_;
  Writer w_{t_};
};

std::string errorLine(const XlError& e) {
  return e.at.file + ":" + std::to_string(e.at.line) + ":" + std::to_string(e.at.col) + ": error: " + e.message;
}

}  // namespace

llvm::Expected<std::string> toLplusC(const std::string& preprocessed, const std::string& mainFile) {
  try {
    Translator translator(tokenize(preprocessed, mainFile));
    return translator.run();
  } catch (const XlError& e) {
    return llvm::createStringError(llvm::inconvertibleErrorCode(), errorLine(e));
  }
}

llvm::Expected<Rewritten> rewrite(const std::string& preprocessed, const std::string& mainFile) {
  auto lc = toLplusC(preprocessed, mainFile);
  if (!lc) return lc.takeError();
  return frontend::rewrite(*lc, mainFile);
}

}  // namespace lcjit::frontend::xl
