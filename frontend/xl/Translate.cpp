// XL → L+C (Translate.h). A model is read whole into declarations and rule blocks, then written
// as L+C in the order lpfg's language wants it: the modules, the derivation length, the axiom
// (init()'s `Axiom ==> …`), the productions (the step method's rules), the interpretation rules
// (how a module that extends one of GroIMP's turtle commands, and the turtle commands lcjit has
// under another name, are drawn). What lcjit does not run yet is an error at the construct.
//
// A module's fields are its parameters and the fields it inherits from the turtle command it
// extends (F's length, diameter and colour, M's length, RU's angle…): all of them are parameters
// of its L+C module, those it does not declare (`super.length` declares one) set from the
// arguments of its `extends` (or the command's defaults) when it is made. A label (`t:Trieb`)
// names a copy of the matched node's fields (`t[length]`, `t.alter`), which the rule's code
// blocks may change and the node keeps when the right side names it again (`t`).
#include "frontend/xl/Translate.h"

#include <algorithm>

#include <cctype>
#include <map>
#include <optional>
#include <set>
#include <string_view>
#include <vector>

#include "frontend/xl/Java.h"
#include "frontend/xl/LcWriter.h"
#include "frontend/xl/Model.h"
#include "frontend/xl/Tokens.h"
#include "frontend/xl/Turtle.h"

namespace lcjit::frontend::xl {

namespace {

class Translator {
public:
  // `run`: the rule method each step applies; empty: the first.
  Translator(std::vector<Token> tokens, std::string run) : t_(std::move(tokens)), run_(std::move(run)) {}

  std::string run() {
    while (cur().kind != Token::End) topLevel();
    chooseMethod();
    if (!init_) axiomNode();
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
  // How a token changes the depth of brackets of any kind: ( [ { open, ) ] } close.
  static int nesting(const Token& t) {
    return t.is("(") || t.is("[") || t.is("{") ? 1 : t.is(")") || t.is("]") || t.is("}") ? -1 : 0;
  }
  // From `(` to its `)`, both included; p_ after it.
  Range balanced() {
    size_t first = p_;
    int depth = 0;
    do {
      if (cur().kind == Token::End) throw XlError{t_[first], "this '" + t_[first].text + "' is not closed"};
      depth += nesting(cur());
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
      depth += nesting(t_[i]);
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
    // `import …;`: what lcjit's XL has of GroIMP's classes is there without one (its turtle, its
    // library); a class a model imports for more is refused where the model uses it.
    if (cur().is("import")) {
      while (!accept(";")) {
        if (cur().kind == Token::End) throw XlError{cur(), "expected ';' at the end of the import"};
        ++p_;
      }
      return;
    }
    if (cur().is("package")) notYet(cur(), "'package'");
    bool modifiers = false, constant = false;
    // XL's `const` is Java's `static final`.
    while (cur().is("public") || cur().is("protected") || cur().is("private") || cur().is("static") || cur().is("final") ||
           cur().is("const"))
      constant = constant || cur().is("final") || cur().is("const"), ++p_, modifiers = true;
    const bool java = cur().kind == Token::Identifier && !javaType(cur().text).empty();
    if (!cur().is("void") && !java) {
      if (modifiers || cur().kind == Token::Identifier)
        notYet(cur(), "a Java declaration of type '" + cur().text + "' (lcjit's XL has fields and methods of Java's number and boolean types)");
      throw XlError{cur(), "expected a module declaration (`module A;`) or a method of rules (`public void run() [ … ]`)"};
    }
    // A method of rules is `void NAME() [`; anything else is Java.
    if (!(cur().is("void") && t_[p_ + 2].is("(") && methodOfRules())) return declaration(constant);
    ++p_;
    Method m;
    m.name = identifier("the method's name");
    expect("(", "after the method's name");
    if (!accept(")")) notYet(cur(), "a method with parameters");
    expect("[", "to begin the method's rules (`public void run() [ A ==> B; ]`)");
    while (!accept("]")) m.rules.push_back(rule());
    const std::string& name = t_[m.name].text;
    if (name == "init") {
      for (const Rule& r : m.rules)
        if (!t_[r.left.front().name].is("Axiom") || r.left.size() > 1 || r.left.front().parens || r.condition ||
            r.is(t_, "::>"))
          notYet(t_[r.left.front().name], "a rule in init() other than `Axiom ==> …`");
      if (m.rules.size() != 1) throw XlError{t_[m.name], "init() should have the one rule `Axiom ==> …;`"};
      init_ = std::move(m);
    } else {
      methods_.push_back(std::move(m));
    }
  }

  // The rule method a step applies: the one --run names, else the first (GroIMP's first button).
  void chooseMethod() {
    for (Method& m : methods_)
      if (run_.empty() || t_[m.name].text == run_) {
        step_ = m;
        return;
      }
    if (run_.empty()) return;
    std::string names;
    for (const Method& m : methods_) names += (names.empty() ? "" : ", ") + t_[m.name].text;
    throw XlError{t_[methods_.empty() ? 0 : methods_.front().name], "no rule method '" + run_ + "' to run (--run)" +
                             (names.empty() ? std::string(": the model has none") : "; the model's: " + names)};
  }

  // A model without init() whose rule method has `Axiom ==> …` (the RGG tutorial's and XL's own
  // manual's form): GroIMP's graph starts as the one node Axiom, which that rule rewrites in the
  // first step. lcjit's axiom is then a module Axiom (XL_Axiom in the L+C, L+C's `Axiom:` being
  // its axiom), and the rule one of the step's.
  void axiomNode() {
    const Rule* axiom = nullptr;
    if (step_)
      for (const Rule& r : step_->rules)
        if (r.left.size() == 1 && t_[r.left.front().name].is("Axiom") && !r.left.front().parens) axiom = &r;
    if (!axiom)
      throw XlError{t_[p_], "the model has no axiom: `protected void init() [ Axiom ==> … ; ]`, or `Axiom ==> …;` among its rules"};
    if (userModule("Axiom")) throw XlError{t_[userModule("Axiom")->name], "a module named Axiom: XL's axiom has that name"};
    Module m;
    m.keyword = m.name = axiom->left.front().name;
    m.lcName = "XL_Axiom";
    modules_.push_back(std::move(m));
    axiomIsNode_ = true;
    axiomNameAt_ = axiom->left.front().name;
  }

  // The token after the parentheses that open at `i`; npos when they do not close.
  size_t afterParentheses(size_t i) const {
    int depth = 0;
    do {
      if (t_[i].kind == Token::End) return std::string::npos;
      depth += t_[i].is("(") ? 1 : t_[i].is(")") ? -1 : 0;
      ++i;
    } while (depth > 0);
    return i;
  }
  // Whether the method starting at `void` has rules (`[`) after its parameters.
  bool methodOfRules() const {
    const size_t i = afterParentheses(p_ + 2);
    return i != std::string::npos && t_[i].is("[");
  }
  // A field or a method of Java statements.
  void declaration(bool constant) {
    Declaration d;
    d.constant = constant;
    d.type = p_++;
    if (cur().is("[")) notYet(cur(), "an array");
    d.name = identifier("the name of the field or method");
    if (accept("(")) {
      d.method = true;
      while (!accept(")")) {
        if (!d.params.empty()) expect(",", "between the method's parameters");
        if (cur().kind != Token::Identifier || javaType(cur().text).empty())
          notYet(cur(), "a parameter of type '" + cur().text + "' (lcjit's XL has Java's number and boolean types)");
        size_t type = p_++;
        d.params.push_back({type, identifier("the parameter's name")});
      }
      if (!cur().is("{")) throw XlError{cur(), "expected '{' to begin the method's statements"};
      d.rest = balanced();
      for (size_t i = d.rest.first; i < d.rest.second; ++i)
        if (t_[i].is("==>") || t_[i].is("==>>") || t_[i].is("::>"))
          notYet(t_[i], "a rule in a Java method's statements (lcjit's rules are in a method's rule block, `void run() [ … ]`)");
    } else {
      if (t_[d.type].is("void")) throw XlError{t_[d.type], "a field of type void"};
      size_t from = d.name;
      int depth = 0;
      while (!(depth == 0 && cur().is(";"))) {
        if (cur().kind == Token::End) throw XlError{cur(), "expected ';' at the end of the field"};
        if (cur().is("[") || cur().is("{")) notYet(cur(), "an array");
        if (cur().is("(")) ++depth;
        if (cur().is(")")) --depth;
        ++p_;
      }
      d.rest = {from, p_++};
    }
    declarations_.push_back(std::move(d));
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
      // A graph's bare node (de.grogra.graph.impl.Node): nothing to inherit, nothing drawn.
      if (t_[*m.base].is("Node") && m.baseArgs.empty()) m.base.reset();
    }
    if (cur().is("==>")) notYet(cur(), "an instantiation rule");
    if (cur().is("implements")) notYet(cur(), "'implements'");
    std::vector<Inherited> bodyFields;
    std::optional<Range> shader;
    std::vector<std::pair<size_t, Range>> assigned;  // an initialiser's `field = value;`: (field, value)
    if (cur().is("{")) moduleBody(bodyFields, shader, assigned);
    else expect(";", "at the end of the module declaration");
    const std::string base = m.base ? t_[*m.base].text : "";
    const std::vector<const Field*> baseFields = fieldsOf(base);
    for (Param& param : m.params) {
      const Field* inherited = nullptr;
      for (const Field* f : baseFields)
        if (f->name == param.name) inherited = f;
      if (param.inherited && inherited) param.type = inherited->type;
      if (param.inherited && !inherited)
        throw XlError{t_[param.at], "'super." + param.name + "': the module does not extend a turtle command with a field '" +
                                        param.name + "'"};
    }
    // The base's fields the module does not declare, set from its `extends` arguments.
    for (size_t k = 0; k < baseFields.size(); ++k) {
      const Field& f = *baseFields[k];
      bool declared = false, hidden = false;
      for (const Param& param : m.params) {
        declared = declared || (param.inherited && param.name == f.name);
        hidden = hidden || (!param.inherited && param.name == f.name);
      }
      if (declared) continue;
      // A parameter of the base field's name is a field of its own, which hides the base's (as
      // Java's do): `module Leaf(float length) extends Parallelogram(length, …)`.
      Inherited field{(hidden ? "__xl_super_" : "") + std::string(f.name), std::string(f.type), {}, std::string(f.fallback),
                      std::string(f.name)};
      if (k < m.baseArgs.size())
        for (size_t i = m.baseArgs[k].first; i < m.baseArgs[k].second; ++i) field.value.push_back(i);
      m.inherited.push_back(std::move(field));
    }
    if (!baseFields.empty() && m.baseArgs.size() > baseFields.size())
      throw XlError{t_[m.baseArgs[baseFields.size()].first],
                    base + " takes at most " + std::to_string(baseFields.size()) + " arguments"};
    // setShader(X) in its body: its colour (F's `color`, a solid's `shader`).
    if (shader) {
      Inherited* colour = nullptr;
      for (Inherited& f : m.inherited)
        if (f.field == "color" || f.field == "shader") colour = &f;
      if (!colour) notYet(t_[shader->first], "setShader on a module extending other than F, Sphere or GroIMP's solids");
      colour->value.clear();
      for (size_t i = shader->first; i < shader->second; ++i) colour->value.push_back(i);
    }
    for (Inherited& f : bodyFields) {  // after the base's, so a body's field may not hide one
      if (m.fieldIndex(f.name) != m.fieldCount()) throw XlError{t_[f.value.empty() ? m.name : f.value.front()], "a second field '" + f.name + "'"};
      m.inherited.push_back(std::move(f));
    }
    for (const auto& [at, value] : assigned) {
      Inherited* field = nullptr;
      for (Inherited& f : m.inherited)
        if (f.name == t_[at].text) field = &f;
      if (!field) notYet(t_[at], "an initialiser setting other than a field of the module's body or an inherited one");
      field->value.clear();
      for (size_t i = value.first; i < value.second; ++i) field->value.push_back(i);
    }
    for (const Module& other : modules_)
      if (t_[other.name].text == t_[m.name].text) throw XlError{t_[m.name], "a second module '" + t_[m.name].text + "'"};
    // lcjit's own modules (lpfg's) keep their names in the L+C: a model's module of such a name
    // (the quick reference's G) is XL_NAME there, and in lcjit's string.
    static const std::set<std::string> predefined = {
#define LCJIT_MODULE(Name, ...) #Name,
#include "runtime/include/lcjit/stdmods.def"
#undef LCJIT_MODULE
    };
    m.lcName = predefined.count(t_[m.name].text) ? "XL_" + t_[m.name].text : t_[m.name].text;
    modules_.push_back(std::move(m));
  }

  // A module's body `{ … }`: fields (`float z;`, `int n = 2;`: each a field of the module, as
  // its parameters are, Java's 0 or its initial value when it is made) and instance initialisers
  // `{ setShader(GREEN); }` (its colour). p_ after the body.
  void moduleBody(std::vector<Inherited>& fields, std::optional<Range>& shader,
                  std::vector<std::pair<size_t, Range>>& assigned) {
    expect("{", "to begin the module's body");
    while (!accept("}")) {
      if (cur().kind == Token::End) throw XlError{cur(), "expected '}' at the end of the module's body"};
      if (cur().is("{")) {
        Range init = balanced();
        size_t i = init.first + 1;
        while (i + 1 < init.second) {
          if (t_[i].is(";")) {
            ++i;
            continue;
          }
          // `field = value;`: the field's value when a node is made.
          if (t_[i].kind == Token::Identifier && t_[i + 1].is("=")) {
            size_t end = i + 2;
            while (end + 1 < init.second && !t_[end].is(";")) ++end;
            assigned.push_back({i, Range{i + 2, end}});
            i = end;
            continue;
          }
          if (!(t_[i].is("setShader") && t_[i + 1].is("(")))
            notYet(t_[i], "a statement in a module's initialiser other than setShader(…) or `field = value;`");
          size_t close = afterParentheses(i + 1);
          shader = Range{i + 2, close - 1};
          i = close;
        }
        continue;
      }
      while (cur().is("public") || cur().is("protected") || cur().is("private") || cur().is("final")) ++p_;
      size_t type = identifier("a field's type");
      const std::string cppType = javaType(t_[type].text);
      size_t name = identifier("the field's name");
      if (cur().is("(")) notYet(t_[name], "a method of a module");
      if (cppType.empty()) notYet(t_[type], "a field of type '" + t_[type].text + "'");
      Inherited f{t_[name].text, cppType, {}, cppType == "bool" ? "false" : "0"};
      if (accept("="))
        while (!cur().is(";")) {
          if (cur().kind == Token::End) throw XlError{cur(), "expected ';' at the end of the field"};
          f.value.push_back(p_++);
        }
      expect(";", "at the end of the field");
      fields.push_back(std::move(f));
    }
    accept(";");
  }

  Rule rule() {
    Rule r;
    // Contexts written apart: `(* b:Baum *),` — a node anywhere in the graph, which the rule
    // reads and does not rewrite.
    while (cur().is("(*")) {
      const size_t open = p_++;
      Node n = patternNode("a module in the context");
      if (!cur().is("*)")) notYet(cur(), "a context of more than one node (`(* A B *)`)");
      ++p_;
      if (!accept(","))
        notYet(t_[open], "a context joined to the rule's nodes (`(* A *) B`: lcjit runs contexts written apart, `(* A *), B`)");
      r.contexts.push_back(n);
    }
    if (cur().is("{")) notYet(cur(), "a block of Java statements among the rules");
    // The left side: nodes, each perhaps labelled, up to the condition or the arrow.
    do {
      r.left.push_back(patternNode(r.left.empty() ? "a rule (`A ==> B;`)" : "a module of the rule's left side"));
    } while (cur().kind == Token::Identifier);
    if (cur().is("[")) notYet(cur(), "a branch on a rule's left side");
    if (accept(",")) {
      if (!cur().is("(")) throw XlError{cur(), "expected '(' to begin the rule's condition"};
      r.condition = balanced();
    }
    if (!cur().is("==>") && !cur().is("==>>") && !cur().is("::>"))
      throw XlError{cur(), "expected '==>' after the rule's left side"};
    r.arrow = p_++;
    // `a:A ::> a[x] :+= 1;`: an update's one statement without braces.
    if (r.is(t_, "::>") && !cur().is("{")) {
      Node n;
      n.kind = Node::Block;
      n.name = p_;
      while (!cur().is(";")) {
        if (cur().kind == Token::End) throw XlError{cur(), "expected ';' at the end of the rule"};
        ++p_;
      }
      n.block = {r.arrow, p_ + 1};  // as a block's: the `;` stands for its `}`
      r.right.push_back(n);
      r.end = p_++;
      return r;
    }
    int depth = 0;
    std::vector<int> groups;  // the open groups of for and if, each with the depth of [ it began at
    while (!(cur().is(";") && groups.empty())) {
      Node n;
      if (cur().kind == Token::End || (cur().is("]") && depth == 0)) throw XlError{cur(), "expected ';' at the end of the rule"};
      if ((cur().is("for") || cur().is("if")) && t_[p_ + 1].is("(")) {
        n.kind = cur().is("for") ? Node::For : Node::If;
        n.name = p_++;
        n.block = balanced();
        r.right.push_back(n);
        openGroup(r, groups, depth);
        continue;
      }
      if (cur().is(")") && !groups.empty()) {
        if (depth != groups.back()) throw XlError{cur(), "expected ']' before the end of this group"};
        groups.pop_back();
        n.kind = Node::Close;
        n.name = p_++;
        r.right.push_back(n);
        if (cur().is("else")) {
          n.kind = Node::Else;
          n.name = p_++;
          r.right.push_back(n);
          openGroup(r, groups, depth);
        }
        continue;
      }
      if (cur().is("[") || cur().is("]")) {
        depth += cur().is("[") ? 1 : -1;
        n.kind = Node::Bracket;
        n.name = p_++;
      } else if (cur().kind == Token::Identifier) {
        n.name = p_++;
        if (cur().is("(")) n.parens = true, n.args = arguments();
        // `X(…).(setShader(RED))`: statements run on the new node; setShader, its colour.
        if (cur().is(".") && t_[p_ + 1].is("(")) {
          ++p_;
          Range calls = balanced();
          if (!(t_[calls.first + 1].is("setShader") && t_[calls.first + 2].is("(") &&
                afterParentheses(calls.first + 2) == calls.second - 1))
            notYet(t_[calls.first + 1], "a statement on a new node other than `.(setShader(…))`");
          n.shader = Range{calls.first + 3, calls.second - 2};
        }
      } else if (cur().is("{")) {
        n.kind = Node::Block;
        n.name = p_;
        n.block = balanced();
        r.right.push_back(n);
        // A block may end a rule without `;` (the quick reference writes `… { t[length] *= 1.1 }`).
        if (depth == 0 && groups.empty() && (cur().is("]") || ruleStarts())) {
          r.end = n.block.second - 1;
          return r;
        }
        continue;
      } else if (cur().is(".") && t_[p_ + 1].is("(")) {
        throw XlError{cur(), "`.(…)` follows the node it acts on (`Sphere(1).(setShader(RED))`)"};
      } else {
        throw XlError{cur(), "expected a module, '[', ']', '{', for or if on the rule's right side"};
      }
      r.right.push_back(n);
    }
    if (depth > 0) throw XlError{cur(), "expected ']' before the end of the rule"};
    r.end = p_++;
    return r;
  }
  // The `(` of a for's, an if's or an else's group on a right side.
  void openGroup(Rule& r, std::vector<int>& groups, int depth) {
    if (!cur().is("(")) throw XlError{cur(), "expected '(' to begin the nodes of this " + t_[r.right.back().name].text};
    Node open;
    open.kind = Node::Open;
    open.name = p_++;
    r.right.push_back(open);
    groups.push_back(depth);
  }
  // A node of a pattern: `[label:]Module[(names)]`.
  Node patternNode(const std::string& what) {
    Node n;
    if (cur().kind == Token::Identifier && t_[p_ + 1].is(":")) {
      n.label = p_;
      p_ += 2;
    }
    n.name = identifier(what);
    if (cur().is("(")) {
      n.parens = true;
      n.args = arguments();
      for (Range a : n.args)
        if (a.second != a.first + 1 || t_[a.first].kind != Token::Identifier)
          notYet(t_[a.first], "a pattern's argument other than a name");
    }
    return n;
  }
  // Whether a rule's left side starts here: `[a:]A[(…)]` and more of them, then `,`, or an arrow.
  bool ruleStarts() const {
    size_t i = p_;
    if (t_[i].is("(*")) return true;
    bool any = false;
    while (t_[i].kind == Token::Identifier) {
      any = true;
      if (t_[i + 1].is(":")) i += 2;
      if (t_[i].kind != Token::Identifier) return false;
      ++i;
      if (t_[i].is("(") && (i = afterParentheses(i)) == std::string::npos) return false;
    }
    return any && (t_[i].is(",") || t_[i].is("==>") || t_[i].is("==>>") || t_[i].is("::>"));
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
      if (arity == 0 && d.name == name)
        *defaultArgument = d.argument, arity = 1 + (int)std::count(d.argument.begin(), d.argument.end(), ',');
    bool known = false;
    for (const TurtleCommand& c : kTurtleCommands) {
      known = known || c.name == name;
      if (c.name == name && c.arity == arity) return &c;
    }
    if (known) throw XlError{t_[at], "GroIMP's " + name + " with " + std::to_string(arity) + " arguments is not supported yet"};
    return nullptr;
  }
  const TurtleCommand* turtleOrError(const Node& n, std::string_view* defaultArgument) {
    const TurtleCommand* c = turtle(n.name, (int)n.args.size(), defaultArgument);
    if (!c)
      throw XlError{t_[n.name], "no module '" + t_[n.name].text + "': declare it (`module " + t_[n.name].text +
                                    ";`); of GroIMP's turtle commands lcjit has " + turtleNames()};
    used_.insert(c);
    return c;
  }
  void checkCount(const Node& n, const Module& m, bool left) {
    const int arity = (int)n.args.size(), params = (int)m.params.size();
    if (n.parens && arity != params)
      throw XlError{t_[n.name], "'" + t_[n.name].text + "' has " + std::to_string(params) + " parameter" +
                                    (params == 1 ? "" : "s") + ", given " + std::to_string(arity)};
    if (!n.parens && params > 0 && !left)
      throw XlError{t_[n.name], "'" + t_[n.name].text + "' needs its " + std::to_string(params) + " argument" +
                                    (params == 1 ? "" : "s")};
  }

  // -- a rule's labels: each a copy of its node's fields (a C++ struct of the same names) --
  struct Label {
    const Module* module;
    std::vector<std::string> bound;  // the pattern's names of its fields
  };
  std::map<std::string, Label> labels_;
  const Label* label(size_t at) const {
    auto it = labels_.find(t_[at].text);
    return t_[at].kind == Token::Identifier && it != labels_.end() ? &it->second : nullptr;
  }

  // A left side's node as an L+C pattern: the user's names for the parameters it names, names of
  // the translation's for the others (its inherited fields among them).
  void pattern(const Node& n, size_t index) {
    if (const Module* m = userModule(t_[n.name].text)) {
      checkCount(n, *m, true);
      std::vector<std::string> names;
      for (size_t k = 0; k < m->fieldCount(); ++k)
        names.push_back(n.parens && k < n.args.size() ? t_[n.args[k].first].text
                                                      : "__xl_" + std::to_string(index) + "_" + std::to_string(k));
      if (n.label) labels_[t_[*n.label].text] = Label{m, names};
      writtenCall(n, m->lcName, std::vector<std::string>(names.begin() + long(n.args.size()), names.end()));
      return;
    }
    if (n.label) notYet(t_[*n.label], "a label on one of GroIMP's turtle commands");
    std::string_view defaultArgument;
    const TurtleCommand* c = turtleOrError(n, &defaultArgument);
    // `F` without parentheses: every F, whatever its length (a class pattern, as in GroIMP).
    std::vector<std::string> unnamed;
    if (!defaultArgument.empty())
      for (size_t k = 0; k <= (size_t)std::count(defaultArgument.begin(), defaultArgument.end(), ','); ++k)
        unnamed.push_back("__xl_" + std::to_string(index) + "_" + std::to_string(k));
    writtenCall(n, std::string(c->module), unnamed);
  }
  // Module `name` with the node's arguments written where the user wrote them (the compiler's
  // errors name them there), then `more`.
  void writtenCall(const Node& n, const std::string& name, const std::vector<std::string>& more) {
    w_.at(n.name, name);
    if (n.args.empty()) {
      if (!more.empty()) w_.add("(" + joined(more) + ")");
      return;
    }
    w_.token(n.args.front().first - 1);  // (
    for (size_t i = 0; i < n.args.size(); ++i) {
      if (i) w_.token(n.args[i].first - 1);  // ,
      java(n.args[i]);
    }
    for (const std::string& m : more) w_.add(", " + m);
    w_.token(n.args.back().second);  // )
  }
  // The copies of the labelled nodes' fields, made first in the production.
  void labelCopies() {
    for (const auto& [name, l] : labels_) {
      std::string decl = "struct {";
      std::string values;
      for (size_t k = 0; k < l.module->fieldCount(); ++k) {
        decl += " " + l.module->fieldType(k) + " " + l.module->fieldName(k) + ";";
        values += (k ? ", " : "") + l.bound[k];
      }
      w_.add(decl + " } " + name + " = {" + values + "};");
    }
  }

  // Java in a condition, an argument or a block, as C++: a label's field `t[length]` is `t.length`,
  // Java's Math is C++'s, `boolean` is bool.
  void java(Range r) {
    for (size_t i = r.first; i < r.second; ++i) {
      const Token& t = t_[i];
      if (size_t end = query(i, r); end != i) {
        i = end - 1;
        continue;
      }
      if (const Label* l = label(i)) {
        const bool bracketed = i + 3 < r.second && t_[i + 1].is("[") && t_[i + 3].is("]");
        const bool dotted = i + 2 < r.second && t_[i + 1].is(".");
        if (bracketed || dotted) {
          const std::string& field = t_[i + 2].text;
          if (dotted && i + 3 < r.second && t_[i + 3].is("("))
            notYet(t_[i + 2], "a method of a node (`" + t.text + "." + field + "(…)`)");
          if (l->module->fieldIndex(field) == l->module->fieldCount())
            throw XlError{t_[i + 2], "'" + t.text + "' (a " + t_[l->module->name].text + ") has no field '" + field + "'"};
          w_.token(i);
          w_.at(i + 1, ".");
          w_.token(i + 2);
          i += bracketed ? 3 : 2;
          continue;
        }
      }
      if (t.is("Math") && i + 2 < r.second && t_[i + 1].is(".")) {
        std::string cpp = javaMath(t_[i + 2].text);
        if (cpp.empty()) notYet(t_[i + 2], "Java's Math." + t_[i + 2].text);
        w_.at(i, cpp);
        i += 2;
        continue;
      }
      if (t.is("boolean")) {
        w_.at(i, "bool");
        continue;
      }
      // XL's deferred assignments (`x[f] := v`, `:+=` …) take effect after the step: a rule's
      // changes to a label's fields do so in lcjit anyway (the node takes them at the end).
      if (t.is(":") && i + 1 < r.second &&
          (t_[i + 1].is("=") || t_[i + 1].is("+=") || t_[i + 1].is("-=") || t_[i + 1].is("*=") || t_[i + 1].is("/=")))
        continue;
      // Java's `"…" + x` makes a string; C++'s would move a pointer: refused, not miscompiled.
      if (t.is("+") && ((i > r.first && t_[i - 1].kind == Token::String) || (i + 1 < r.second && t_[i + 1].kind == Token::String)))
        notYet(t, "a string made with + (`\"…\" + x`)");
      w_.token(i);
    }
  }
  // XL's aggregate graph queries over the whole graph, `count((* M *))`, `empty((* M *))`,
  // `sum((* M *)[field])` and `mean`, `max`, `min` likewise (de.grogra.rgg.Library), M a module of
  // the model: the string as the step found it, through InString (lcjit's, the rewriter's),
  // whose condition is made false to go through every M. Inside a rule only (InString is the
  // rewriter's, in production bodies). Returns the token after the query, or `i` for none.
  size_t query(size_t i, Range r) {
    static const std::set<std::string> kAggregates = {"count", "empty", "sum", "mean", "max", "min"};
    if (t_[i].kind != Token::Identifier || !kAggregates.count(t_[i].text) || i + 5 >= r.second || !t_[i + 1].is("(") ||
        !t_[i + 2].is("(*"))
      return i;
    const std::string& f = t_[i].text;
    if (!inRule_) notYet(t_[i], "a graph query (`" + f + "((* … *))`) outside a rule");
    const Module* m = t_[i + 3].kind == Token::Identifier ? userModule(t_[i + 3].text) : nullptr;
    if (!m) notYet(t_[i + 3], "a query of other than one of the model's modules (`(* M *)`)");
    if (!t_[i + 4].is("*)")) notYet(t_[i + 4], "a query of more than one module");
    size_t at = i + 5, field = m->fieldCount();
    if (t_[at].is("[")) {
      if (at + 2 >= r.second || !t_[at + 2].is("]")) throw XlError{t_[at], "expected '[FIELD]' after the query"};
      field = m->fieldIndex(t_[at + 1].text);
      if (field == m->fieldCount())
        throw XlError{t_[at + 1], "a " + t_[m->name].text + " has no field '" + t_[at + 1].text + "'"};
      at += 3;
    }
    if (!t_[at].is(")")) throw XlError{t_[at], "expected ')' to close " + f + "()"};
    const bool counts = f == "count" || f == "empty";
    if (counts != (field == m->fieldCount()))
      throw XlError{t_[i], counts ? f + "() counts nodes: no field" : f + "() needs a field: `" + f + "((* M *)[field])`"};
    const std::string q = "__xl_q" + std::to_string(temps_++);
    std::string decls, vars;
    for (size_t k = 0; k < m->fieldCount(); ++k) {
      decls += m->fieldType(k) + " " + q + "_" + std::to_string(k) + " = 0; ";
      vars += (k ? ", " : "") + q + "_" + std::to_string(k);
    }
    const std::string found = "InString(" + m->lcName + (vars.empty() ? "" : "(" + vars + ")") + ", ";
    const std::string value = field < m->fieldCount() ? q + "_" + std::to_string(field) : "";
    std::string e;
    if (f == "count") e = "int " + q + " = 0; " + found + "(++" + q + ", false)); " + q + ";";
    if (f == "empty") e = "bool " + q + " = !" + found + "true); " + q + ";";
    if (f == "sum") e = "double " + q + " = 0; " + found + "(" + q + " += " + value + ", false)); " + q + ";";
    if (f == "mean")
      e = "double " + q + " = 0; int " + q + "n = 0; " + found + "(" + q + " += " + value + ", ++" + q + "n, false)); " + q +
          "n ? " + q + " / " + q + "n : 0.0;";
    if (f == "max" || f == "min")
      e = "double " + q + " = " + (f == "max" ? "-" : "") + "HUGE_VAL; " + found + "(" + q + " = std::f" + f + "(" + q + ", " +
          value + "), false)); " + q + ";";
    w_.at(i, "({ " + decls + e + " })");
    return at + 1;
  }
  bool inRule_ = false;  // writing a production (java(): graph queries)

  // A block of Java statements: the last one's `;` may be missing before `}`.
  // A block of a right side, without its braces: what it declares is seen by the rest of the
  // right side, as in XL (`{ double r = 50 - i * 5; } Leaf(r, r * 0.5)`).
  void block(const Node& n) {
    const size_t close = n.block.second - 1;
    w_.at(n.block.first, " ");
    java({n.block.first + 1, close});
    if (close > n.block.first + 1 && !t_[close - 1].is(";") && !t_[close - 1].is("}")) w_.add(";");
  }

  // -- a right side: its arguments computed in order, with its blocks, then produced --
  std::vector<std::string> argumentNames_;  // by right-side node and argument, in order
  size_t temps_ = 0;
  // Each argument of a made node, as a local computed where it is written (blocks after it do not
  // change it, as in XL), then the blocks.
  void rightStatements(const std::vector<Node>& right) {
    argumentNames_.clear();
    for (const Node& n : right) {
      if (n.kind == Node::Block) {
        block(n);
        continue;
      }
      if (n.kind != Node::Module || label(n.name)) continue;
      for (Range a : n.args) {
        std::string name = "__xl_a" + std::to_string(temps_++);
        w_.add("const auto " + name + " = (");
        java(a);
        w_.add(");");
        argumentNames_.push_back(name);
      }
    }
  }
  // The right side's modules (after rightStatements: `arguments` are its locals; in the axiom,
  // the arguments as written).
  void rightModules(const std::vector<Node>& right, bool axiom) {
    size_t next = 0;
    for (const Node& n : right) {
      if (n.kind == Node::Bracket) {
        w_.at(n.name, t_[n.name].is("[") ? "SB" : "EB");  // L+C's names of XL's [ ]
        continue;
      }
      if (n.kind == Node::Block) continue;
      // In a rule, each argument is its local (rightStatements); in the axiom, as written.
      std::vector<std::string> given;
      if (!(!axiom && label(n.name)))
        for (Range a : n.args) given.push_back(axiom ? "(" + text(a) + ")" : argumentNames_[next++]);
      madeNode(n, given, axiom);
    }
  }
  // Node `n` of a right side, made with the arguments `given`: a label's node as its copy left
  // it, or the module with its inherited fields after `given`.
  void madeNode(const Node& n, std::vector<std::string> given, bool axiom) {
    if (const Label* l = axiom ? nullptr : label(n.name)) {
      if (n.parens) throw XlError{t_[n.name], "'" + t_[n.name].text + "' names a node of the left side: no arguments"};
      w_.at(n.name, fromLabel(t_[n.name].text, *l->module));
      return;
    }
    std::string name;
    std::vector<std::string> more;
    if (const Module* m = userModule(t_[n.name].text)) {
      checkCount(n, *m, false);
      name = m->lcName;
      for (const Inherited& f : m->inherited)
        more.push_back(n.shader && (f.field == "color" || f.field == "shader") ? "(" + text(*n.shader) + ")"
                                                                             : inheritedValue(*m, f, given));
      if (n.shader && m->baseField("color").empty() && m->baseField("shader").empty())
        notYet(t_[n.shader->first], "setShader on a module extending other than F, Sphere or GroIMP's solids");
    } else {
      if (n.shader) notYet(t_[n.shader->first], "setShader on one of GroIMP's turtle commands (lcjit: on a module extending it)");
      std::string_view defaultArgument;
      name = turtleOrError(n, &defaultArgument)->module;
      if (!defaultArgument.empty()) more.push_back(std::string(defaultArgument));
    }
    if (axiom) {
      writtenCall(n, name, more);
    } else {
      given.insert(given.end(), more.begin(), more.end());
      w_.at(n.name, name + (given.empty() ? "" : "(" + joined(given) + ")"));
    }
  }
  static bool hasBlock(const std::vector<Node>& right) {
    for (const Node& n : right)
      if (n.kind == Node::Block) return true;
    return false;
  }
  static bool hasControl(const std::vector<Node>& right) {
    for (const Node& n : right)
      if (n.control()) return true;
    return false;
  }
  // A right side with for or if, made node by node where it stands (L+C's nproduce): each node's
  // arguments computed, then the node; blocks run in place; for and if as C++'s. The caller ends
  // it with `produce ;`. A label's node is made where it stands, so no block may come after it.
  void stepwise(const std::vector<Node>& right) {
    bool labelled = false;
    for (const Node& n : right) {
      switch (n.kind) {
        case Node::Bracket: w_.at(n.name, t_[n.name].is("[") ? "nproduce SB;" : "nproduce EB;"); break;
        case Node::Block:
          if (labelled) notYet(t_[n.name], "a block after a label's node on a right side with for or if");
          block(n);
          break;
        case Node::For: forHeader(n); break;
        case Node::If:
          w_.at(n.name, "if (");
          java({n.block.first + 1, n.block.second - 1});
          w_.add(")");
          break;
        case Node::Else: w_.at(n.name, "else"); break;
        case Node::Open: w_.at(n.name, "{"); break;
        case Node::Close: w_.at(n.name, "}"); break;
        case Node::Module: {
          if (label(n.name)) {
            labelled = true;
            w_.add("nproduce");
            madeNode(n, {}, false);
            w_.add(";");
            break;
          }
          w_.add("{");
          std::vector<std::string> given;
          for (Range a : n.args) {
            given.push_back("__xl_a" + std::to_string(temps_++));
            w_.add("const auto " + given.back() + " = (");
            java(a);
            w_.add(");");
          }
          w_.add("nproduce");
          madeNode(n, given, false);
          w_.add("; }");
          break;
        }
      }
    }
  }
  // XL's for on a right side: `for ((a : b))` runs for a, a + 1 … b; `for (int i : a : b)` (or
  // `: (a : b)`) with i each of them; Java's `for (init; condition; update)` as written.
  void forHeader(const Node& n) {
    const Range inner{n.block.first + 1, n.block.second - 1};
    bool classic = false;
    for (size_t i = inner.first; i < inner.second; ++i) classic = classic || t_[i].is(";");
    if (classic) {
      w_.at(n.name, "for (");
      java(inner);
      w_.add(")");
      return;
    }
    std::string var;
    Range range = inner;
    if (inner.second - inner.first > 3 && t_[inner.first].kind == Token::Identifier &&
        t_[inner.first + 1].kind == Token::Identifier && t_[inner.first + 2].is(":")) {
      const std::string type = javaType(t_[inner.first].text);
      if (type.empty()) notYet(t_[inner.first], "a for over values of type '" + t_[inner.first].text + "'");
      var = t_[inner.first + 1].text;
      w_.at(n.name, "for (" + type + " " + var + " = (");
      range = {inner.first + 3, inner.second};
    } else {
      var = "__xl_i" + std::to_string(temps_++);
      w_.at(n.name, "for (long long " + var + " = (");
    }
    // `(a : b)` or `a : b`: the `:` outside any parentheses.
    if (t_[range.first].is("(") && afterParentheses(range.first) == range.second) range = {range.first + 1, range.second - 1};
    size_t colon = range.second;
    int depth = 0;
    for (size_t i = range.first; i < range.second && colon == range.second; ++i) {
      depth += nesting(t_[i]);
      if (depth == 0 && t_[i].is(":")) colon = i;
    }
    if (colon == range.second) notYet(t_[range.first], "this for on a right side (lcjit's: `for ((a : b))`, `for (int i : a : b)`, Java's)");
    java({range.first, colon});
    w_.add("); " + var + " <= (");
    java({colon + 1, range.second});
    w_.add("); ++" + var + ")");
  }
  // An inherited field's value for a module made with the arguments `given`: its `extends`
  // argument with the module's parameters replaced by them.
  std::string inheritedValue(const Module& m, const Inherited& f, const std::vector<std::string>& given) const {
    if (f.value.empty()) return f.fallback;
    std::string s = "(";
    for (size_t i : f.value) {
      std::string piece = LcWriter::spelled(t_[i]);
      for (size_t k = 0; k < m.params.size(); ++k)
        if (t_[i].kind == Token::Identifier && t_[i].text == m.params[k].name && k < given.size()) piece = given[k];
      s += (s.size() > 1 ? " " : "") + piece;
    }
    return s + ")";
  }
  // The node a label names, as its fields' copy left it: `T(t.alter, t.length, …)`.
  static std::string fromLabel(const std::string& label, const Module& m) {
    std::vector<std::string> fields;
    for (size_t k = 0; k < m.fieldCount(); ++k) fields.push_back(label + "." + m.fieldName(k));
    return m.lcName + (fields.empty() ? "" : "(" + joined(fields) + ")");
  }
  static std::string joined(const std::vector<std::string>& items) {
    std::string s;
    for (size_t k = 0; k < items.size(); ++k) s += (k ? ", " : "") + items[k];
    return s;
  }
  std::string text(Range r) const {
    std::string s;
    for (size_t i = r.first; i < r.second; ++i) s += (i > r.first ? " " : "") + LcWriter::spelled(t_[i]);
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

  // -- a rule as an L+C production --
  static size_t rewrittenNode(const Rule& r, const std::vector<Token>& t) {
    return r.is(t, "==>>") && r.left.size() == 3 ? 1 : 0;
  }
  // The model's modules a rule's pattern also matches: those extending the turtle command it
  // names (a GroIMP pattern F(x) matches every node whose class is F or extends it), its node
  // unlabelled and given its parameters.
  std::vector<const Module*> subclassesMatched(const Rule& r) const {
    std::vector<const Module*> found;
    if (r.is(t_, "::>")) return found;
    const Node& n = r.left[rewrittenNode(r, t_)];
    if (n.label || userModule(t_[n.name].text) || n.args.empty()) return found;
    for (const Module& m : modules_)
      if (m.base && t_[*m.base].text == t_[n.name].text) found.push_back(&m);
    return found;
  }
  // A subclass's pattern for a turtle command's (subclassesMatched): its fields, each of the
  // command's fields the pattern names taking the pattern's name.
  void subclassPattern(const Node& n, const Module& m, size_t index) {
    const std::vector<const Field*> commandFields = fieldsOf(t_[n.name].text);
    if (n.args.size() > commandFields.size()) notYet(t_[n.name], "this pattern of " + t_[n.name].text + " matching its subclasses");
    std::vector<std::string> names;
    for (size_t f = 0; f < m.fieldCount(); ++f) names.push_back("__xl_" + std::to_string(index) + "_" + std::to_string(f));
    for (size_t k = 0; k < n.args.size(); ++k)
      if (size_t f = m.fieldIndex(m.baseField(std::string(commandFields[k]->name))); f < m.fieldCount())
        names[f] = t_[n.args[k].first].text;
    w_.at(n.name, m.lcName + (names.empty() ? "" : "(" + joined(names) + ")"));
  }

  // The production of rule `r`; with `subclass`, the same rule for a module extending the turtle
  // command its pattern names.
  void production(const Rule& r, const Module* subclass = nullptr) {
    labels_.clear();
    inRule_ = true;
    std::vector<Node> right = r.right;
    if (r.is(t_, "==>>")) right = spoRight(r);
    const size_t node = rewrittenNode(r, t_);
    if (r.left.size() > 1 && !r.is(t_, "==>>")) notYet(t_[r.left[1].name], "a rule of more than one node on its left side");
    for (size_t k = 0; k < r.left.size(); ++k) {
      if (k == 1 && node == 1) w_.add("<");
      if (subclass && k == node) subclassPattern(r.left[k], *subclass, k);
      else pattern(r.left[k], k);
      if (k == 1 && node == 1) w_.add(">");
    }
    w_.add(":");
    w_.add("{");
    // Each context's fields, found by InString (lcjit's, the rewriter's): variables, and the
    // label's copy of them.
    std::vector<std::vector<std::string>> contextVars;
    for (size_t k = 0; k < r.contexts.size(); ++k) {
      const Node& n = r.contexts[k];
      const Module* m = userModule(t_[n.name].text);
      if (!m) notYet(t_[n.name], "a context of one of GroIMP's turtle commands");
      checkCount(n, *m, true);
      std::vector<std::string> vars;
      for (size_t f = 0; f < m->fieldCount(); ++f) {
        vars.push_back(n.parens && f < n.args.size() ? t_[n.args[f].first].text
                                                     : "__xl_c" + std::to_string(k) + "_" + std::to_string(f));
        w_.add(m->fieldType(f) + " " + vars.back() + " = 0;");
      }
      if (n.label) labels_[t_[*n.label].text] = Label{m, vars};
      contextVars.push_back(vars);
    }
    labelCopies();
    if (r.condition || !r.contexts.empty()) {
      w_.add("if (");
      for (size_t k = 0; k < r.contexts.size(); ++k) {
        const Node& n = r.contexts[k];
        const Module& m = *userModule(t_[n.name].text);
        std::string s = "InString(" + m.lcName + (contextVars[k].empty() ? "" : "(" + joined(contextVars[k]) + ")") + ", (";
        if (n.label)
          for (size_t f = 0; f < m.fieldCount(); ++f) s += t_[*n.label].text + "." + m.fieldName(f) + " = " + contextVars[k][f] + ", ";
        w_.add(s);
      }
      if (r.condition) java(*r.condition);
      else w_.add("true");
      for (size_t k = 0; k < r.contexts.size(); ++k) w_.add("))");
      w_.add(")");
    }
    w_.add("{");
    if (r.is(t_, "::>")) {
      // An update: the node's fields changed by the blocks, the node itself kept.
      for (const Node& n : right)
        if (n.kind != Node::Block) throw XlError{t_[n.name], "an update rule (`::>`) has blocks `{ … }` on its right side, no nodes"};
      rightStatements(right);
      const Node& kept = r.left.front();
      if (!userModule(t_[kept.name].text) || !kept.label)
        notYet(t_[kept.name], "an update rule other than `c:C ::> { … }` (C a module of the model)");
      w_.at(r.end, "produce " + fromLabel(t_[*kept.label].text, *userModule(t_[kept.name].text)) + ";");
    } else if (hasControl(right)) {
      stepwise(right);
      w_.at(r.end, "produce ;");
    } else {
      rightStatements(right);
      if (deletes(r, t_)) w_.add("lcjit_cut_branch();");
      w_.at(r.arrow, "produce");
      rightModules(right, false);
      w_.at(r.end, ";");
    }
    w_.add("}");
    w_.add("}");
    inRule_ = false;
  }
  // An SPO rule's right side, as the production of an L-system. SPO keeps the relations of the
  // nodes both sides name and drops those of the nodes it deletes:
  // - `X ==>> ;` deletes X and what hangs on it (the rest of its branch goes, in this step, by
  //   lcjit_cut_branch()); so does `X ==>> G` (the quick reference's): G, connected to nothing,
  //   is not part of the graph lcjit keeps (GroIMP shows only what hangs on its root);
  // - `x:X ==>> x …` keeps X, its relations with it, and puts … after it, as `==>` would;
  // - `a:A X c:C ==>> a … c` keeps A and C and their relations and puts … between them: X
  //   replaced, with A and C its context.
  // Other SPO rules are refused.
  static bool names(const Node& n, const Node& left, const std::vector<Token>& t) {
    return n.kind == Node::Module && !n.parens && left.label && t[n.name].text == t[*left.label].text;
  }
  static bool deletes(const Rule& r, const std::vector<Token>& t) {
    if (!r.is(t, "==>>") || r.left.size() != 1) return false;
    for (const Node& n : r.right)
      if (names(n, r.left.front(), t) || n.control()) return false;
    return true;
  }
  std::vector<Node> spoRight(const Rule& r) {
    if (deletes(r, t_)) {
      for (const Node& n : r.right)
        if (n.kind == Node::Block) notYet(t_[n.name], "a block in an SPO rule that deletes its node");
      return {};
    }
    if (r.left.size() == 1 && !r.right.empty() && names(r.right.front(), r.left.front(), t_)) {
      for (size_t k = 1; k < r.right.size(); ++k)
        if (names(r.right[k], r.left.front(), t_)) notYet(t_[r.right[k].name], "an SPO rule naming its node twice on its right side");
      return r.right;
    }
    if (r.left.size() == 3 && r.left[0].label && r.left[2].label && r.right.size() >= 2) {
      const Node& first = r.right.front();
      const Node& last = r.right.back();
      auto same = [&](const Node& n, const Node& l) {
        return n.kind == Node::Module && !n.parens && t_[n.name].text == t_[*l.label].text;
      };
      bool blocks = false;
      for (const Node& n : r.right) blocks = blocks || n.kind == Node::Block;
      if (same(first, r.left[0]) && same(last, r.left[2]) && !blocks)
        return std::vector<Node>(r.right.begin() + 1, r.right.end() - 1);
    }
    notYet(t_[r.arrow], "this SPO rule (`==>>`: lcjit runs `X ==>> ;` and `a:A X c:C ==>> a … c;`)");
  }

  std::string write() {
    // The body (axiom, productions, interpretation rules) first: it says which of GroIMP's turtle
    // commands the model uses, declared in the head after the user's modules.
    LcWriter head(t_);
    for (const Module& m : modules_) {
      std::vector<std::string> types;
      for (size_t k = 0; k < m.fieldCount(); ++k) types.push_back(m.fieldType(k));
      head.at(m.keyword, "module " + m.lcName + (types.empty() ? "" : "(" + joined(types) + ")") + ";");
    }
    // XL's library, then the model's fields and methods (each method declared first: Java's may
    // call one written after it).
    // The shaders' names a model does not declare itself (its own `const int YELLOW = 14;` is its).
    std::string shaders;
    for (size_t k = 0; k < std::size(kShaders); ++k) {
      bool declared = false;
      for (const Declaration& d : declarations_) declared = declared || t_[d.name].text == kShaders[k];
      if (!declared) shaders += (shaders.empty() ? "" : ", ") + std::string(kShaders[k]) + " = " + std::to_string(k);
    }
    w_.add("enum : int { " + shaders + " }; " + std::string(kLibrary));
    for (const Declaration& d : declarations_)
      if (d.method) w_.add(signature(d) + ";");
    for (const Declaration& d : declarations_) {
      if (d.method) {
        w_.at(d.type, signature(d));
        java(d.rest);
      } else {
        w_.at(d.type, (d.constant ? "const " : "") + javaType(t_[d.type].text));
        java(d.rest);
        w_.add(";");
      }
    }
    if (axiomIsNode_) {
      w_.at(axiomAt(), "derivation length: 0; axiom: XL_Axiom;");
    } else if (const Rule& axiom = init_->rules.front(); hasControl(axiom.right) || hasBlock(axiom.right)) {
      // An axiom with for, if or Java: its nodes are made by a rule, the decomposition of the
      // node XL_Init, which L+C applies to the axiom before anything else (manual §4.3.1).
      w_.at(axiom.left.front().name, "derivation length: 0; axiom: XL_Init;");
    } else {
      w_.at(axiom.left.front().name, "derivation length: 0;");
      w_.add("axiom:");
      for (const Node& n : axiom.right)
        if (n.kind == Node::Block) notYet(t_[n.name], "a block of Java statements in the axiom");
      rightModules(axiom.right, true);
      w_.at(axiom.end, ";");
    }
    if (step_)
      for (const Rule& r : step_->rules) {
        production(r);
        // Right after it, as XL tries its rules in order: the same rule for the subclasses.
        for (const Module* m : subclassesMatched(r)) production(r, m);
      }
    if (init_ && (hasControl(init_->rules.front().right) || hasBlock(init_->rules.front().right))) {
      const Rule& axiom = init_->rules.front();
      w_.add("decomposition:");
      w_.at(axiom.arrow, "XL_Init : {");
      stepwise(axiom.right);
      w_.at(axiom.end, "produce ; }");
      head.at(axiomAt(), "module XL_Init;");
    }
    std::vector<std::pair<size_t, std::string>> interpretation;  // (at, rule)
    for (const Module& m : modules_) {
      if (!m.base) continue;
      if (userModule(t_[*m.base].text)) notYet(t_[*m.base], "a module extending one of the model's modules");
      const std::string base = t_[*m.base].text;
      // Its pattern, each field by its name.
      std::string rule = m.lcName;
      std::vector<std::string> names;
      for (size_t k = 0; k < m.fieldCount(); ++k) names.push_back(m.fieldName(k));
      if (!names.empty()) rule += "(" + joined(names) + ")";
      std::string body;
      if (base == "F") {
        // GroIMP's F: its own diameter and colour when it has them (≥ 0), else the turtle state's.
        body = drawn(kOwnCylinder, {m.baseField("length"), m.baseField("diameter"), m.baseField("color")});
      } else {
        std::string_view defaultArgument;
        std::vector<std::string> args;
        for (const Field* f : fieldsOf(base))
          if (f->name != "shader") args.push_back(m.baseField(std::string(f->name)));
        const TurtleCommand* c = turtle(*m.base, (int)args.size(), &defaultArgument);
        if (!c) throw XlError{t_[*m.base], "no turtle command '" + base + "' to extend (lcjit has " + turtleNames() + ")"};
        if (c->drawn.empty()) continue;
        body = "produce " + drawn(c->drawn, args) + ";";
        // Its shader (−1: the turtle's colour) for itself alone; what follows starts where it ends.
        if (const std::string shader = m.baseField("shader"); !shader.empty())
          body = "if (" + shader + " < 0) " + body + " else produce SB SetColor(" + shader + " + 2) " + drawn(c->drawn, args) + " EB" +
                 (c->advance.empty() ? "" : " f(" + drawn(c->advance, args) + ")") + ";";
      }
      interpretation.push_back({m.name, rule + " : { " + body + " }"});
    }
    std::string turtleDecls;
    for (const TurtleCommand& c : kTurtleCommands) {
      if (!used_.count(&c) || c.own) continue;
      bool twice = false;  // one declaration per module
      for (const TurtleCommand& d : kTurtleCommands)
        twice = twice || (&d < &c && d.module == c.module && used_.count(&d));
      if (twice) continue;
      turtleDecls += "module " + std::string(c.module) + (c.declared.empty() ? "" : "(" + std::string(c.declared) + ")") + "; ";
      if (c.drawn.empty() && c.body.empty()) continue;
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
      interpretation.push_back({axiomAt(), rule + " : { " +
                                                 (c.body.empty() ? "produce " + drawn(c.drawn, args) + ";" : drawn(c.body, args)) +
                                                 " }"});
    }
    if (!interpretation.empty()) {
      w_.add("interpretation:");
      for (const auto& [at, rule] : interpretation) w_.at(at, rule);
    }
    if (!turtleDecls.empty()) head.at(axiomAt(), turtleDecls);
    return "#include <lpfgall.h>\n" + head.take() + w_.take();
  }

  std::string signature(const Declaration& d) const {
    std::string s = (t_[d.type].is("void") ? std::string("void") : javaType(t_[d.type].text)) + " " + t_[d.name].text + "(";
    for (size_t k = 0; k < d.params.size(); ++k)
      s += (k ? ", " : "") + javaType(t_[d.params[k].first].text) + " " + t_[d.params[k].second].text;
    return s + ")";
  }

  std::vector<Token> t_;
  size_t p_ = 0;
  std::vector<Declaration> declarations_;
  std::vector<Module> modules_;
  std::optional<Method> init_, step_;
  std::vector<Method> methods_;  // the rule methods besides init(), in the model's order
  std::string run_;
  bool axiomIsNode_ = false;  // no init(): the axiom is the node Axiom (axiomNode)
  size_t axiomNameAt_ = 0;
  // Where the axiom is written: init()'s name, or the Axiom the rule rewrites.
  size_t axiomAt() const { return init_ ? init_->name : axiomNameAt_; }
  std::set<const TurtleCommand*> used_;
  LcWriter w_{t_};
};

std::string errorLine(const XlError& e) {
  return e.at.file + ":" + std::to_string(e.at.line) + ":" + std::to_string(e.at.col) + ": error: " + e.message;
}

}  // namespace

std::string_view shownName(std::string_view lcName) {
  if (lcName == "SB") return "[";
  if (lcName == "EB") return "]";
  if (lcName == "F_d" || lcName == "F_dc") return "F";
  if (lcName.substr(0, 3) == "XL_") return lcName.substr(3);
  return lcName;
}

namespace {
// Where the REPL's own C++ begins in its unit (app/session/Session.cpp: a file named <repl> that
// includes the model, then adds declarations and statements in C++): the line marker returning
// into it (GNU flag 2) from the first file it includes (flag 1) other than the preprocessor's
// own (<built-in>, <command line>). npos: a model alone.
size_t replText(const std::string& preprocessed) {
  bool inModel = false;
  for (size_t at = 0; at < preprocessed.size();) {
    size_t end = preprocessed.find('\n', at);
    if (end == std::string::npos) end = preprocessed.size();
    std::string_view line(preprocessed.data() + at, end - at);
    if (line.size() > 2 && line[0] == '#' && line[1] == ' ') {
      const bool enters = line.size() > 2 && line.substr(line.size() - 2) == " 1" && line.find("\"<") == std::string_view::npos;
      if (enters) inModel = true;
      if (inModel && line.find("<repl>\" 2") != std::string_view::npos) return at;
    }
    at = end + 1;
  }
  return std::string::npos;
}
}  // namespace

llvm::Expected<std::string> toLplusC(const std::string& preprocessed, const std::string& mainFile, const std::string& run) {
  try {
    // In the REPL, the model is XL and what the REPL adds after it C++, which the L+C takes as
    // it is.
    const size_t repl = replText(preprocessed);
    if (repl != std::string::npos) {
      Translator translator(tokenize(preprocessed.substr(0, repl), mainFile), run);
      return translator.run() + preprocessed.substr(repl);
    }
    Translator translator(tokenize(preprocessed, mainFile), run);
    return translator.run();
  } catch (const XlError& e) {
    return llvm::createStringError(llvm::inconvertibleErrorCode(), errorLine(e));
  }
}

llvm::Expected<Rewritten> rewrite(const std::string& preprocessed, const std::string& mainFile, const std::string& run) {
  auto lc = toLplusC(preprocessed, mainFile, run);
  if (!lc) return lc.takeError();
  return frontend::rewrite(*lc, mainFile);
}

}  // namespace lcjit::frontend::xl
