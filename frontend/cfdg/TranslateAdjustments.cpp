// Context Free adjustments → C++ (Translator.h, section 4): terms in Context Free's order, constant
// terms folded as cfdg folds them, the rest applied at run time.
#include "frontend/cfdg/Translator.h"

#include <algorithm>

#include "frontend/cfdg/Entropy.h"
#include "runtime/cfdg/Expander.h"  // __cf_StateDoubles (lcjit/cfdg.h)

namespace lcjit::frontend::cfdg::translate {

// ---------------------------------------------------------------------------------------------
// 4. Adjustments
// ---------------------------------------------------------------------------------------------

void Translator::flattenArgs(const Term& t, std::vector<const Expr*>& out) {
  for (const auto& a : t.args) {
    if (a->kind == Expr::List)
      for (const auto& x : a->args) out.push_back(x.get());
    else
      out.push_back(a.get());
  }
}

// The numbers an argument gives (0 for an adjustment).
int Translator::widthOf(const Expr* e) {
  Value v = probe(*e);
  return v.adjustment ? 0 : int(v.parts.size());
}

int Translator::widthOf(const std::vector<const Expr*>& args) {
  int n = 0;
  for (const Expr* e : args) n += widthOf(e);
  return n;
}

// Context Free's preparation before seeds: `x A y B` (A one number) become one x term; x and s
// with three numbers split into a z (or zsize) term, then the two-valued one, when the
// arguments part into two numbers and the rest (else they stay xyz, sizexyz).
std::vector<Translator::PreparedTerm> Translator::prepare(const Adjustment& a) {
  std::vector<PreparedTerm> out;
  for (size_t k = 0; k < a.terms.size(); ++k) {
    const Term& t = a.terms[k];
    PreparedTerm p;
    p.kind = t.word;
    p.at = t.at;
    p.targetForm = t.targetForm;
    flattenArgs(t, p.args);
    if (p.kind == "x" && widthOf(p.args) == 1 && k + 1 < a.terms.size() && a.terms[k + 1].word == "y") {
      flattenArgs(a.terms[k + 1], p.args);
      ++k;
    }
    if ((p.kind == "x" || p.kind == "s") && widthOf(p.args) == 3) {
      std::vector<const Expr*> xy, z;
      int width = 0;
      for (const Expr* e : p.args) {
        if (xy.empty() || width < 2) xy.push_back(e), width += widthOf(e);
        else z.push_back(e);
      }
      if (!z.empty() && width == 2) {
        PreparedTerm zt;
        zt.kind = p.kind == "x" ? "z" : "zsize";
        zt.at = p.at;
        zt.args = z;
        out.push_back(zt);
        p.args = xy;
      } else {
        p.kind = p.kind == "x" ? "xyz" : "sizexyz";
      }
    }
    out.push_back(std::move(p));
  }
  return out;
}

std::string Translator::termBytes(const PreparedTerm& t) {
  std::string b;
  for (const Expr* e : t.args) b += bytes(*e);
  if (t.args.size() > 1 || (t.args.size() == 1 && t.args[0]->kind == Expr::List)) b += hotbits("cons");
  std::string word = t.kind;
  if (t.targetForm) word += "|";
  return b + hotbits(word);
}

std::string Translator::adjustmentBytes(const std::vector<PreparedTerm>& terms) {
  std::string b;
  for (const auto& t : terms) b += termBytes(t);
  return b;
}

int Translator::canonicalRank(const std::string& k) {
  static const std::map<std::string, int> kRank = {{"x", 0}, {"y", 1}, {"z", 2}, {"r", 3}, {"s", 4},
                                                   {"zsize", 5}, {"skew", 6}, {"f", 7}, {"trans", 8}};
  auto it = kRank.find(k);
  return it == kRank.end() ? -1 : it->second;
}

int Translator::termClass(const std::string& k) {
  enum { Geom = 1, Z = 2, PathOp = 4, Hue = 8, Sat = 16, Bright = 32, Alpha = 64, Time = 128 };
  if (k == "x" || k == "y" || k == "r") return Geom | PathOp;
  if (k == "z" || k == "zsize") return Z;
  if (k == "xyz" || k == "sizexyz") return Geom | Z;
  if (k == "trans" || k == "s" || k == "skew" || k == "f") return Geom;
  if (k == "h" || k == "|h") return Hue;
  if (k == "sat" || k == "|sat") return Sat;
  if (k == "b" || k == "|b") return Bright;
  if (k == "a" || k == "|a") return Alpha;
  if (k == "time" || k == "timescale") return Time;
  return 0;
}

std::string Translator::termEnum(const PreparedTerm& t) {
  const std::string& k = t.kind;
  if (t.targetForm) {
    if (k == "h") return "__cf_HueTarg";
    if (k == "sat") return "__cf_SatTarg";
    if (k == "b") return "__cf_BrightTarg";
    if (k == "a") return "__cf_AlphaTarg";
  }
  static const std::map<std::string, std::string> kEnum = {
      {"x", "__cf_X"}, {"y", "__cf_Y"}, {"z", "__cf_Z"}, {"xyz", "__cf_XYZ"}, {"trans", "__cf_Transform"},
      {"s", "__cf_Size"}, {"sizexyz", "__cf_SizeXYZ"}, {"r", "__cf_Rotate"}, {"skew", "__cf_Skew"},
      {"f", "__cf_Flip"}, {"zsize", "__cf_ZSize"}, {"blend", "__cf_Blend"}, {"h", "__cf_Hue"},
      {"sat", "__cf_Sat"}, {"b", "__cf_Bright"}, {"a", "__cf_Alpha"}, {"|h", "__cf_TargHue"},
      {"|sat", "__cf_TargSat"}, {"|b", "__cf_TargBright"}, {"|a", "__cf_TargAlpha"},
      {"time", "__cf_Time"}, {"timescale", "__cf_TimeScale"}};
  auto it = kEnum.find(k);
  if (it == kEnum.end()) fail(t.at, "the adjustment '" + k + (t.targetForm ? "|" : "") + "' is not supported by lcjit yet");
  return it->second;
}

// Canonical order: colour, time and blend terms first as written, then x y z r s zsize skew f
// trans; of two terms of one of these kinds the last one counts.
std::vector<Translator::PreparedTerm> Translator::canonical(std::vector<PreparedTerm> terms) {
  std::vector<PreparedTerm> front, geometric;
  for (auto& t : terms) (canonicalRank(t.kind) < 0 ? front : geometric).push_back(std::move(t));
  std::stable_sort(geometric.begin(), geometric.end(),
                   [](const PreparedTerm& x, const PreparedTerm& y) { return canonicalRank(x.kind) < canonicalRank(y.kind); });
  std::vector<PreparedTerm> unique;
  for (size_t k = 0; k < geometric.size(); ++k)
    if (k + 1 == geometric.size() || geometric[k + 1].kind != geometric[k].kind) unique.push_back(std::move(geometric[k]));
  terms = std::move(front);
  for (auto& t : unique) terms.push_back(std::move(t));
  return terms;
}

void Translator::foldedValue(const Value& v, const std::string& state) {
  foldedOnly_ = true;
  v.apply(state, true);
  foldedOnly_ = false;
}

// An adjustment variable `name` (its __cf_State declared by the caller) given adjustment value
// `v`, written `value`: made from the identity here (a constant value folded, another applied),
// and bound. Context Free keeps `name = [ … ]` as the adjustment; another expression only when
// it is constant. A definition's seed is its name's as written.
Binding Translator::adjustmentVariable(const Value& v, const Expr& value, const std::string& name, Binding::Kind kind, uint64_t seed) {
  if (value.kind != Expr::Modification && !v.constant)
    fail(value.at, "an adjustment variable defined by other than [ … ] is not supported by lcjit yet");
  line("__cf_identity(&" + name + ");");
  if (v.constant) foldedValue(v, name);
  else v.apply(name, true);
  Binding b{kind, name, __cf_StateDoubles, v.constant};
  b.adjustment = true;
  b.info = v.info;
  b.info.seed = seed;
  return b;
}

// The value of a prepared term's arguments: numbers, or (`trans a`) an adjustment.
Value Translator::termValue(const PreparedTerm& t) {
  if (t.kind == "trans" && t.args.size() == 1) {
    Value v = expr(*t.args[0]);
    if (v.adjustment) return v;
  }
  std::vector<Value> values;
  for (const Expr* e : t.args) values.push_back(numbers(*e));
  return joined(std::move(values), false);
}

// The colour values (1 << channel: 1 sat, 2 brightness, 3 alpha) a term with `count` numbers
// sets: a second setting of one in an adjustment waits for the run.
unsigned Translator::termColours(const std::string& kind, int count) {
  if (kind == "sat") return 1u << 1;
  if (kind == "b") return 1u << 2;
  if (kind == "a") return 1u << 3;
  if (kind == "h" && count > 2) return count == 3 ? 6u : 14u;
  return 0;
}

// Writes code that applies adjustment `a` (already prepared) to the state named `state`:
// the terms Context Free folds at parse time are merged into one constant adjustment applied
// first, the others applied one by one, in order, as it does at run time. With `merge` the
// adjustment is merged into `state` (an adjustment value being built) instead. Returns the seed
// the adjustment values folded in bring to the element's.
uint64_t Translator::applyAdjustment(const Adjustment& a, std::vector<PreparedTerm> terms, const std::string& state, bool merge) {
  const bool foldedOnly = foldedOnly_;
  foldedOnly_ = false;
  if (!a.ordered) terms = canonical(std::move(terms));
  int nonConstant = 0;
  std::string folded = temp();
  bool anyFolded = false;
  bool literalsOnly = true;
  unsigned colourSet = 0;  // channels the folded part sets (a second one waits for run time)
  uint64_t seed = 0;
  std::vector<std::pair<const PreparedTerm*, Value>> runtime;
  std::string foldCode;
  for (const auto& t : terms) {
    Value v = termValue(t);
    if (v.adjustment) {
      // `trans a`: a constant adjustment is folded in (with its seed) unless a term of its
      // classes waits for the run, or it sets a colour value already set.
      int mc = v.constant ? v.info.classes : -1;
      if (!v.constant) nonConstant = -1;
      if (!v.constant || (mc & nonConstant) != 0 || (colourSet & v.info.colours) != 0) {
        runtime.emplace_back(&t, std::move(v));
        continue;
      }
      colourSet |= v.info.colours;
      seed ^= v.info.seed;
      foldCode += "{ " + captured([&] { foldedValue(v, "m"); }) + "} ";
      literalsOnly = false;
      anyFolded = true;
      continue;
    }
    if (t.kind == "sat") usesSat_ = true;
    if (t.kind == "time") usesTime_ = true;
    if (t.kind == "blend") usesBlend_ = true;
    int mc = termClass(t.kind);
    if (t.kind == "s" && v.constant && v.parts.size() == 2 && v.parts[0] == "(0x1p+0)" && v.parts[1] == "(0x1p+0)")
      continue;  // `s 1 1` changes nothing and is dropped
    if (!v.constant) nonConstant |= mc;
    bool keep = (mc & nonConstant) != 0 || !v.constant;
    int channel = mc == 8 ? 0 : mc == 16 ? 1 : mc == 32 ? 2 : mc == 64 ? 3 : -1;
    if (!keep && channel > 0 && (colourSet & (1u << channel))) keep = true;
    if (!keep && t.kind == "h" && v.parts.size() != 2 && v.parts.size() > 1)
      for (size_t k = 1; k < v.parts.size(); ++k)
        if (colourSet & (1u << k)) keep = true;
    if (keep) {
      runtime.emplace_back(&t, std::move(v));
      continue;
    }
    if (channel >= 0) colourSet |= 1u << channel;
    if (t.kind == "h" && v.parts.size() > 2)
      for (size_t k = 1; k < v.parts.size(); ++k) colourSet |= 1u << k;
    std::string args = "{";
    for (auto& p : v.parts) {
      args += p + ", ";
      if (p.find_first_not_of("()+-0123456789abcdefpx.") != std::string::npos) literalsOnly = false;
    }
    args += "0}";
    foldCode += "{ " + v.pre + "const double _a[] = " + args + "; __cf_fold(&m, " + termEnum(t) + ", " +
                std::to_string(v.parts.size()) + ", _a); } ";
    anyFolded = true;
  }
  if (anyFolded) {
    // Folded once when its values are literals; else (constant names of the body) each time.
    line(std::string(literalsOnly ? "static " : "") + "const __cf_State " + folded + " = [&]{ __cf_State m; __cf_identity(&m); " +
         foldCode + "return m; }();");
    line(std::string(merge ? "__cf_merge(&" : "__cf_apply(&") + state + ", &" + folded + ");");
  }
  for (auto& [t, v] : runtime) {
    if (foldedOnly) break;
    if (v.adjustment) {
      v.apply(state, merge);
      continue;
    }
    std::string args = temp();
    std::string list;
    for (auto& p : v.parts) list += p + ", ";
    line("{ " + v.pre + "const double " + args + "[] = {" + list + "0}; " + (merge ? "__cf_fold(&" : "__cf_term(c, &") +
         state + ", " + termEnum(*t) + ", " + std::to_string(v.parts.size()) + ", " + args + "); }");
  }
  return seed;
}

}  // namespace lcjit::frontend::cfdg::translate
