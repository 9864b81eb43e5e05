// The elements of a Context Free body → C++ (Translator.h, section 5): replacements, transforms,
// loops and definitions.
#include "frontend/cfdg/Translator.h"

#include "frontend/cfdg/Entropy.h"
#include "runtime/cfdg/Expander.h"  // kSeedBase

namespace lcjit::frontend::cfdg::translate {

using runtime::cfdg::kSeedBase;

// ---------------------------------------------------------------------------------------------
// 5. Elements
// ---------------------------------------------------------------------------------------------

void Translator::body(const Body& b) {
  for (const auto& e : b) element(*e);
}

void Translator::element(const Element& e) {
  switch (e.kind) {
    case Element::Replace:
      if (inPath_) subpath(e);
      else replacement(e);
      return;
    case Element::Define: define(e); return;
    case Element::Loop: loop(e); return;
    case Element::If: {
      Value cond = scalar(*e.value);
      line("if ((" + cond.parts[0] + ") != 0.0) {");
      ++indent_;
      scopes_.emplace_back();
      body(e.body);
      scopes_.pop_back();
      --indent_;
      line("} else {");
      ++indent_;
      scopes_.emplace_back();
      body(e.otherwise);
      scopes_.pop_back();
      --indent_;
      line("}");
      return;
    }
    case Element::Switch: {
      Value sel = scalar(*e.value);
      std::string s = temp();
      line("{ double " + s + " = __builtin_floor(" + sel.parts[0] + ");");
      ++indent_;
      bool first = true;
      const Element::Case* otherwise = nullptr;
      for (const auto& c : e.cases) {
        if (c.values.empty()) {
          otherwise = &c;
          continue;
        }
        std::string test;
        for (const auto& val : c.values) {
          const Expr& x = *val;
          std::vector<const Expr*> items;
          if (x.kind == Expr::List) for (const auto& i : x.args) items.push_back(i.get());
          else items.push_back(&x);
          for (const Expr* i : items) {
            if (!test.empty()) test += " || ";
            if (i->kind == Expr::Binary && i->text == "..") {
              Value lo = scalar(*i->args[0]), hi = scalar(*i->args[1]);
              test += "(" + s + " >= (" + lo.parts[0] + ") && " + s + " <= (" + hi.parts[0] + "))";
            } else {
              test += s + " == (" + scalar(*i).parts[0] + ")";
            }
          }
        }
        line(std::string(first ? "if (" : "} else if (") + test + ") {");
        first = false;
        ++indent_;
        scopes_.emplace_back();
        body(c.body);
        scopes_.pop_back();
        --indent_;
      }
      if (otherwise) {
        line(first ? "{" : "} else {");
        first = false;
        ++indent_;
        scopes_.emplace_back();
        body(otherwise->body);
        scopes_.pop_back();
        --indent_;
      }
      if (!first) line("}");
      --indent_;
      line("}");
      return;
    }
    case Element::Transform:
    case Element::Clone: transform(e); return;
    case Element::PathOp: pathOp(e); return;
    case Element::PathCommand: pathCommand(e); return;
  }
}

// Whether every term of `a` only moves, turns, scales, skews or flips: such an adjustment in a
// transform statement is a copy's geometry alone.
bool Translator::geometryOnly(const Adjustment& a) {
  constexpr int kGeometry = 1 | 4;  // termClass: moves, turns, sizes, skews, flips
  for (const auto& t : prepare(a)) {  // three-valued x and s move z too: z, xyz, sizexyz
    const std::string& k = t.kind;
    if (k != "x" && k != "y" && k != "r" && k != "s" && k != "skew" && k != "f" && k != "trans") return false;
    if (k == "trans" && t.args.size() == 1) {
      Value v = probe(*t.args[0]);
      if (v.adjustment && (v.info.classes & ~kGeometry) != 0) return false;
    }
  }
  return true;
}

// transform ADJ, ADJ… BODY (and clone): the body once per adjustment. Adjustments that only
// change geometry are evaluated first, as transforms, each distinct one kept once; the others
// (colour, z) are applied to each copy as it is made, first. Each copy steps the random state;
// clone starts every element of the body from the state the statement began with.
void Translator::transform(const Element& e) {
  std::vector<const Expr*> items;
  if (e.value->kind == Expr::List) for (const auto& a : e.value->args) items.push_back(a.get());
  else items.push_back(e.value.get());
  // A copy's adjustment: written [ … ], or a constant adjustment variable (Context Free takes no
  // other).
  struct Copy {
    const Adjustment* literal;
    const Expr* value;
  };
  std::vector<Copy> mods, geometric;
  bool symmetric = false;  // symmetry flags among the transforms (section 7)
  for (const Expr* x : items) {
    if (x->kind == Expr::Modification) {
      (geometryOnly(*x->adjustment) ? geometric : mods).push_back({x->adjustment.get(), nullptr});
      continue;
    }
    Value v = probe(*x);
    if (!v.adjustment) {
      symmetric = true;
      continue;
    }
    if (!v.constant) fail(x->at, "Wrong type");
    constexpr int kGeometry = 1 | 4;  // as geometryOnly
    ((v.info.classes & ~kGeometry) == 0 ? geometric : mods).push_back({nullptr, x});
  }
  std::string outer = temp(), transforms = temp(), count = temp(), clone = temp(), child = temp(), k = temp();
  line("{");
  ++indent_;
  line("const __cf_State* " + outer + " = c->frame;");
  if (symmetric) {
    // The transforms and the groups' transforms, each kept once, in the engine's buffer.
    std::vector<std::string> list = symmetryItems(*e.value, true);
    std::string initialisers, sym = temp();
    for (auto& i : list) initialisers += i + ", ";
    line("const __cf_SymmetryItem " + sym + "[] = {" + initialisers + "};");
    const std::string n = std::to_string(list.size());
    line("int " + count + " = __cf_symmetry(c, " + sym + ", " + n + ", nullptr, 0);");
    line("__cf_State* " + transforms + " = (__cf_State*)__builtin_alloca(sizeof(__cf_State) * (" + count + " + 1));");
    line("__cf_symmetry(c, " + sym + ", " + n + ", " + transforms + ", " + count + ");");
    geometric.clear();
  } else {
    line("__cf_State " + transforms + "[" + std::to_string(geometric.size() + 1) + "];");
    line("int " + count + " = 0;");
  }
  for (const Copy& copy : geometric) {
    std::string m = temp();
    line("{");
    ++indent_;
    line("__cf_State " + m + ";");
    line("__cf_identity(&" + m + ");");
    if (copy.value) expr(*copy.value).apply(m, true);
    const Adjustment* a = copy.literal;
    auto terms = a ? prepare(*a) : std::vector<PreparedTerm>{};
    if (a && !a->ordered) terms = canonical(std::move(terms));
    for (const auto& t : terms) {
      Value v = termValue(t);
      if (v.adjustment) {
        v.apply(m, true);
        continue;
      }
      std::string list;
      for (auto& p : v.parts) list += p + ", ";
      std::string args = temp();
      line("{ " + v.pre + "const double " + args + "[] = {" + list + "0}; __cf_fold(&" + m + ", " + termEnum(t) + ", " +
           std::to_string(v.parts.size()) + ", " + args + "); }");
    }
    line("if (!__cf_seen_transform(" + transforms + ", " + count + ", &" + m + ")) " + transforms + "[" + count + "++] = " + m + ";");
    --indent_;
    line("}");
  }
  line("const uint64_t " + clone + " = c->cur;");
  line("(void)" + clone + ";");
  line("for (int " + k + " = 0; " + k + " < " + std::to_string(mods.size()) + " + " + count + "; ++" + k + ") {");
  ++indent_;
  line("__cf_State " + child + " = *" + outer + ";");
  if (!mods.empty()) {
    line("switch (" + k + ") {");
    for (size_t i = 0; i < mods.size(); ++i) {
      line("case " + std::to_string(i) + ": {");
      ++indent_;
      if (mods[i].literal) applyAdjustment(*mods[i].literal, prepare(*mods[i].literal), child);
      else expr(*mods[i].value).apply(child, false);
      line("break;");
      --indent_;
      line("}");
    }
    line("default: __cf_transform_by(&" + child + ", &" + transforms + "[" + k + " - " + std::to_string(mods.size()) + "]);");
    line("}");
  } else {
    line("__cf_transform_by(&" + child + ", &" + transforms + "[" + k + "]);");
  }
  line("c->cur = __cf_step(c->cur);");
  line("c->frame = &" + child + ";");
  scopes_.emplace_back();
  for (const auto& el : e.body) {
    if (e.kind == Element::Clone) line("c->cur = " + clone + ";");
    element(*el);
  }
  scopes_.pop_back();
  --indent_;
  line("}");
  line("c->frame = " + outer + ";");
  --indent_;
  line("}");
}

// An adjustment value in a fresh __cf_State variable, as Context Free stores one; its name.
std::string Translator::adjustmentTemp(const Value& v) {
  std::string t = temp();
  line("__cf_State " + t + ";");
  line("__cf_identity(&" + t + ");");
  v.apply(t, true);
  return t;
}

// The parameter block of a shape's arguments (numbers; an adjustment in a __cf_State's room),
// evaluated in order: its name and the numbers it holds.
std::pair<std::string, int> Translator::argumentBlock(const std::vector<ExprP>& args, const std::vector<Param>* params) {
  std::vector<std::pair<std::string, bool>> items;
  const std::vector<bool> natural = params ? naturalSlots(*params) : std::vector<bool>();
  int n = 0;
  for (const auto& a : args) {
    Value v = expr(*a);
    if (v.adjustment) {
      items.emplace_back(adjustmentTemp(v), true);
      n += __cf_StateDoubles;
      continue;
    }
    for (auto& p : emitted(v)) {
      std::string t = temp();
      const bool check = items.size() < natural.size() && natural[items.size()];
      line("const double " + t + " = " + (check ? naturalChecked(p, placeOf(*a)) : p) + ";");
      items.emplace_back(t, false);
      ++n;
    }
  }
  std::string block = temp();
  line("double " + block + "[" + std::to_string(n + 1) + "];");
  int k = 0;
  for (auto& [t, adjustment] : items) {
    if (adjustment) {
      line("__cf_state_to(" + block + " + " + std::to_string(k) + ", " + t + ");");
      k += __cf_StateDoubles;
    } else {
      line(block + "[" + std::to_string(k++) + "] = " + t + ";");
    }
  }
  return {block, n};
}

// A seed xored into the running one, written once the adjustment after it is known (the
// adjustment values it folds in change it): the position to give patchSeed.
size_t Translator::seedPlaceholder() {
  size_t at = code_.size();
  line("c->cur ^= @SEED@;");
  return at;
}

void Translator::patchSeed(size_t at, uint64_t seed) {
  size_t p = code_.find("@SEED@", at);
  code_.replace(p, 6, hex64(seed));
}

void Translator::define(const Element& e) {
  Value v = expr(*e.value);
  std::string name = "v_" + identifier(e.name) + "_" + std::to_string(temp_++);
  if (v.adjustment) {
    const uint64_t seed = seedOf(kSeedBase, asWritten(e.name, e.nameWritten));
    if (!v.constant) line("c->cur ^= " + hex64(seed) + ";");
    line("__cf_State " + name + ";");
    scopes_.back()[e.name] = adjustmentVariable(v, *e.value, name, Binding::Local, seed);
    scopes_.back()[e.name].locality = locality(*e.value);
    return;
  }
  if (!v.constant) line("c->cur ^= " + hex64(seedOf(kSeedBase, asWritten(e.name, e.nameWritten))) + ";");
  std::vector<std::string> parts = emitted(v);
  if (parts.size() == 1) {
    line("double " + name + " = " + parts[0] + ";");
  } else {
    std::string list;
    for (auto& p : parts) list += p + ", ";
    line("double " + name + "[" + std::to_string(parts.size()) + "] = {" + list + "};");
  }
  scopes_.back()[e.name] = {Binding::Local, name, int(parts.size()), v.constant};
  scopes_.back()[e.name].locality = locality(*e.value);
  scopes_.back()[e.name].natural = natural(*e.value);
}

void Translator::replacement(const Element& e) {
  line("{");
  ++indent_;
  std::string shapeCode;
  std::string spec;
  std::string params = "nullptr";
  int paramCount = 0;
  const Binding* named = e.shapeExpr ? nullptr : lookup(e.shape);
  const Binding* function = named && named->kind == Binding::Function ? named : nullptr;
  if (function) named = nullptr;
  std::string value;  // a shape value (a parameter or variable of type shape, if(), select())
  if (function) {
    // `f(args) [adj]`: the shape a shape-valued function gives. Its bytes: the name, then the
    // call's (arguments and name again).
    if (function->function->type != "shape")
      fail(e.args.empty() ? e.shapeAt : e.args[0]->at, "Function does not return a shape");
    if (e.reuseParams) fail(e.shapeAt, "a function's arguments cannot be the shape's own parameters");
    std::vector<Value> args;
    for (const auto& a : e.args) args.push_back(expr(*a));
    value = temp();
    line("double " + value + " = " + single(userCall(*function, std::move(args), e.args, e.shapeAt)).parts[0] + ";");
    spec = asWritten(e.shape, e.shapeWritten) + functionBytes(*function->function, e.args);
  } else if (e.shapeExpr) {
    Value s = scalar(*e.shapeExpr);
    value = temp();
    line("double " + value + " = " + s.parts[0] + ";");
    spec = bytes(*e.shapeExpr);
  } else if (named) {
    if (e.hasArgs && !e.reuseParams) fail(e.shapeAt, "'" + e.shape + "' is a shape value: its parameters are bound already");
    Expr name;
    name.kind = Expr::Name;
    name.at = e.shapeAt;
    name.text = e.shape;
    value = temp();
    line("double " + value + " = " + scalar(name).parts[0] + ";");
    spec = asWritten(e.shape, e.shapeWritten);
  } else {
    int id = shapeId(e.shape, e.shapeAt);
    shapeCode = std::to_string(id);
    const ShapeDecl* decl = id >= 4 ? &decls_[size_t(id - 4)] : nullptr;
    for (const auto& p : decl ? decl->params : std::vector<Param>{}) paramCount += p.width;
    spec = asWritten(e.shape, e.shapeWritten);
    if (e.reuseParams) {
      params = "p";
    } else if (e.hasArgs && !e.args.empty()) {
      spec += argBytes(e.args);
      auto [block, count] = argumentBlock(e.args, decl ? &decl->params : nullptr);
      if (count != paramCount)
        fail(e.shapeAt, "shape '" + e.shape + "' takes " + std::to_string(paramCount) + " parameter values, " +
                            std::to_string(count) + " given");
      if (decl) parameterRequirements(decl->params, e.args, true);
      params = block;
    } else if (paramCount > 0) {
      fail(e.shapeAt, "shape '" + e.shape + "' needs parameters");
    }
  }
  auto terms = prepare(e.adjustment);
  uint64_t seed = seedOf(0, adjustmentBytes(terms) + spec);
  size_t seedAt = seedPlaceholder();
  line("c->cur = __cf_step(c->cur);");
  line("__cf_State s = *c->frame;");
  patchSeed(seedAt, seed ^ applyAdjustment(e.adjustment, std::move(terms), "s"));
  if (!value.empty()) line("__cf_replace_value(c, " + value + ", &s);");
  else line("__cf_replace(c, " + shapeCode + ", &s, " + params + ");");
  --indent_;
  line("}");
}

void Translator::loop(const Element& e) {
  // The index, named `cpp` in C++: it depends on parameters as the loop's count (start, end,
  // step) does, and is natural as section 9 says.
  const Locality indexLocality = locality(*e.value);
  const bool indexNatural = naturalLoopIndex(*e.value);
  auto bindIndex = [&](const std::string& cpp) {
    if (e.name.empty()) return;
    Binding b{Binding::Local, cpp, 1, false};
    b.locality = indexLocality;
    b.natural = indexNatural;
    scopes_.back()[e.name] = b;
  };
  scopes_.emplace_back();  // the index is a name in the loop's adjustment
  bindIndex("0.0");
  auto terms = prepare(e.adjustment);
  scopes_.pop_back();
  std::string indexName = e.name.empty() ? "~~inaccessiblevar~~" : asWritten(e.name, e.nameWritten);
  uint64_t seed = seedOf(kSeedBase, indexName + bytes(*e.value)) ^ seedOf(kSeedBase, adjustmentBytes(terms));
  if (e.v2Loop)  // CFDG 2: the terms' bytes twice (as written, then in the order they apply), then the count
    seed = seedOf(0, adjustmentBytes(terms) + adjustmentBytes(e.adjustment.ordered ? terms : canonical(terms)) +
                         "~~inaccessiblevar~~" + e.v2Count);
  line("{");
  ++indent_;
  size_t seedAt = seedPlaceholder();
  std::vector<std::string> bounds;
  for (auto& part : emitted(numbers(*e.value))) {  // in order: they may draw random numbers
    std::string t = temp();
    line("double " + t + " = " + part + ";");
    bounds.push_back(t);
  }
  if (bounds.empty() || bounds.size() > 3) fail(e.at, "loop takes a count, or a start and an end, and a step");
  std::string start = "0.0", end, step = "1.0";
  if (bounds.size() == 1) end = bounds[0];
  else start = bounds[0], end = bounds[1];
  if (bounds.size() == 3) step = bounds[2];
  std::string frame = temp(), outer = temp(), index = "v_" + (e.name.empty() ? std::string("loop") : identifier(e.name)) + "_" + std::to_string(temp_++);
  line("__cf_State " + frame + " = *c->frame;");
  line("const __cf_State* " + outer + " = c->frame;");
  std::string pathOps = enterPathOps(e, frame);
  line("double " + index + " = " + start + ";");
  line("for (;;) {");
  ++indent_;
  line("if ((" + step + ") > 0.0 ? " + index + " >= " + end + " : " + index + " <= " + end + ") break;");
  line("c->frame = &" + frame + ";");
  scopes_.emplace_back();
  bindIndex(index);
  body(e.body);
  scopes_.pop_back();
  // The loop's adjustment sees the index (`loop i = 1, 5 [x i]`), as it is in this pass, but
  // not the body's names.
  scopes_.emplace_back();
  bindIndex(index);
  patchSeed(seedAt, seed ^ applyAdjustment(e.adjustment, terms, frame));
  scopes_.pop_back();
  line(index + " += " + step + ";");
  --indent_;
  line("}");
  line("c->frame = &" + frame + ";");
  scopes_.emplace_back();
  bindIndex(index);
  body(e.otherwise);
  scopes_.pop_back();
  leavePathOps(pathOps);
  line("c->frame = " + outer + ";");
  --indent_;
  line("}");
}

}  // namespace lcjit::frontend::cfdg::translate
