// Context Free paths → C++ (Translator.h, section 7): path operations, path commands, sub-paths.
#include "frontend/cfdg/Translator.h"

#include "frontend/cfdg/Entropy.h"
#include "runtime/cfdg/Paths.h"  // Context Free's path flags

namespace lcjit::frontend::cfdg::translate {

// ---------------------------------------------------------------------------------------------
// 7. Paths
// ---------------------------------------------------------------------------------------------

int Translator::bodyKind(const Body& b) {
  int k = 0;
  for (const auto& e : b) k |= elementKind(*e);
  return k;
}

int Translator::elementKind(const Element& e) {
  switch (e.kind) {
    case Element::PathOp: return kOps;
    case Element::PathCommand: return kCommands;
    case Element::Replace: return inPath_ ? subpathKind(e) : kReplacements;
    case Element::Loop:
    case Element::If:
    case Element::Transform:
    case Element::Clone: return bodyKind(e.body) | bodyKind(e.otherwise);
    case Element::Switch: {
      int k = 0;
      for (const auto& c : e.cases) k |= bodyKind(c.body);
      return k;
    }
    case Element::Define: return 0;
  }
  return 0;
}

// What path `shape`'s body holds, its sub-paths taken as they were when it was read.
int Translator::pathBodyOf(int shape) {
  for (size_t r = 0; r < d_.rules.size(); ++r)
    if (d_.rules[r].isPath && d_.rules[r].shape == out_.shapes[size_t(shape)]) {
      bool outer = inPath_;
      size_t rule = currentRule_;
      inPath_ = true, currentRule_ = r;
      int k = bodyKind(d_.rules[r].body);
      inPath_ = outer, currentRule_ = rule;
      return k;
    }
  return 0;
}

// What a sub-path element is taken to hold when it is read: a path written earlier in the file
// holds what its body holds; anything else (a later path, a primitive, a shape parameter or
// variable) is taken to be operations, and checked when it runs.
int Translator::subpathKind(const Element& e) {
  auto it = e.shapeExpr ? shapeIds_.end() : shapeIds_.find(e.shape);
  if (it == shapeIds_.end() || it->second < 4) return kOps;
  const ShapeDecl& decl = decls_[size_t(it->second - 4)];
  if (!decl.isPath) return kReplacements;
  for (size_t r = 0; r < currentRule_ && r < d_.rules.size(); ++r)
    if (d_.rules[r].isPath && d_.rules[r].shape == e.shape) {
      int k = pathBodyOf(it->second);
      return k != 0 ? k : kOps;
    }
  return kOps;
}

// A loop of path operations only: its frame transforms them (from the identity, unless they
// already are transformed). Returns the saved state for leavePathOps, or "".
std::string Translator::enterPathOps(const Element& loop, const std::string& frame) {
  if (!inPath_ || (bodyKind(loop.body) | bodyKind(loop.otherwise)) != kOps) return {};
  std::string saved = temp();
  line("int " + saved + " = __cf_pathEnterOps(c, &" + frame + ");");
  return saved;
}

void Translator::leavePathOps(const std::string& saved) {
  if (!saved.empty()) line("__cf_pathLeaveOps(c, " + saved + ");");
}

// A CF:: flag, or a sum of them (flags combine with +).
bool Translator::isFlag(const Expr& e) const {
  if (e.kind == Expr::Name) return e.text.rfind("CF::", 0) == 0 && e.text != "CF::Infinity";
  if (e.kind == Expr::Paren) return isFlag(*e.args[0]);
  if (e.kind == Expr::Binary && e.text == "+") return isFlag(*e.args[0]) && isFlag(*e.args[1]);
  return false;
}

int Translator::flagsOf(const Expr& e) {
  if (e.kind == Expr::Paren) return flagsOf(*e.args[0]);
  if (e.kind == Expr::Binary) return flagsOf(*e.args[0]) | flagsOf(*e.args[1]);
  return flagNumber(e);
}

void Translator::pathOp(const Element& e) {
  if (!inPath_) fail(e.at, "path operations are only allowed in a path");
  static const std::map<std::string, std::string> kOpNames = {
      {"MOVETO", "__cf_MoveTo"}, {"MOVEREL", "__cf_MoveRel"}, {"LINETO", "__cf_LineTo"},
      {"LINEREL", "__cf_LineRel"}, {"ARCTO", "__cf_ArcTo"}, {"ARCREL", "__cf_ArcRel"},
      {"CURVETO", "__cf_CurveTo"}, {"CURVEREL", "__cf_CurveRel"}, {"CLOSEPOLY", "__cf_ClosePoly"}};
  std::vector<const Expr*> items;
  if (e.value && e.value->kind == Expr::List) for (const auto& a : e.value->args) items.push_back(a.get());
  else if (e.value) items.push_back(e.value.get());
  // Numbers, then at most one flag (Context Free's rules and words).
  int flags = e.flags;
  const Expr* flag = nullptr;
  std::vector<std::string> values;
  for (const Expr* item : items) {
    if (isFlag(*item)) {
      if (flag) fail(item->at, "There can only be one flag argument");
      flag = item;
      flags |= flagsOf(*item);
      continue;
    }
    if (flag) fail(flag->at, "Flags must be the last argument");
    for (auto& part : emitted(numbers(*item))) {
      std::string t = temp();
      line("double " + t + " = " + part + ";");  // in order: they may draw random numbers
      values.push_back(t);
    }
  }
  const std::string& op = e.name;
  const int n = int(values.size());
  using namespace runtime::cfdg;  // the path flags
  // Context Free checks the arguments CFDG 3 writes; CFDG 2's named ones are put in order by the
  // parser, and their flags are not checked.
  const bool v2 = d_.version == 2;
  if (op == "MOVETO" || op == "MOVEREL" || op == "LINETO" || op == "LINEREL") {
    if (flags && !v2) fail(e.at, "No flags can be used with this operation");
    if (n != 2) fail(e.at, "Move/line path operation requires two arguments");
  } else if (op == "ARCTO" || op == "ARCREL") {
    if ((flags & ~(kArcCW | kArcLarge)) && !v2)
      fail(e.at, "Only CF::ArcCW and CF::ArcLarge flags can be used with this operation");
    if (n != 3 && n != 5) fail(e.at, "Arc path operations require three or five arguments");
  } else if (op == "CURVETO" || op == "CURVEREL") {
    if ((flags & ~kContinuous) && !v2) fail(e.at, "Only CF::Continuous flag can be used with this operation");
    if ((flags & kContinuous) && n != 2 && n != 4)
      fail(e.at, "Continuous curve path operations require two or four arguments");
    if (!(flags & kContinuous) && n != 4 && n != 6)
      fail(e.at, "Non-continuous curve path operations require four or six arguments");
  } else {
    if ((flags & ~kAlign) && !v2) fail(e.at, "Only CF::Align flag can be used with this operation");
    if (n != 0) fail(e.at, "CLOSEPOLY takes no arguments, only flags");
  }
  std::string list;
  for (int k = 0; k < 6; ++k) list += (k < n ? values[size_t(k)] : std::string("0")) + (k < 5 ? ", " : "");
  line("{ double _d[6] = {" + list + "}; __cf_pathOp(c, " + kOpNames.at(op) + ", " + std::to_string(flags) + ", " +
       std::to_string(n) + ", _d); }");
}

// STROKE(width, flags) [adj], FILL(flags) [adj]; CFDG 2: STROKE {width w p … adj}.
void Translator::pathCommand(const Element& e) {
  if (!inPath_) fail(e.at, "path commands are only allowed in a path");
  using namespace runtime::cfdg;  // the path flags
  int flags = (e.name == "FILL" ? kFill : 0) | e.flags;  // miter joins, butt caps
  const Expr* width = nullptr;
  const Expr* flagArg = nullptr;
  if (e.args.size() > 2) fail(e.args[2]->at, "Path commands can have zero, one, or two parameters");
  if (e.args.size() == 2) width = e.args[0].get(), flagArg = e.args[1].get();
  if (e.args.size() == 1) (isFlag(*e.args[0]) ? flagArg : width) = e.args[0].get();
  if (flagArg) {
    if (!isFlag(*flagArg)) fail(flagArg->at, "Unexpected argument in path command");
    int f = flagsOf(*flagArg);
    if (f & kJoinPresent) flags &= ~kJoinMask;  // a join replaces the miter join
    if (f & kCapPresent) flags &= ~kCapMask;    // a cap, the butt cap
    flags |= f;
  }
  // The adjustment's terms give the seed, the CFDG 2 stroke width with them (`width` adds its
  // value's bytes); the command runs with the others.
  auto terms = prepare(e.adjustment);
  uint64_t seed = seedOf(0, adjustmentBytes(terms) + e.name);
  std::vector<PreparedTerm> applied;
  for (auto& t : terms) {
    if (t.kind != "width") {
      applied.push_back(t);
      continue;
    }
    if (width || t.args.size() != 1) fail(t.at, "Only one stroke width term is allowed");
    width = t.args[0];
  }
  line("{");
  ++indent_;
  size_t seedAt = seedPlaceholder();
  line("c->cur = __cf_step(c->cur);");
  line("__cf_State s = *c->frame;");
  patchSeed(seedAt, seed ^ applyAdjustment(e.adjustment, std::move(applied), "s"));
  std::string w = "0.1";
  if (width) w = scalar(*width).parts[0];  // after the adjustment, as Context Free evaluates it
  line("__cf_pathCommand(c, &s, " + std::to_string(flags) + ", " + w + ");");
  --indent_;
  line("}");
}

// `path NAME(args) [adj]` in a path: the path's body (or a primitive's outline) runs here with
// the element's state, its operations transformed by it when it holds operations only.
void Translator::subpath(const Element& e) {
  if (!e.subpath) fail(e.shapeAt, "Replacements are not allowed in paths");
  if (e.shapeExpr) fail(e.shapeAt, "a sub-path must name a path");
  std::string shapeCode;
  std::string params = "nullptr";
  std::string spec = asWritten(e.shape, e.shapeWritten);
  const int kind = subpathKind(e);
  line("{");
  ++indent_;
  auto it = shapeIds_.find(e.shape);
  const Binding* variable = it == shapeIds_.end() ? lookup(e.shape) : nullptr;
  int paramCount = 0;
  const ShapeDecl* decl = nullptr;  // the path named, when it is one of the design's
  if (variable) {
    if (variable->kind == Binding::Function || variable->width != 1)
      fail(e.shapeAt, "'" + e.shape + "' is not a shape");
    shapeCode = variable->kind == Binding::Param ? "p[" + variable->cpp + "]" : variable->cpp;
  } else {
    int id = shapeId(e.shape, e.shapeAt);
    if (id == 3) fail(e.shapeAt, "FILL cannot be a subpath");
    if (id >= 4 && !decls_[size_t(id - 4)].isPath) fail(e.shapeAt, "Subpath can only refer to a path");
    if (id >= 4 && pathBodyOf(id) != kind) fail(e.shapeAt, "Subpath type mismatch error");
    shapeCode = std::to_string(id);
    if (id >= 4) decl = &decls_[size_t(id - 4)];
    for (const auto& p : decl ? decl->params : std::vector<Param>{}) paramCount += p.width;
  }
  if (e.reuseParams) {
    params = "p";
  } else if (e.hasArgs && !e.args.empty()) {
    spec += argBytes(e.args);
    auto [block, count] = argumentBlock(e.args, decl ? &decl->params : nullptr);
    if (!variable && count != paramCount)
      fail(e.shapeAt, "path '" + e.shape + "' takes " + std::to_string(paramCount) + " parameter values, " +
                          std::to_string(count) + " given");
    if (decl) parameterRequirements(decl->params, e.args, true);
    params = block;
  } else if (paramCount > 0) {
    fail(e.shapeAt, "path '" + e.shape + "' needs parameters");
  }
  auto terms = prepare(e.adjustment);
  size_t seedAt = seedPlaceholder();
  line("c->cur = __cf_step(c->cur);");
  line("__cf_State s = *c->frame;");
  std::string saved;
  if (kind == kOps) {
    saved = temp();
    line("int " + saved + " = __cf_pathEnterOps(c, &s);");
  }
  patchSeed(seedAt, seedOf(0, adjustmentBytes(terms) + spec) ^ applyAdjustment(e.adjustment, std::move(terms), "s"));
  if (variable && params == "nullptr")  // the shape and parameters the value holds
    line("__cf_subpath_value(c, " + shapeCode + ", &s, " + std::to_string(kind) + ");");
  else
    line("__cf_subpath(c, (int)(" + shapeCode + "), &s, " + params + ", " + std::to_string(kind) + ");");
  leavePathOps(saved);
  --indent_;
  line("}");
}

}  // namespace lcjit::frontend::cfdg::translate
