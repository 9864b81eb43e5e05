// XL's graph queries (Translator.h): `count((* l:Leaf, (l[area] > 1) *))`, `sum((* F *)[length])`,
// `mean((* Leaf *).getArea())` … over the whole graph, in a rule (the string as its step found
// it) or in Java (the string as it is), written with lcjit's InString (the rewriter's).
#include "frontend/xl/Translator.h"

#include <set>

namespace lcjit::frontend::xl {

std::vector<Translator::Matched> Translator::matchedBy(size_t name, const Module*& fields) {
  std::vector<Matched> found;
  const std::string& type = t_[name].text;
  auto all = [](const Module& m) {
    Matched f{&m, {}};
    for (size_t k = 0; k < m.fieldCount(); ++k) f.fieldsFrom.push_back(m.fieldName(k));
    return f;
  };
  if (const Module* base = userModule(type)) {
    fields = base;
    found.push_back(all(*base));
    for (const Module* m : subclassesOf(*base)) found.push_back(all(*m));
    return found;
  }
  if (!isTurtleCommand(type)) throw XlError{t_[name], "no module '" + type + "' to query"};
  // The command's fields as a module of its own (its values when a form has fewer: F(l)'s
  // diameter is −1, as GroIMP's node's), kept where the label points at it.
  Module all_fields;
  all_fields.lcName = "__xl_fields_of_" + type;
  for (const Field* f : fieldsOf(type))
    all_fields.params.push_back({0, std::string(f->type), std::string(f->name), false, std::string(f->fallback)});
  commandModules_.push_back(std::move(all_fields));
  fields = &commandModules_.back();
  for (const TurtleCommand& c : kTurtleCommands) {
    if (c.name != type) continue;
    const Module* m = commandModule(c);
    if (!m) continue;
    used_.insert(&c);  // declared, if the model makes none, so that the query can name it
    Matched f{m, {}};
    for (size_t k = 0; k < fields->fieldCount(); ++k)
      f.fieldsFrom.push_back(k < m->fieldCount() ? m->fieldName(k) : "");
    found.push_back(f);
  }
  for (const Module& m : modules_) {
    if (m.command != type) continue;
    Matched f{&m, {}};
    for (size_t k = 0; k < fields->fieldCount(); ++k) f.fieldsFrom.push_back(m.baseField(fields->fieldName(k)));
    found.push_back(f);
  }
  return found;
}

size_t Translator::query(size_t i, Range r) {
  static const std::set<std::string> kAggregates = {"count", "empty", "sum", "prod", "mean", "max", "min", "first", "last"};
  if (t_[i].kind != Token::Identifier || !kAggregates.count(t_[i].text) || i + 4 >= r.second || !t_[i + 1].is("(") ||
      !t_[i + 2].is("(*"))
    return i;
  const std::string& f = t_[i].text;
  size_t at = i + 3;
  std::string name = "__xl_n";
  if (t_[at].kind == Token::Identifier && t_[at + 1].is(":")) {
    name = t_[at].text;
    at += 2;
  }
  if (t_[at].kind != Token::Identifier) notYet(t_[at], "a query of other than a module (`(* M *)`, `(* m:M *)`)");
  const size_t type = at++;
  std::optional<Range> condition;
  if (t_[at].is(",") && t_[at + 1].is("(")) {
    condition = Range{at + 1, afterParentheses(at + 1)};
    at = condition->second;
  }
  if (!t_[at].is("*)")) notYet(t_[at], "a query of more than one node, or a condition other than `, (…)`");
  ++at;
  // What of each node the aggregate takes: `[field]`, `.field` or `.method(…)`.
  std::optional<size_t> member;
  std::optional<Range> call;
  if (t_[at].is("[")) {
    if (!t_[at + 2].is("]")) throw XlError{t_[at], "expected '[FIELD]' after the query"};
    member = at + 1;
    at += 3;
  } else if (t_[at].is(".") && t_[at + 1].kind == Token::Identifier) {
    member = at + 1;
    at += 2;
    if (t_[at].is("(")) {
      call = Range{at, afterParentheses(at)};
      at = call->second;
    }
  }
  if (!t_[at].is(")")) throw XlError{t_[at], "expected ')' to close " + f + "()"};
  const bool counts = f == "count" || f == "empty";
  if (counts == member.has_value())
    throw XlError{t_[i], counts ? f + "() counts nodes: no field" : f + "() needs a field: `" + f + "((* M *)[field])`"};

  const Module* fields = nullptr;
  const std::vector<Matched> matched = matchedBy(type, fields);
  if (member && !call && fields->fieldIndex(t_[*member].text) == fields->fieldCount())
    throw XlError{t_[*member], "a " + t_[type].text + " has no field '" + t_[*member].text + "'"};
  // XL's aggregates are of the value's type (de.grogra.xl.util.Operators: sum, mean, max and min
  // of ints are ints, of floats floats, summed as such; a mean of ints divides as ints).
  std::string valueType = "int";
  if (member && !call) valueType = fields->fieldType(fields->fieldIndex(t_[*member].text));
  if (call) {
    const Declaration* method = nullptr;
    for (const Declaration* d : methodsOf(*fields))
      if (t_[d->name].text == t_[*member].text) method = d;
    if (!method) throw XlError{t_[*member], "a " + t_[type].text + " has no method '" + t_[*member].text + "'"};
    valueType = javaTypeAt(method->type);
    if (valueType.empty() || valueType == "bool")
      throw XlError{t_[*member], f + "() of a method that returns no number ('" + t_[method->type].text + "')"};
  }

  // The condition and the value, each a lambda of the node's copy (written once, for every
  // module the type matches): in them the label names the copy, as in a rule.
  const std::string q = "__xl_q" + std::to_string(temps_++);
  const std::map<std::string, Label> outer = labels_;
  std::vector<std::string> names;
  for (size_t k = 0; k < fields->fieldCount(); ++k) names.push_back(fields->fieldName(k));
  labels_[name] = Label{fields, names};
  w_.at(i, "({ auto " + q + "c = [&](auto& " + name + ") -> bool { return");
  if (condition) java(*condition);
  else w_.add("true");
  w_.add("; }; auto " + q + "v = [&](auto& " + name + ") -> " + valueType + " { return");
  if (member) {
    w_.add(name + ".");
    w_.token(*member);
    if (call) java(*call);
  } else {
    w_.add("0");
  }
  w_.add("; };");
  labels_ = outer;

  if (f == "count") w_.add("int " + q + " = 0;");
  if (f == "empty") w_.add("bool " + q + " = true;");
  if (f == "sum") w_.add(valueType + " " + q + " = 0;");
  if (f == "prod") w_.add(valueType + " " + q + " = 1;");
  // first and last of none: NaN for floats, 0 for ints; first takes one value and stops.
  if (f == "first" || f == "last") w_.add(valueType + " " + q + " = __xl_none<" + valueType + ">(); bool " + q + "d = false;");
  if (f == "mean") w_.add(valueType + " " + q + " = 0; int " + q + "n = 0;");
  // Of none, max is the type's least (−∞ for floats), min its greatest.
  if (f == "max" || f == "min")
    w_.add(valueType + " " + q + " = " + (f == "max" ? "__xl_least<" : "__xl_greatest<") + valueType + ">();");
  std::string take;
  if (f == "count") take = "++" + q;
  if (f == "empty") take = q + " = false";
  if (f == "sum") take = q + " += " + q + "v(__xl_m)";
  if (f == "prod") take = q + " *= " + q + "v(__xl_m)";
  if (f == "first") take = "{ if (!" + q + "d) " + q + " = " + q + "v(__xl_m); " + q + "d = true; }";
  if (f == "last") take = q + " = " + q + "v(__xl_m)";
  if (f == "mean") take = q + " += " + q + "v(__xl_m), ++" + q + "n";
  if (f == "max") take = "{ auto __xl_v = " + q + "v(__xl_m); if (__xl_v > " + q + ") " + q + " = __xl_v; }";
  if (f == "min") take = "{ auto __xl_v = " + q + "v(__xl_m); if (__xl_v < " + q + ") " + q + " = __xl_v; }";
  for (const Matched& m : matched) {
    // Each node's fields into locals (InString binds them), then a copy of the fields the label
    // names: a module's struct when it has methods.
    std::string decls, vars, copy;
    for (size_t k = 0; k < m.module->fieldCount(); ++k) {
      const std::string v = q + "_" + std::to_string(k);
      decls += m.module->fieldType(k) + " " + v + " = 0; ";
      vars += (k ? ", " : "") + v;
    }
    std::string type = "struct {";
    for (size_t k = 0; k < fields->fieldCount(); ++k) {
      const size_t from = m.module->fieldIndex(m.fieldsFrom[k]);
      copy += (k ? ", " : "") + (from < m.module->fieldCount() ? q + "_" + std::to_string(from) : fields->params[k].fallback);
      type += " " + fields->fieldType(k) + " " + fields->fieldName(k) + ";";
    }
    type += " }";
    if (!methodsOf(*m.module).empty()) type = fieldsStruct(*m.module), copy = vars;
    w_.add("{ " + decls + "InString(" + m.module->lcName + (vars.empty() ? "" : "(" + vars + ")") + ", ({ " + type +
           " __xl_m = {" + copy + "}; if (" + q + "c(__xl_m)) " + take + "; false; })); }");
  }
  // A mean of none: 0 / 0, NaN for floats (an int's division by zero stops the model code, where
  // Java throws).
  w_.add(f == "mean" ? q + " / " + q + "n; })" : q + "; })");
  return at + 1;
}

}  // namespace lcjit::frontend::xl
