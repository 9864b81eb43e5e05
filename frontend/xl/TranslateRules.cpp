// Writing one XL rule as an L+C production (Translator.h): the patterns of its left side, its
// labels' copies of their nodes' fields, its Java (with XL's names, Math and graph queries), its
// right side made in order, and the SPO rules lcjit runs.
#include "frontend/xl/Translator.h"

namespace lcjit::frontend::xl {

const Translator::Label* Translator::label(size_t at) const {
  auto it = labels_.find(t_[at].text);
  return t_[at].kind == Token::Identifier && it != labels_.end() ? &it->second : nullptr;
}

std::string Translator::unnamedField(size_t node, size_t field) {
  return "__xl_" + std::to_string(node) + "_" + std::to_string(field);
}

void Translator::pattern(const Node& n, size_t index) {
  if (const Module* m = userModule(t_[n.name].text)) {
    checkCount(n, *m);
    std::vector<std::string> names;
    for (size_t k = 0; k < m->fieldCount(); ++k)
      names.push_back(n.parens && k < n.args.size() ? t_[n.args[k].first].text
                                                    : unnamedField(index, k));
    if (n.label) labels_[t_[*n.label].text] = Label{m, names};
    writtenCall(n, m->lcName, std::vector<std::string>(names.begin() + long(n.args.size()), names.end()));
    return;
  }
  std::vector<std::string> defaults;
  const TurtleCommand* c = turtleOrError(n, &defaults);
  if (n.label) {
    // A label on a turtle command (`s:Sphere`): its fields as a module of the command's names.
    const Module* m = commandModule(*c);
    if (!m) notYet(t_[*n.label], "a label on GroIMP's " + t_[n.name].text);
    std::vector<std::string> names;
    for (size_t k = 0; k < m->fieldCount(); ++k)
      names.push_back(k < n.args.size() ? t_[n.args[k].first].text : unnamedField(index, k));
    labels_[t_[*n.label].text] = Label{m, names};
    writtenCall(n, std::string(c->module), std::vector<std::string>(names.begin() + long(n.args.size()), names.end()));
    return;
  }
  // `F` without parentheses: every F, whatever its length (a class pattern, as in GroIMP).
  std::vector<std::string> unnamed;
  for (size_t k = 0; k < defaults.size(); ++k)
    unnamed.push_back(unnamedField(index, k));
  writtenCall(n, std::string(c->module), unnamed);
}

const Module* Translator::commandModule(const TurtleCommand& c) {
  for (const Module& m : commandModules_)
    if (m.lcName == c.module) return &m;
  const std::vector<const Field*> fields = fieldsOf(c.name);
  if (fields.size() < size_t(c.arity)) return nullptr;
  Module m;
  m.lcName = std::string(c.module);
  for (int k = 0; k < c.arity; ++k) m.params.push_back({0, std::string(fields[k]->type), std::string(fields[k]->name)});
  commandModules_.push_back(std::move(m));
  return &commandModules_.back();
}

void Translator::writtenCall(const Node& n, const std::string& name, const std::vector<std::string>& more) {
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

void Translator::labelCopies() {
  for (const auto& [name, l] : labels_) {
    std::string decl = "struct {";
    std::string values;
    for (size_t k = 0; k < l.module->fieldCount(); ++k) {
      decl += " " + l.module->fieldType(k) + " " + l.module->fieldName(k) + ";";
      values += (k ? ", " : "") + l.bound[k];
    }
    // A module with methods has a struct of its own (write()), its methods on the copy.
    if (!methodsOf(*l.module).empty()) w_.add(fieldsStruct(*l.module) + " " + name + " = {" + values + "};");
    else w_.add(decl + " } " + name + " = {" + values + "};");
  }
}

void Translator::java(Range r) {
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
        if (dotted && i + 3 < r.second && t_[i + 3].is("(")) {
          // Null's setTransform(x, y, z) (the quick reference's `r.setTransform(0, 0, 1)`): the
          // translation's fields of the label's copy, which the node keeps.
          if (field == "setTransform" && l->module->fieldIndex("__xl_tx") < l->module->fieldCount()) {
            const size_t close = afterParentheses(i + 3);
            w_.at(i, "__xl_set_transform(" + t.text + ".__xl_tx, " + t.text + ".__xl_ty, " + t.text + ".__xl_tz, ");
            java(Range{i + 4, close - 1});
            w_.token(close - 1);
            i = close - 1;
            continue;
          }
          bool has = false;
          for (const Declaration* d : methodsOf(*l->module)) has = has || t_[d->name].text == field;
          if (!has) notYet(t_[i + 2], "a method of a node other than its module's (`" + t.text + "." + field + "(…)`)");
          w_.token(i);
          w_.at(i + 1, ".");
          w_.token(i + 2);
          i += 2;
          continue;
        }
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
    // Java's arrays (lcjit/xl.h's __xl_Array): `int[]` a type; `new int[n][m]` made by
    // __xl_new, each dimension's length computed where it is written; `new int[] {1, 2}` an
    // array of the values in braces.
    if (t.kind == Token::Identifier && !javaType(t.text).empty() && i + 2 < r.second && t_[i + 1].is("[") &&
        t_[i + 2].is("]")) {
      w_.at(i, javaTypeAt(i));
      while (i + 2 < r.second && t_[i + 1].is("[") && t_[i + 2].is("]")) i += 2;
      continue;
    }
    if (t.is("new") && i + 2 < r.second && !javaType(t_[i + 1].text).empty() && t_[i + 2].is("[")) {
      std::vector<Range> lengths;
      size_t at = i + 2, dims = 0;
      for (; at < r.second && t_[at].is("["); ++dims) {
        size_t close = at + 1;
        for (int depth = 1; close < r.second && (depth += nesting(t_[close])) > 0;) ++close;
        if (close > at + 1) lengths.push_back({at + 1, close});
        at = close + 1;
      }
      std::string type = javaType(t_[i + 1].text);
      for (size_t k = 0; k < dims; ++k) type = "__xl_Array<" + type + ">";
      if (lengths.empty()) {  // `new int[] {…}`: the braces follow
        w_.at(i, type);
      } else {
        w_.at(i, "__xl_new<" + type + ">(");
        for (size_t k = 0; k < lengths.size(); ++k) {
          if (k) w_.add(",");
          java(lengths[k]);
        }
        w_.add(")");
      }
      i = at - 1;
      continue;
    }
    if (t.is("boolean")) {
      w_.at(i, "bool");
      continue;
    }
    if (t.is("this") && i + 1 < r.second && t_[i + 1].is(".")) {  // in a module's method: its fields
      w_.at(i, "this->");
      ++i;
      continue;
    }
    // XL's deferred assignments (`x[f] := v`, `:+=` …) take effect after the step: a rule's
    // changes to a label's fields do so in lcjit anyway (the node takes them at the end).
    if (t.is(":") && i + 1 < r.second &&
        (t_[i + 1].is("=") || t_[i + 1].is("+=") || t_[i + 1].is("-=") || t_[i + 1].is("*=") || t_[i + 1].is("/=")))
      continue;
    // Java's `"…" + x` makes a string; C++'s would move a pointer: a literal a `+` touches is
    // XL's library's __xl_String (lcjit/xl.h), whose `+` is Java's.
    if (t.kind == Token::String && ((i > r.first && t_[i - 1].is("+")) || (i + 1 < r.second && t_[i + 1].is("+")))) {
      w_.at(i, "__xl_String(");
      w_.token(i);
      w_.add(")");
      continue;
    }
    w_.token(i);
  }
}

void Translator::block(const Node& n) {
  const size_t close = n.block.second - 1;
  w_.at(n.block.first, " ");
  java({n.block.first + 1, close});
  if (close > n.block.first + 1 && !t_[close - 1].is(";") && !t_[close - 1].is("}")) w_.add(";");
}

void Translator::rightStatements(const std::vector<Node>& right) {
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

void Translator::rightModules(const std::vector<Node>& right, bool axiom) {
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

void Translator::madeNode(const Node& n, std::vector<std::string> given, bool axiom) {
  if (const Label* l = axiom ? nullptr : label(n.name)) {
    if (n.parens) throw XlError{t_[n.name], "'" + t_[n.name].text + "' names a node of the left side: no arguments"};
    w_.at(n.name, fromLabel(t_[n.name].text, *l->module));
    return;
  }
  std::string name;
  std::vector<std::string> more;
  if (const Module* m = userModule(t_[n.name].text)) {
    checkCount(n, *m);
    if (!n.parens)
      for (const Param& p : m->params) given.push_back(p.fallback);  // GroIMP's constructor without arguments
    name = m->lcName;
    for (const Inherited& f : m->inherited)
      more.push_back(n.shader && (f.field == "color" || f.field == "shader") ? "(" + text(*n.shader) + ")"
                                                                           : inheritedValue(*m, f, given));
    if (n.shader && m->baseField("color").empty() && m->baseField("shader").empty())
      notYet(t_[n.shader->first], "setShader on a module extending other than F, Sphere or GroIMP's solids");
  } else {
    std::vector<std::string> defaults;
    const TurtleCommand* c = turtleOrError(n, &defaults);
    name = c->module;
    more.insert(more.end(), defaults.begin(), defaults.end());
    if (n.shader) {
      // Drawn in its colour, then the turtle where it ends: an instantiation rule's node is
      // drawing alone, not a node of the graph that would keep the colour.
      if (!instantiating_) notYet(t_[n.shader->first], "setShader on one of GroIMP's turtle commands in a rule (lcjit: on a module extending it)");
      given.insert(given.end(), more.begin(), more.end());
      w_.at(n.name, "SB SetColor((int)(" + text(*n.shader) + ") + 2) " + name + (given.empty() ? "" : "(" + joined(given) + ")") +
                        " EB" + (c->advance.empty() ? "" : " f(" + drawn(c->advance, given) + ")"));
      return;
    }
  }
  if (axiom) {
    if (!n.parens) more.insert(more.begin(), given.begin(), given.end());  // the parameters' fallbacks
    writtenCall(n, name, more);
  } else {
    given.insert(given.end(), more.begin(), more.end());
    w_.at(n.name, name + (given.empty() ? "" : "(" + joined(given) + ")"));
  }
}

bool Translator::hasBlock(const std::vector<Node>& right) {
  for (const Node& n : right)
    if (n.kind == Node::Block) return true;
  return false;
}

bool Translator::hasControl(const std::vector<Node>& right) {
  for (const Node& n : right)
    if (n.control()) return true;
  return false;
}

void Translator::stepwise(const std::vector<Node>& right) {
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

void Translator::forHeader(const Node& n) {
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

std::string Translator::inheritedValue(const Module& m, const Inherited& f, const std::vector<std::string>& given) const {
  if (f.value.empty() && f.pieces.empty()) return f.fallback;
  std::string s = "(";
  for (std::string piece : valuePieces(f)) {
    for (size_t k = 0; k < m.params.size(); ++k)
      if (piece == m.params[k].name && k < given.size()) piece = given[k];
    s += (s.size() > 1 ? " " : "") + piece;
  }
  return s + ")";
}

std::string Translator::fromLabel(const std::string& label, const Module& m) {
  std::vector<std::string> fields;
  for (size_t k = 0; k < m.fieldCount(); ++k) fields.push_back(label + "." + m.fieldName(k));
  return m.lcName + (fields.empty() ? "" : "(" + joined(fields) + ")");
}

std::string Translator::joined(const std::vector<std::string>& items) {
  std::string s;
  for (size_t k = 0; k < items.size(); ++k) s += (k ? ", " : "") + items[k];
  return s;
}

std::string Translator::text(Range r) const {
  std::string s;
  for (size_t i = r.first; i < r.second; ++i) s += (i > r.first ? " " : "") + LcWriter::spelled(t_[i]);
  return s;
}

std::string Translator::drawn(std::string_view pattern, const std::vector<std::string>& args) {
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

size_t Translator::rewrittenNode(const Rule& r, const std::vector<Token>& t) {
  return r.is(t, "==>>") && r.left.size() == 3 ? 1 : 0;
}

std::vector<const Module*> Translator::subclassesMatched(const Rule& r) const {
  std::vector<const Module*> found;
  const Node& n = r.left[rewrittenNode(r, t_)];
  const std::string& type = t_[n.name].text;
  if (const Module* base = userModule(type)) return subclassesOf(*base);
  if (n.label || r.is(t_, "::>")) return found;
  for (const Module& m : modules_)
    if (m.command == type) found.push_back(&m);
  return found;
}

std::vector<const Module*> Translator::subclassesOf(const Module& base) const {
  std::vector<const Module*> found;
  for (const Module& m : modules_)
    for (const Module* at = &m; at && at->base;) {
      at = userModule(t_[*at->base].text);
      if (at == &base) {
        found.push_back(&m);
        break;
      }
    }
  return found;
}

void Translator::subclassPattern(const Node& n, const Module& m, size_t index) {
  // The fields the pattern's arguments name, in order: a module's parameters, a command's fields.
  std::vector<std::string> named;
  if (const Module* base = userModule(t_[n.name].text)) {
    for (const Param& p : base->params) named.push_back(m.fieldIndex(p.name) < m.fieldCount() ? p.name : "");
  } else {
    for (const Field* f : fieldsOf(t_[n.name].text)) named.push_back(m.baseField(std::string(f->name)));
  }
  if (n.args.size() > named.size()) notYet(t_[n.name], "this pattern of " + t_[n.name].text + " matching its subclasses");
  std::vector<std::string> names;
  for (size_t f = 0; f < m.fieldCount(); ++f) names.push_back(unnamedField(index, f));
  for (size_t k = 0; k < n.args.size(); ++k)
    if (size_t f = m.fieldIndex(named[k]); !named[k].empty() && f < m.fieldCount()) names[f] = t_[n.args[k].first].text;
  if (n.label) labels_[t_[*n.label].text] = Label{&m, names};
  w_.at(n.name, m.lcName + (names.empty() ? "" : "(" + joined(names) + ")"));
}

void Translator::production(const Rule& r, const Module* subclass) {
  labels_.clear();
  std::vector<Node> right = r.right;
  if (r.is(t_, "==>>")) right = spoRight(r);
  const size_t node = rewrittenNode(r, t_);
  if (r.left.size() > 1 && !r.is(t_, "==>>")) notYet(t_[r.left[1].name], "a rule of more than one node on its left side");
  // Joined contexts are L+C's: `(* A *) B` is `A < B`, `B (* C *)` is `B > C`.
  if (r.before) {
    pattern(*r.before, r.left.size());
    w_.add("<");
  }
  for (size_t k = 0; k < r.left.size(); ++k) {
    if (k == 1 && node == 1) w_.add("<");
    if (subclass && k == node) subclassPattern(r.left[k], *subclass, k);
    else pattern(r.left[k], k);
    if (k == 1 && node == 1) w_.add(">");
  }
  if (r.after) {
    w_.add(">");
    pattern(*r.after, r.left.size() + 1);
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
    checkCount(n, *m);
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
    if (!kept.label || !label(*kept.label))
      notYet(t_[kept.name], "an update rule other than `c:C ::> { … }`");
    w_.at(r.end, "produce " + fromLabel(t_[*kept.label].text, *label(*kept.label)->module) + ";");
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
}

bool Translator::names(const Node& n, const Node& left, const std::vector<Token>& t) {
  return n.kind == Node::Module && !n.parens && left.label && t[n.name].text == t[*left.label].text;
}

bool Translator::deletes(const Rule& r, const std::vector<Token>& t) {
  if (!r.is(t, "==>>") || r.left.size() != 1) return false;
  for (const Node& n : r.right)
    if (names(n, r.left.front(), t) || n.control()) return false;
  return true;
}

std::vector<Node> Translator::spoRight(const Rule& r) {
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
    bool blocks = false;
    for (const Node& n : r.right) blocks = blocks || n.kind == Node::Block;
    if (names(first, r.left[0], t_) && names(last, r.left[2], t_) && !blocks)
      return std::vector<Node>(r.right.begin() + 1, r.right.end() - 1);
  }
  notYet(t_[r.arrow], "this SPO rule (`==>>`: lcjit runs `X ==>> ;` and `a:A X c:C ==>> a … c;`)");
}

}  // namespace lcjit::frontend::xl
