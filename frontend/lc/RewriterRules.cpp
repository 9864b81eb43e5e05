// The rewriter's productions, decomposition and interpretation rules: the predecessor with its
// contexts (a rule function that unpacks the matched modules' parameters, and an entry of the
// rules' table), the body with produce, nproduce and propensity statements and InXContext calls
// rewritten, and the module lists of successors and the axiom.
//
// Sections, in order (each begins with a `// ----` rule): Predecessors (patternModule, rule) ·
// Bodies (block, produceStatement, inContext) · Module lists (successorList, parseModuleList).
#include <algorithm>
#include <map>

#include "frontend/lc/RewriterImpl.h"

namespace lcjit::frontend::detail {

// ---------------------------------------------------------------------------------------------
// Predecessors

PatternModule Rewriter::patternModule() {
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

void Rewriter::rule() {
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

// ---------------------------------------------------------------------------------------------
// Bodies

// A `{ ... }` body, with produce/nproduce/propensity/InXContext rewritten when in a rule.
void Rewriter::block(bool rule) {
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
      if (t.is("InString") && peek().is("(")) {
        const Token kw = t;
        next();
        inString(kw, rule);
        continue;
      }
    }
    if (t.is("{")) ++depth;
    if (t.is("}")) --depth;
    out_.token(t);
    next();
  }
}

// A produce, nproduce or propensity statement at the current token (false if there is none).
// In a rule body the successor goes to the rule's context; in a function it goes to the rule
// running when the function is called (lcjit_current_ctx), and in a control statement (Start,
// EndEach ...) nproduce goes nowhere: no rule is running.
bool Rewriter::produceStatement(Where where) {
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

void Rewriter::inContext(const Token& kw, int side) {
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
  for (size_t i = 0; i < mods.size(); ++i) bindParams(mods[i], "__lc_p[" + std::to_string(i) + "]");
  out_.glueAt(close, "return true; }())");
}

// The pattern module's parameter names given the values of the module record at `record` (a
// C++ expression), as InLeftContext and InString bind them.
void Rewriter::bindParams(const PatternModule& m, const std::string& record) {
  if (m.params.empty()) return;
  out_.glueAt(m.name, "{ __lc_R_" + m.name.text + " __lc_q; __builtin_memcpy(&__lc_q, " + record + ", sizeof __lc_q);");
  for (size_t j = 0; j < m.params.size(); ++j) {
    out_.token(m.params[j]);
    out_.glue(" = __lc_q.p" + std::to_string(j) + ";");
  }
  out_.glue("}");
}

// lcjit's own InString(M(a, …), CONDITION): whether the string, as the step found it, holds a
// module M whose parameters, put in the variables a, …, make CONDITION true; they keep the first
// such one's. XL's contexts written apart (`(* b:Baum *), t:Trieb, (b[alter] > 10)`) are written
// with it, and XL's queries (`count((* A *))`), in rules and in methods. CONDITION may hold
// another InString.
void Rewriter::inString(const Token& kw, bool rule) {
  expect("(", "after InString");
  PatternModule m = patternModule();
  expect(",", "after InString's module (InString(M(a), CONDITION))");
  out_.glueAt(kw, "([&]() -> bool { size_t __lc_at = 0; for (const char* __lc_q0; (__lc_q0 = lcjit_find_module(" +
                      std::string(rule ? "__lc_ctx" : "lcjit_current_ctx()") + ", " +
                      std::to_string(m.module->id) + ", &__lc_at));) {");
  bindParams(m, "__lc_q0");
  out_.glue(" if (");
  int depth = 0;
  while (!(depth == 0 && atText(")"))) {
    if (at(Token::End) || (depth == 0 && atText(";"))) fail(kw, "expected ')' to close InString");
    if (cur().is("InString") && peek().is("(")) {
      const Token inner = cur();
      next();
      inString(inner, rule);
      continue;
    }
    if (atText("(")) ++depth;
    if (atText(")")) --depth;
    out_.token(cur());
    next();
  }
  const Token& close = next();
  out_.glueAt(close, ") return true; } return false; }())");
}

// ---------------------------------------------------------------------------------------------
// Module lists

// A module list in an axiom or successor (`statement`: which), up to (not including)
// `terminator` at depth 0, written as calls.
void Rewriter::successorList(const char* terminator, const char* statement) {
  ModuleList list;
  parseModuleList(terminator, statement, list);
  for (const ModuleCall& c : list.calls) emitCall(list, c);
}

// Parses a module list (see successorList) into `list`; groups `( A B )` are transparent.
void Rewriter::parseModuleList(const char* terminator, const char* statement, ModuleList& list) {
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

}  // namespace lcjit::frontend::detail
