// Reading an XL model (Translator.h): its Java declarations, its modules with their fields and
// bodies, its methods of rules, each rule's contexts, left side, condition and right side, as the
// tokens they were written with.
#include "frontend/xl/Translator.h"

namespace lcjit::frontend::xl {

bool Translator::accept(const char* s) {
  if (!cur().is(s)) return false;
  ++p_;
  return true;
}

void Translator::expect(const char* s, const std::string& where) {
  if (!accept(s)) throw XlError{cur(), "expected '" + std::string(s) + "' " + where};
}

size_t Translator::identifier(const std::string& what) {
  if (cur().kind != Token::Identifier) throw XlError{cur(), "expected " + what};
  return p_++;
}

void Translator::notYet(const Token& at, const std::string& what) {
  throw XlError{at, what + " is not supported yet by lcjit's XL (docs/xl.md)"};
}

int Translator::nesting(const Token& t) {
  return t.is("(") || t.is("[") || t.is("{") ? 1 : t.is(")") || t.is("]") || t.is("}") ? -1 : 0;
}

Range Translator::balanced() {
  size_t first = p_;
  int depth = 0;
  do {
    if (cur().kind == Token::End) throw XlError{t_[first], "this '" + t_[first].text + "' is not closed"};
    depth += nesting(cur());
    ++p_;
  } while (depth > 0);
  return {first, p_};
}

std::vector<Range> Translator::arguments() {
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

void Translator::topLevel() {
  if (cur().is("module")) return module();
  // XL's manual writes a model as a Java class, `public class Koch extends RGG { … }`: what it
  // holds is the model.
  const size_t classAt = cur().is("public") ? p_ + 1 : p_;
  if (t_[classAt].is("class") && t_[classAt + 2].is("extends") && t_[classAt + 3].is("RGG") && t_[classAt + 4].is("{")) {
    p_ = classAt + 5;
    ++classes_;
    return;
  }
  if (cur().is("}") && classes_ > 0) {
    ++p_;
    --classes_;
    return;
  }
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
  while (!accept("]")) {
    if (cur().is("{")) m.blocks.push_back(balanced());
    else m.rules.push_back(rule());
  }
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

void Translator::chooseMethod() {
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

void Translator::axiomNode() {
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

size_t Translator::afterParentheses(size_t i) const {
  int depth = 0;
  do {
    if (t_[i].kind == Token::End) return std::string::npos;
    depth += t_[i].is("(") ? 1 : t_[i].is(")") ? -1 : 0;
    ++i;
  } while (depth > 0);
  return i;
}

bool Translator::methodOfRules() const {
  const size_t i = afterParentheses(p_ + 2);
  return i != std::string::npos && t_[i].is("[");
}

void Translator::declaration(bool constant) {
  Declaration d;
  d.constant = constant;
  d.type = p_++;
  while (cur().is("[") && t_[p_ + 1].is("]")) p_ += 2;  // an array's `[]` (javaTypeAt)
  d.name = identifier("the name of the field or method");
  if (accept("(")) {
    methodRest(d);
  } else {
    if (t_[d.type].is("void")) throw XlError{t_[d.type], "a field of type void"};
    size_t from = d.name;
    int depth = 0;
    while (!(depth == 0 && cur().is(";"))) {
      if (cur().kind == Token::End) throw XlError{cur(), "expected ';' at the end of the field"};
      if (nesting(cur()) > 0) ++depth;
      if (nesting(cur()) < 0) --depth;
      ++p_;
    }
    d.rest = {from, p_++};
  }
  declarations_.push_back(std::move(d));
}

void Translator::methodRest(Declaration& d) {
  d.method = true;
  while (!accept(")")) {
    if (!d.params.empty()) expect(",", "between the method's parameters");
    if (cur().kind != Token::Identifier || javaType(cur().text).empty())
      notYet(cur(), "a parameter of type '" + cur().text + "' (lcjit's XL has Java's number and boolean types)");
    size_t type = p_++;
    while (cur().is("[") && t_[p_ + 1].is("]")) p_ += 2;
    d.params.push_back({type, identifier("the parameter's name")});
  }
  if (!cur().is("{")) throw XlError{cur(), "expected '{' to begin the method's statements"};
  d.rest = balanced();
  for (size_t i = d.rest.first; i < d.rest.second; ++i)
    if (t_[i].is("==>") || t_[i].is("==>>") || t_[i].is("::>"))
      notYet(t_[i], "a rule in a Java method's statements (lcjit's rules are in a method's rule block, `void run() [ … ]`)");
}

std::optional<Range> Translator::dotShader(const std::string& on) {
  if (!(cur().is(".") && t_[p_ + 1].is("("))) return std::nullopt;
  ++p_;
  Range calls = balanced();
  if (!(t_[calls.first + 1].is("setShader") && t_[calls.first + 2].is("(") &&
        afterParentheses(calls.first + 2) == calls.second - 1))
    notYet(t_[calls.first + 1], "a statement on " + on + " other than `.(setShader(…))`");
  return Range{calls.first + 3, calls.second - 2};
}

void Translator::module() {
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
  // `extends Cylinder(l, r).(setShader(X))`: each node's colour, as an initialiser's setShader.
  std::optional<Range> shader = dotShader("a module's base");
  if (cur().is("implements")) notYet(cur(), "'implements'");
  std::vector<Inherited> bodyFields;
  std::vector<std::pair<size_t, Range>> assigned;  // an initialiser's `field = value;`: (field, value)
  const bool body = cur().is("{");
  if (body) moduleBody(bodyFields, shader, assigned, m.methods);
  if (cur().is("==>")) {
    // An instantiation rule: what each of its nodes is drawn as (its fields by their names).
    Rule r;
    r.arrow = p_++;
    rightSide(r);
    instantiations_[t_[m.name].text] = std::move(r);
  } else if (!body) {
    expect(";", "at the end of the module declaration");
  }
  const std::string base = m.base ? t_[*m.base].text : "";
  const Module* userBase = m.base ? userModule(base) : nullptr;
  const std::vector<BaseField> baseFields = userBase ? baseFieldsOf(*userBase) : baseFieldsOf(base);
  m.command = userBase ? userBase->command : fieldsOf(base).empty() ? "" : base;
  if (m.base && !userBase && fieldsOf(base).empty()) {
    if (!isTurtleCommand(base))
      throw XlError{t_[*m.base], "no module '" + base + "' to extend: declare it before this one, or extend one of GroIMP's " +
                                     turtleNames()};
    m.command = base;
  }
  for (Param& param : m.params) {
    const BaseField* inherited = nullptr;
    for (const BaseField& f : baseFields)
      if (f.name == param.name) inherited = &f;
    if (param.inherited && inherited) param.type = inherited->type, param.fallback = inherited->fallback;
    if (param.inherited && !inherited)
      throw XlError{t_[param.at], "'super." + param.name + "': " + (base.empty() ? "the module extends nothing" : base + " has no field '" + param.name + "'")};
    if (!param.inherited) param.fallback = param.type == "bool" ? "false" : "0";
  }
  // The base's fields the module does not declare, set from its `extends` arguments.
  for (size_t k = 0; k < baseFields.size(); ++k) {
    const BaseField& f = baseFields[k];
    bool declared = false, hidden = false;
    for (const Param& param : m.params) {
      declared = declared || (param.inherited && param.name == f.name);
      hidden = hidden || (!param.inherited && param.name == f.name);
    }
    if (declared) continue;
    // A parameter of the base field's name is a field of its own, which hides the base's (as
    // Java's do): `module Leaf(float length) extends Parallelogram(length, …)`.
    Inherited field{(hidden ? "__xl_super_" : "") + f.name, f.type, {}, f.fallback, f.field};
    if (k < m.baseArgs.size() && f.parameter)
      for (size_t i = m.baseArgs[k].first; i < m.baseArgs[k].second; ++i) field.value.push_back(i);
    else if (userBase && !f.parameter)
      field.pieces = basePieces(*userBase, userBase->inherited[k - userBase->params.size()], m.baseArgs);
    m.inherited.push_back(std::move(field));
  }
  size_t settable = 0;  // what `extends Base(…)` sets: a turtle command's fields, a module's parameters
  for (const BaseField& f : baseFields) settable += f.parameter ? 1 : 0;
  if (m.base && m.baseArgs.size() > settable)
    throw XlError{t_[m.baseArgs[settable].first], base + " takes at most " + std::to_string(settable) + " arguments"};
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

std::vector<Translator::BaseField> Translator::baseFieldsOf(std::string_view command) {
  std::vector<BaseField> fields;
  for (const Field* f : fieldsOf(command))
    fields.push_back({std::string(f->name), std::string(f->type), std::string(f->fallback), std::string(f->name), true});
  return fields;
}

std::vector<Translator::BaseField> Translator::baseFieldsOf(const Module& base) const {
  std::vector<BaseField> fields;
  for (const Param& p : base.params) fields.push_back({p.name, p.type, p.fallback, p.inherited ? p.name : "", true});
  std::vector<std::string> defaults;
  for (const Param& p : base.params) defaults.push_back(p.fallback);
  for (const Inherited& f : base.inherited) fields.push_back({f.name, f.type, inheritedValue(base, f, defaults), f.field, false});
  return fields;
}

std::vector<std::string> Translator::basePieces(const Module& base, const Inherited& f, const std::vector<Range>& args) const {
  std::vector<std::string> out;
  for (const std::string& piece : valuePieces(f)) {
    size_t k = 0;
    while (k < base.params.size() && base.params[k].name != piece) ++k;
    if (k == base.params.size()) {
      out.push_back(piece);
    } else if (k < args.size()) {
      out.push_back("(");
      for (size_t i = args[k].first; i < args[k].second; ++i) out.push_back(LcWriter::spelled(t_[i]));
      out.push_back(")");
    } else {
      out.push_back("(" + base.params[k].fallback + ")");
    }
  }
  return out;
}

std::vector<std::string> Translator::valuePieces(const Inherited& f) const {
  if (!f.pieces.empty()) return f.pieces;
  if (f.value.empty()) return {f.fallback};
  std::vector<std::string> pieces;
  for (size_t i : f.value) pieces.push_back(t_[i].kind == Token::Identifier ? t_[i].text : LcWriter::spelled(t_[i]));
  return pieces;
}

void Translator::moduleBody(std::vector<Inherited>& fields, std::optional<Range>& shader,
                            std::vector<std::pair<size_t, Range>>& assigned, std::vector<Declaration>& methods) {
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
    if (cur().is("(")) {
      // A method: C++ in the struct of the module's fields (a label's copy is one), on them.
      Declaration d;
      d.type = type;
      d.name = name;
      if (!t_[type].is("void") && cppType.empty()) notYet(t_[type], "a method giving a '" + t_[type].text + "'");
      ++p_;
      methodRest(d);
      methods.push_back(std::move(d));
      continue;
    }
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

Rule Translator::rule() {
  Rule r;
  // Contexts written apart: `(* b:Baum *),` — a node anywhere in the graph, which the rule
  // reads and does not rewrite.
  while (cur().is("(*")) {
    const size_t open = p_++;
    Node n = patternNode("a module in the context");
    if (!cur().is("*)")) notYet(cur(), "a context of more than one node (`(* A B *)`)");
    ++p_;
    if (accept(",")) {
      r.contexts.push_back(n);
      continue;
    }
    if (cur().kind != Token::Identifier)
      notYet(t_[open], "a context joined to the rule's nodes other than the node before it (`(* A *) B`)");
    r.before = n;
    break;
  }
  // The left side: nodes, each perhaps labelled, up to the condition or the arrow.
  do {
    r.left.push_back(patternNode(r.left.empty() ? "a rule (`A ==> B;`)" : "a module of the rule's left side"));
  } while (cur().kind == Token::Identifier);
  if (cur().is("(*")) {  // the node after it: `B (* C *)`
    ++p_;
    r.after = patternNode("a module in the context");
    if (!cur().is("*)")) notYet(cur(), "a context of more than one node (`(* A B *)`)");
    ++p_;
  }
  if ((r.before || r.after) && r.left.size() > 1)
    notYet(t_[r.left[1].name], "a context joined to a rule of more than one node");
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
  rightSide(r);
  return r;
}

void Translator::rightSide(Rule& r) {
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
        if (!(cur().is("if") && t_[p_ + 1].is("("))) openGroup(r, groups, depth);  // else if: the if's own
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
      n.shader = dotShader("a new node");
    } else if (cur().is("{")) {
      n.kind = Node::Block;
      n.name = p_;
      n.block = balanced();
      r.right.push_back(n);
      // A block may end a rule without `;` (the quick reference writes `… { t[length] *= 1.1 }`).
      if (depth == 0 && groups.empty() && (cur().is("]") || ruleStarts())) {
        r.end = n.block.second - 1;
        return;
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
  return;
}

void Translator::openGroup(Rule& r, std::vector<int>& groups, int depth) {
  if (!cur().is("(")) throw XlError{cur(), "expected '(' to begin the nodes of this " + t_[r.right.back().name].text};
  Node open;
  open.kind = Node::Open;
  open.name = p_++;
  r.right.push_back(open);
  groups.push_back(depth);
}

Node Translator::patternNode(const std::string& what) {
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

bool Translator::ruleStarts() const {
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

}  // namespace lcjit::frontend::xl
