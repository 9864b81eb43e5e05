// Context Free expressions → C++ (Translator.h, sections 2 and 3): the seed bytes an expression
// contributes, and the C++ of values, calls, vectors and adjustment values.
#include "frontend/cfdg/Translator.h"

#include <cmath>
#include <cstdio>

#include "frontend/cfdg/Entropy.h"
#include "runtime/cfdg/Expander.h"  // kSeedBase

namespace lcjit::frontend::cfdg::translate {

using runtime::cfdg::kSeedBase;

namespace {

const std::map<std::string, std::string> kFunctions1 = {
    {"cos", "__cf_Cos"}, {"sin", "__cf_Sin"}, {"tan", "__cf_Tan"}, {"cot", "__cf_Cot"},
    {"acos", "__cf_Acos"}, {"asin", "__cf_Asin"}, {"atan", "__cf_Atan"}, {"acot", "__cf_Acot"},
    {"cosh", "__cf_Cosh"}, {"sinh", "__cf_Sinh"}, {"tanh", "__cf_Tanh"}, {"acosh", "__cf_Acosh"},
    {"asinh", "__cf_Asinh"}, {"atanh", "__cf_Atanh"}, {"log", "__cf_Log"}, {"log10", "__cf_Log10"},
    {"sqrt", "__cf_Sqrt"}, {"exp", "__cf_Exp"}, {"abs", "__cf_Abs"}, {"floor", "__cf_Floor"},
    {"ceiling", "__cf_Ceiling"}, {"infinity", "__cf_Infinity"}, {"factorial", "__cf_Factorial"},
    {"sg", "__cf_Sg"}, {"bitnot", "__cf_BitNot"}};
const std::map<std::string, std::string> kFunctions2 = {
    {"atan2", "__cf_Atan2"}, {"mod", "__cf_Mod"}, {"divides", "__cf_Divides"}, {"div", "__cf_Div"},
    {"bitor", "__cf_BitOr"}, {"bitand", "__cf_BitAnd"}, {"bitxor", "__cf_BitXor"},
    {"bitleft", "__cf_BitLeft"}, {"bitright", "__cf_BitRight"}};

// Context Free's distributions: the engine's number and how many arguments (-1: one or more).
const std::map<std::string, std::pair<std::string, int>> kDistributions = {
    {"rand::exponential", {"__cf_RandExponential", 1}}, {"rand::gamma", {"__cf_RandGamma", 2}},
    {"rand::weibull", {"__cf_RandWeibull", 2}}, {"rand::extremeV", {"__cf_RandExtremeValue", 2}},
    {"rand::normal", {"__cf_RandNormal", 2}}, {"rand::lognormal", {"__cf_RandLogNormal", 2}},
    {"rand::chisquared", {"__cf_RandChiSquared", 1}}, {"rand::cauchy", {"__cf_RandCauchy", 2}},
    {"rand::fisherF", {"__cf_RandFisherF", 2}}, {"rand::studentT", {"__cf_RandStudentT", 1}},
    {"randint::bernoulli", {"__cf_RandBernoulli", 1}}, {"randint::binomial", {"__cf_RandBinomial", 2}},
    {"randint::negbinomial", {"__cf_RandNegBinomial", 2}}, {"randint::poisson", {"__cf_RandPoisson", 1}},
    {"randint::geometric", {"__cf_RandGeometric", 1}}, {"randint::discrete", {"__cf_RandDiscrete", -1}}};

}  // namespace

// ---------------------------------------------------------------------------------------------
// 2. Seed bytes
// ---------------------------------------------------------------------------------------------

// The bytes an argument list contributes: each argument in a parenthesis, then the list.
std::string Translator::argBytes(const std::vector<ExprP>& args) {
  std::string b;
  for (const auto& a : args) b += bytes(*a) + hotbits("paren");
  return b + hotbits("cons");
}

// A call of the design's function `fn`: its arguments (none: nothing), then its name as its
// definition writes it.
std::string Translator::functionBytes(const Definition& fn, const std::vector<ExprP>& args) {
  return (args.empty() ? std::string() : argBytes(args)) + asWritten(fn.name, fn.written);
}

std::string Translator::bytes(const Expr& e) {
  switch (e.kind) {
    case Expr::Number: return e.text;
    case Expr::Name:
      if (e.text.rfind("CF::", 0) == 0) return {};  // flags and ∞ are textless numbers
      return asWritten(e.text, e.written);
    case Expr::Unary:
      return bytes(*e.args[0]) + hotbits(e.text == "-" ? "N" : e.text == "+" ? "P" : "!");
    case Expr::Binary:
      if (e.text == "..") return bytes(*e.args[0]) + bytes(*e.args[1]) + hotbits("cons") + hotbits("rand");
      if (e.text == "+/-") return bytes(*e.args[0]) + bytes(*e.args[1]) + hotbits("cons") + hotbits("rand2");
      return bytes(*e.args[0]) + bytes(*e.args[1]) + hotbits(e.text);
    case Expr::Paren: return bytes(*e.args[0]) + hotbits("paren");
    case Expr::List: {
      std::string b;
      for (const auto& a : e.args) b += bytes(*a);
      return b + hotbits("cons");
    }
    case Expr::Index: return asWritten(e.text, e.written) + bytes(*e.args[0]);
    case Expr::Call: {
      const std::string& f = e.text;
      if (f == "if" || f == "select") {
        // select()'s arguments are a call's, each in a parenthesis; if()'s a plain list.
        std::string b;
        for (const auto& a : e.args) b += bytes(*a) + (f == "select" ? hotbits("paren") : std::string());
        return b + hotbits("cons") + hotbits("select");
      }
      const Binding* bnd = lookup(f);
      // A user function: its name as its definition writes it.
      if (bnd && bnd->kind == Binding::Function) return functionBytes(*bnd->function, e.args);
      const std::string& name = asWritten(f, e.written);
      if (shapeIds_.count(f)) return e.reuseParams || e.args.empty() ? name : name + argBytes(e.args);
      std::string h = hotbits(f);
      if (h.empty()) return argBytes(e.args) + f;
      // Functions with default arguments get them before their bytes are taken; the inserted
      // numbers have no text.
      if ((f == "rand" || f == "rand_static" || f == "randint") && e.args.size() < 2) {
        std::string b;
        for (const auto& a : e.args) b += bytes(*a) + hotbits("paren");
        return b + hotbits("cons") + h;
      }
      // ftime(), frame() and infinity() are given one textless argument (not a list).
      if ((f == "ftime" || f == "frame" || f == "infinity") && e.args.empty()) return h;
      if (e.args.size() == 1) return bytes(*e.args[0]) + hotbits("paren") + hotbits("cons") + h;
      return argBytes(e.args) + h;
    }
    case Expr::Let: {
      // The definitions whose values are not constant (a list when more than one), then
      // `let`: the value itself adds nothing.
      std::string b;
      int given = 0;
      scopes_.emplace_back();
      for (size_t k = 0; k + 1 < e.args.size(); ++k) {
        Value v = probe(*e.args[k]);
        if (!v.constant) b += bytes(*e.args[k]), ++given;
        Binding bound{Binding::Local, "", int(v.parts.size()), v.constant};
        bound.adjustment = v.adjustment;
        scopes_.back()[e.names[k]] = bound;
      }
      scopes_.pop_back();
      return b + (given > 1 ? hotbits("cons") : std::string()) + "let";
    }
    case Expr::Modification: return {};
  }
  return {};
}

// ---------------------------------------------------------------------------------------------
// 3. Expressions → C++
// ---------------------------------------------------------------------------------------------

// A number as a C++ literal that keeps every bit (hexadecimal floating point).
std::string Translator::literal(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%a", v);
  return std::string("(") + b + ")";
}

// Sequences the parts of impure operands: C++ leaves the order of operands open, Context Free
// draws left to right. `$k` in `combine` is operand k.
std::string Translator::ordered(const std::vector<std::string>& operands, const std::string& combine, bool pure) {
  std::vector<std::string> names = operands;
  std::string r = pure ? "" : "({ ";
  if (!pure)
    for (auto& n : names) {
      std::string t = temp();
      r += "double " + t + " = " + n + "; ";
      n = t;
    }
  std::string c = combine;
  for (size_t k = names.size(); k-- > 0;) {  // $12 before $1
    std::string key = "$" + std::to_string(k);
    for (size_t p; (p = c.find(key)) != std::string::npos;) c.replace(p, key.size(), names[k]);
  }
  return pure ? c : r + c + "; })";
}

int Translator::staticOf(const Expr& e) {
  auto it = staticIndex_.find(&e);
  return it != staticIndex_.end() ? it->second : staticIndex_[&e] = statics_++;
}

// The statements `f` writes, as text (for a statement expression).
std::string Translator::captured(const std::function<void()>& f) {
  std::string saved = std::move(code_);
  int indent = indent_;
  code_.clear();
  indent_ = 0;
  f();
  std::string out = std::move(code_);
  code_ = std::move(saved);
  indent_ = indent;
  for (char& ch : out)
    if (ch == '\n') ch = ' ';
  return out;
}

// A value's numbers computed by its statements, in order, the parts naming them.
void Translator::hoist(Value& v) {
  for (auto& p : v.parts) {
    std::string t = temp();
    v.pre += "const double " + t + " = " + p + "; ";
    p = t;
  }
}

// Values taken left to right, their numbers in one list. When `settle`, or when one of them
// has statements to run first, the numbers that draw random numbers are computed first too, in
// order: each is drawn once, in its place.
Value Translator::joined(std::vector<Value> values, bool settle) {
  Value out;
  for (auto& v : values) settle |= !v.pre.empty();
  for (auto& v : values) {
    if (settle && !v.pure && v.pre.empty()) hoist(v);
    out.pre += v.pre;
    out.parts.insert(out.parts.end(), v.parts.begin(), v.parts.end());
    out.constant &= v.constant;
    out.pure &= v.pure;
  }
  return out;
}

// Numbers, one or more (a vector).
Value Translator::numbers(const Expr& e) {
  Value v = expr(e);
  if (v.adjustment) fail(e.at, "an adjustment is not a number");
  return v;
}

// One number, as one C++ expression.
Value Translator::scalar(const Expr& e) {
  Value v = numbers(e);
  if (v.parts.size() != 1) fail(e.at, "a number is expected here, this has " + std::to_string(v.parts.size()) + " values");
  return single(std::move(v));
}

Value Translator::single(Value v) {
  if (!v.pre.empty()) v.parts[0] = "({ " + v.pre + v.parts[0] + "; })";
  v.pre.clear();
  return v;
}

// A value's numbers for statements: its own statements written first.
std::vector<std::string> Translator::emitted(Value v) {
  if (!v.pre.empty()) line(v.pre);
  return v.parts;
}

// An adjustment value as a __cf_State (merged from the identity, as Context Free stores one).
std::string Translator::adjustmentState(const Value& v) {
  std::string t = temp();
  return "({ __cf_State " + t + "; __cf_identity(&" + t + "); " + captured([&] { v.apply(t, true); }) + t + "; })";
}

// A number written as a constant where Context Free needs one when it reads the design.
double Translator::constantNumber(const Expr& e, const std::string& what) {
  if (e.kind == Expr::Paren) return constantNumber(*e.args[0], what);
  if (e.kind == Expr::Unary && e.text == "-") return -constantNumber(*e.args[0], what);
  if (e.kind == Expr::Unary && e.text == "+") return constantNumber(*e.args[0], what);
  if (e.kind != Expr::Number) fail(e.at, what + " must be a number written here for lcjit");
  return numberValue(e.text);
}

// An adjustment variable or parameter: its value applied or merged.
Value Translator::adjustmentVariable(const std::string& cpp, const Binding& b) {
  Value v;
  v.parts.clear();
  v.adjustment = true;
  v.constant = b.constant;
  v.info = b.info;
  v.apply = [this, cpp](const std::string& state, bool merge) {
    std::string t = temp();
    line("{ const __cf_State " + t + " = " + cpp + "; " + (merge ? "__cf_merge(&" : "__cf_apply(&") + state + ", &" + t + "); }");
  };
  return v;
}

Value Translator::expr(const Expr& e) {
  Value v;
  switch (e.kind) {
    case Expr::Number: v.parts = {number(e.text)}; return v;
    case Expr::Name: {
      if (e.text == "CF::Infinity") return {{"(__builtin_inf())"}, true, true};
      if (e.text.rfind("CF::", 0) == 0) return {{flag(e)}, true, true};
      const Binding* b = lookup(e.text);
      if (!b) {
        if (shapeIds_.count(e.text)) return {{std::to_string(shapeIds_.at(e.text)) + ".0"}, true, true};
        fail(e.at, "'" + e.text + "' is not defined");
      }
      if (b->kind == Binding::Function) fail(e.at, "function '" + e.text + "' needs arguments");
      if (b->adjustment)
        return adjustmentVariable(b->kind == Binding::Param ? "__cf_state_at(p + " + b->cpp + ")" : b->cpp, *b);
      v.constant = b->constant;
      for (int k = 0; k < b->width; ++k) {
        if (b->kind == Binding::Param) v.parts.push_back("p[" + std::to_string(std::stoi(b->cpp) + k) + "]");
        else v.parts.push_back(b->width == 1 ? b->cpp : b->cpp + "[" + std::to_string(k) + "]");
      }
      return v;
    }
    case Expr::Paren: return expr(*e.args[0]);
    case Expr::List: {
      std::vector<Value> items;
      for (const auto& a : e.args) items.push_back(numbers(*a));
      return joined(std::move(items), true);
    }
    case Expr::Unary: {
      if (numbers(*e.args[0]).parts.size() != 1)
        fail(e.at, "a sign before a vector is not supported by lcjit (Context Free gives it one value's place)");
      Value a = scalar(*e.args[0]);
      std::string op = e.text == "!" ? "(double)!(" + a.parts[0] + ")" : "(" + e.text + a.parts[0] + ")";
      return {{op}, a.constant, a.pure};
    }
    case Expr::Binary: {
      const std::string& op = e.text;
      Value l = numbers(*e.args[0]), r = numbers(*e.args[1]);
      naturalOperands(e);
      const size_t ls = l.parts.size(), rs = r.parts.size();
      if (ls != 1 || rs != 1) return vectorOperation(e, std::move(l), std::move(r));
      l = single(std::move(l));
      r = single(std::move(r));
      bool pure = l.pure && r.pure;
      std::string c;
      if (op == "..") {
        return {{ordered({l.parts[0], r.parts[0]}, "__cf_rand(c, $0, $1)", pure)}, false, false};
      }
      if (op == "+/-") {
        return {{ordered({l.parts[0], r.parts[0]}, "__cf_randpm(c, $0, $1)", pure)}, false, false};
      }
      if (op == "^") c = "__cf_pow($0, $1)";
      else if (op == "--") c = "((($0) - ($1)) > 0 ? (($0) - ($1)) : 0.0)";
      else if (op == "==") c = "(double)(($0) == ($1))";
      else if (op == "<>") c = "(double)(($0) != ($1))";
      else if (op == "^^") c = "(double)((($0) != 0.0) != (($1) != 0.0))";
      else if (op == "<" || op == ">" || op == "<=" || op == ">=") c = "(double)(($0) " + op + " ($1))";
      else c = "(($0) " + op + " ($1))";
      if (op == "&&" || op == "||") {
        // Short-circuit: the right side is evaluated only when needed.
        std::string lt = temp();
        std::string body = op == "&&" ? "(" + lt + " == 0.0 ? 0.0 : (" + r.parts[0] + "))"
                                      : "(" + lt + " != 0.0 ? " + lt + " : (" + r.parts[0] + "))";
        return {{"({ double " + lt + " = " + l.parts[0] + "; " + body + "; })"}, l.constant && r.constant, pure};
      }
      return {{ordered({l.parts[0], r.parts[0]}, c, pure)}, l.constant && r.constant, pure};
    }
    case Expr::Index: return index(e);
    case Expr::Call: return call(e);
    case Expr::Let: return let(e);
    case Expr::Modification: return adjustmentLiteral(*e.adjustment);
  }
  return v;
}

// Operators with a vector operand, as Context Free computes them: + - -- element by element on
// equal lengths, * and / also with one scalar operand, == and <> comparing whole vectors.
Value Translator::vectorOperation(const Expr& e, Value l, Value r) {
  const std::string& op = e.text;
  const size_t ls = l.parts.size(), rs = r.parts.size();
  if (op == "+" || op == "-" || op == "--" || op == "==" || op == "<>") {
    if (ls != rs) fail(e.at, "Operands must have the same length");
  } else if (op == "*" || op == "/") {
    if (ls != rs && std::min(ls, rs) > 1) fail(e.at, "At least one operand must be scalar (or both same size)");
  } else {
    fail(e.at, "Binary operators must have two scalar operands");
  }
  Value both = joined({l, r}, true);  // each impure number drawn once, in order
  const std::vector<std::string> lp(both.parts.begin(), both.parts.begin() + long(ls));
  const std::vector<std::string> rp(both.parts.begin() + long(ls), both.parts.end());
  Value out;
  out.constant = both.constant;
  out.pure = both.pure;
  out.pre = both.pre;
  if (op == "==" || op == "<>") {
    std::string all;
    for (size_t k = 0; k < ls; ++k) all += (k ? " && " : "") + std::string("(") + lp[k] + ") == (" + rp[k] + ")";
    out.parts = {op == "==" ? "(double)(" + all + ")" : "(double)!(" + all + ")"};
    return single(std::move(out));
  }
  for (size_t k = 0; k < std::max(ls, rs); ++k) {
    const std::string& a = lp[ls == 1 ? 0 : k];
    const std::string& b = rp[rs == 1 ? 0 : k];
    if (op == "--") out.parts.push_back("((" + a + ") - (" + b + ") > 0.0 ? (" + a + ") - (" + b + ") : 0.0)");
    else out.parts.push_back("((" + a + ") " + op + " (" + b + "))");
  }
  return out;
}

// v[i], v[i, length], v[i, length, stride]: `length` numbers from index i, `stride` apart.
Value Translator::index(const Expr& e) {
  const Binding* b = lookup(e.text);
  if (!b || b->kind == Binding::Function || b->adjustment) fail(e.at, "'" + e.text + "' is not a vector");
  std::vector<const Expr*> items;
  if (e.args[0]->kind == Expr::List) for (const auto& a : e.args[0]->args) items.push_back(a.get());
  else items.push_back(e.args[0].get());
  if (items.size() > 3) fail(e.at, "a vector index takes an index, a length and a stride");
  int length = 1, stride = 1;
  for (size_t k = items.size() - 1; k > 0; --k) {  // Context Free reads them from the last
    stride = length;
    length = int(constantNumber(*items[k], "Vector stride/length"));
  }
  if (stride < 0 || length < 0) fail(e.at, "Vector length & stride arguments must be positive");
  if (stride * (length - 1) >= b->width) fail(e.at, "Vector length & stride arguments too large for source");
  Value i = scalar(*items[0]);
  std::string k = temp();
  std::string checked = "({ int " + k + " = (int)(" + i.parts[0] + "); if (" + k + " < 0 || " + k + " + " +
                        std::to_string((length - 1) * stride) + " >= " + std::to_string(b->width) +
                        ") __cf_fail_at(c, " + placeString(e.at) + ", \"Vector index exceeds bounds\"); " + k + "; })";
  auto element = [&](const std::string& at) {
    if (b->kind == Binding::Param) return "p[" + b->cpp + " + " + at + "]";
    return (b->width == 1 ? "(&" + b->cpp + ")" : b->cpp) + "[" + at + "]";
  };
  Value v;
  v.constant = b->constant && i.constant;
  v.pure = i.pure;
  if (length == 1) {
    v.parts = {"(" + element(checked) + ")"};
    return v;
  }
  std::string t = temp();
  v.pre = "const int " + t + " = " + checked + "; ";
  for (int n = 0; n < length; ++n) v.parts.push_back(element(t + " + " + std::to_string(n * stride)));
  return v;
}

// let(a = …; b = …; value): the definitions, then the value, with their names.
Value Translator::let(const Expr& e) {
  // The definitions' code, binding their names in a new scope (left for the caller to pop).
  auto define = [this, &e](bool& constant, bool& pure) {
    std::string code;
    scopes_.emplace_back();
    for (size_t k = 0; k + 1 < e.args.size(); ++k) {
      Value val = expr(*e.args[k]);
      std::string name = "v_" + identifier(e.names[k]) + "_" + std::to_string(temp_++);
      Binding bound{Binding::Local, name, int(val.parts.size()), val.constant};
      bound.locality = locality(*e.args[k]);
      bound.natural = natural(*e.args[k]);
      if (val.adjustment)  // Context Free keeps no value for it
        fail(e.args[k]->at, "an adjustment defined in let() is not supported by lcjit");
      if (val.parts.size() == 1) {
        code += "const double " + name + " = " + single(val).parts[0] + "; ";
      } else {
        code += val.pre + "const double " + name + "[" + std::to_string(val.parts.size()) + "] = {";
        for (auto& p : val.parts) code += p + ", ";
        code += "}; ";
      }
      scopes_.back()[e.names[k]] = bound;
      constant &= val.constant;
      pure &= val.pure;
    }
    return code;
  };
  bool constant = true, pure = true;
  std::string code = define(constant, pure);
  Value r = expr(*e.args.back());
  scopes_.pop_back();
  if (r.adjustment) {
    Value out = r;
    out.constant = constant && r.constant;
    if (!out.constant) out.info = AdjustmentInfo{};
    out.apply = [this, &e, define](const std::string& state, bool merge) {
      bool c = true, p = true;
      line("{");
      line(define(c, p));
      expr(*e.args.back()).apply(state, merge);
      scopes_.pop_back();
      line("}");
    };
    return out;
  }
  r.constant &= constant;
  r.pure &= pure;
  if (r.parts.size() == 1) {
    r = single(std::move(r));
    r.parts[0] = "({ " + code + r.parts[0] + "; })";
    return r;
  }
  if (!r.pure && r.pre.empty()) hoist(r);
  r.pre = code + r.pre;
  return r;
}

// [ … ] as a value.
Value Translator::adjustmentLiteral(const Adjustment& a) {
  Value v;
  v.parts.clear();
  v.adjustment = true;
  auto terms = prepare(a);
  v.info.classes = 0;
  for (const auto& t : terms) {
    if (t.kind == "sat") usesSat_ = true;
    if (t.kind == "time") usesTime_ = true;
    if (t.kind == "blend") usesBlend_ = true;
    Value x = termValue(t);
    v.constant &= x.constant;
    v.pure &= x.pure;
    v.info.classes |= x.adjustment ? x.info.classes : termClass(t.kind);
    v.info.colours |= x.adjustment ? x.info.colours : termColours(t.kind, int(x.parts.size()));
  }
  v.info.seed = seedOf(kSeedBase, adjustmentBytes(terms));
  const Adjustment* at = &a;
  v.apply = [this, at](const std::string& state, bool merge) {
    line("{");
    applyAdjustment(*at, prepare(*at), state, merge);
    line("}");
  };
  return v;
}

int Translator::flagNumber(const Expr& e) {
  static const std::map<std::string, int> kFlags = {
      {"CF::None", 0}, {"CF::MiterJoin", 8}, {"CF::RoundJoin", 10}, {"CF::BevelJoin", 11},
      {"CF::ButtCap", 128}, {"CF::SquareCap", 144}, {"CF::RoundCap", 160}, {"CF::ArcCW", 256},
      {"CF::ArcLarge", 512}, {"CF::Continuous", 1024}, {"CF::Align", 2048}, {"CF::EvenOdd", 4096},
      {"CF::IsoWidth", 8192},
      // Symmetry groups (CF::Symmetry, transform statements): k << 15.
      {"CF::Cyclic", 31 << 15}, {"CF::Dihedral", 1 << 15}, {"CF::p11g", 2 << 15}, {"CF::p11m", 3 << 15},
      {"CF::p1m1", 4 << 15}, {"CF::p2", 30 << 15}, {"CF::p2mg", 6 << 15}, {"CF::p2mm", 7 << 15},
      {"CF::pm", 8 << 15}, {"CF::pg", 9 << 15}, {"CF::cm", 10 << 15}, {"CF::pmm", 11 << 15},
      {"CF::pmg", 12 << 15}, {"CF::pgg", 13 << 15}, {"CF::cmm", 14 << 15}, {"CF::p4", 15 << 15},
      {"CF::p4m", 16 << 15}, {"CF::p4g", 17 << 15}, {"CF::p3", 18 << 15}, {"CF::p3m1", 19 << 15},
      {"CF::p31m", 20 << 15}, {"CF::p6", 21 << 15}, {"CF::p6m", 22 << 15}};
  auto it = kFlags.find(e.text);
  if (it == kFlags.end()) fail(e.at, "'" + e.text + "' is not a Context Free flag lcjit knows");
  return it->second;
}

Translator::Arguments Translator::arguments(const std::vector<Value>& values, bool settle) {
  Arguments out;
  for (const auto& v : values) settle |= v.adjustment || !v.pre.empty();
  std::vector<Value> numbers;
  for (const auto& v : values) {
    out.constant &= v.constant;
    out.pure &= v.pure;
    if (v.adjustment) {
      std::string t = temp();
      out.pre += "const __cf_State " + t + " = " + adjustmentState(v) + "; ";
      out.items.push_back(t);
      out.adjustment.push_back(true);
      continue;
    }
    Value n = v;
    if (settle && !n.pure && n.pre.empty()) hoist(n);
    out.pre += n.pre;
    for (auto& p : n.parts) out.items.push_back(p), out.adjustment.push_back(false);
  }
  out.settled = settle;
  return out;
}

// `combine` ($k: item k) of the arguments, as one C++ expression.
std::string Translator::combined(const Arguments& a, const std::string& combine) {
  std::string r = ordered(a.items, combine, a.pure || a.settled);
  return a.pre.empty() ? r : "({ " + a.pre + r + "; })";
}

// A parameter block of `shape`'s parameters from the arguments, as one C++ expression bound
// by `use` ($b: the block).
std::string Translator::block(const Arguments& a, int count, const std::string& use, const Place& at, const std::string& name) {
  int n = 0;
  std::string b = temp(), fill;
  for (size_t k = 0; k < a.items.size(); ++k) {
    if (a.adjustment[k]) {
      fill += "__cf_state_to(" + b + " + " + std::to_string(n) + ", $" + std::to_string(k) + "); ";
      n += __cf_StateDoubles;
    } else {
      fill += b + "[" + std::to_string(n++) + "] = $" + std::to_string(k) + "; ";
    }
  }
  if (n != count)
    fail(at, "shape '" + name + "' takes " + std::to_string(count) + " parameter values, " + std::to_string(n) + " given");
  std::string u = use;
  for (size_t p; (p = u.find("$b")) != std::string::npos;) u.replace(p, 2, b);
  return "({ double " + b + "[" + std::to_string(n + 1) + "]; " + fill + u + "; })";
}

Value Translator::call(const Expr& e) {
  const std::string& f = e.text;
  std::vector<Value> args;
  bool constant = true, pure = true;
  for (const auto& a : e.args) {
    args.push_back(expr(*a));
    constant &= args.back().constant;
    pure &= args.back().pure;
  }
  if (f == "if" || f == "select") return choice(e, std::move(args));
  auto numeric = [&]() {
    for (size_t k = 0; k < args.size(); ++k)
      if (args[k].adjustment) fail(e.args[k]->at, f + "() takes numbers");
  };
  if (const Binding* b = lookup(f); b && b->kind == Binding::Function) return userCall(*b, std::move(args), e.args, e.at);
  if (auto id = shapeIds_.find(f); id != shapeIds_.end()) {
    // A shape with its parameters bound: a shape value (for a parameter or variable of type
    // shape).
    int count = 0;
    if (id->second >= 4)
      for (const auto& p : decls_[size_t(id->second - 4)].params) count += p.width;
    if (e.reuseParams)  // NAME(=): bound to the running shape's own parameters
      return {{"__cf_bind(c, " + std::to_string(id->second) + ", p)"}, false, true};
    if (id->second >= 4) parameterRequirements(decls_[size_t(id->second - 4)].params, e.args, true);
    Arguments a = arguments(args, true);
    if (id->second >= 4) checkNaturals(decls_[size_t(id->second - 4)].params, e.args, args, a);
    std::string r = block(a, count, "__cf_bind(c, " + std::to_string(id->second) + ", $b)", e.at, f);
    return {{combined(a, r)}, constant, pure};
  }
  numeric();
  naturalOperands(e);
  Value all = joined(args, !pure);  // the numbers of all the arguments, in order
  const size_t n = all.parts.size();
  auto wrap = [&](const std::string& r) -> Value {
    return {{all.pre.empty() ? r : "({ " + all.pre + r + "; })"}, constant, pure};
  };
  auto ord = [&](const std::vector<std::string>& operands, const std::string& combine) {
    return ordered(operands, combine, pure || !all.pre.empty());
  };
  if (f == "rand" || f == "randint" || f == "rand_static") {
    if (n > 2) fail(e.at, "Illegal argument(s) for random function");
    std::string lo = "0.0", hi = f == "randint" ? "2.0" : "1.0";
    if (n == 1) hi = all.parts[0];
    if (n == 2) lo = all.parts[0], hi = all.parts[1];
    if (f == "rand_static") {
      std::string r = "(c->statics[" + std::to_string(staticOf(e)) + "] * __builtin_fabs((" + hi + ") - (" + lo +
                      ")) + __builtin_fmin(" + lo + ", " + hi + "))";
      return wrap(r);
    }
    Value v = wrap(ord({lo, hi}, std::string(f == "rand" ? "__cf_rand" : "__cf_randint") + "(c, $0, $1)"));
    v.constant = v.pure = false;
    return v;
  }
  if (f == "ftime" || f == "frame") {
    // The frame's time, or its place in the animation: known when the design runs.
    if (!args.empty()) fail(e.at, "ftime()/frame() functions takes no arguments");
    usesFrameTime_ = true;
    return {{"__cf_time(c, " + std::string(f == "ftime" ? "0" : "1") + ")"}, false, true};
  }
  if (auto it = kDistributions.find(f); it != kDistributions.end()) {
    // Arguments left to right, then the draws the distribution takes from the running state.
    const int arity = it->second.second;
    if (arity < 0 && n == 0) fail(e.at, "Function takes at least one arguments");
    if (arity == 1 && n != 1) fail(e.at, "Function takes one argument");
    if (arity == 2 && n != 2) fail(e.at, "Function takes two arguments");
    std::string combine = "({ const double _d[] = {";
    for (size_t k = 0; k < n; ++k) combine += "$" + std::to_string(k) + ", ";
    combine += "}; __cf_distribution(c, " + it->second.first + ", " + std::to_string(n) + ", _d); })";
    Value v = wrap(ord(all.parts, combine));
    v.constant = v.pure = false;
    return v;
  }
  if (f == "abs" && n == 2) return wrap(ord(all.parts, "__cf_fn2(c, __cf_Abs2, $0, $1)"));
  if (f == "min" || f == "max") {
    if (args.size() < 2 || n != args.size()) fail(e.at, f + "() takes two or more numbers");
    std::string combine = "$0";
    for (size_t k = 1; k < n; ++k)
      combine = "__cf_fn2(c, " + std::string(f == "min" ? "__cf_Min" : "__cf_Max") + ", " + combine + ", $" +
                std::to_string(k) + ")";
    return wrap(ord(all.parts, combine));
  }
  if (f == "dot" || f == "cross") {
    if (args.size() != 2) fail(e.at, "Dot/cross product takes two vectors");
    const size_t ls = args[0].parts.size(), rs = args[1].parts.size();
    if (f == "dot" && (ls != rs || ls < 2)) fail(e.at, "Dot product takes two vectors of the same length");
    if (f == "cross" && (ls != 3 || rs != 3)) fail(e.at, "Cross product takes two vector3s");
    Value both = joined(args, true);
    const auto& p = both.parts;
    Value v;
    v.constant = both.constant;
    v.pure = both.pure;
    v.pre = both.pre;
    if (f == "dot") {
      std::string sum = "0.0";
      for (size_t k = 0; k < ls; ++k) sum = "(" + sum + " + (" + p[k] + ") * (" + p[ls + k] + "))";
      v.parts = {sum};
      return single(std::move(v));
    }
    auto x = [&](int i, int j, int k, int l) {  // l[i]*r[j] - l[k]*r[l]
      return "((" + p[size_t(i)] + ") * (" + p[size_t(3 + j)] + ") - (" + p[size_t(k)] + ") * (" + p[size_t(3 + l)] + "))";
    };
    v.parts = {x(1, 2, 2, 1), x(2, 0, 0, 2), x(0, 1, 1, 0)};
    return v;
  }
  if (f == "hsb2rgb" || f == "rgb2hsb") {
    if (n != 3) fail(e.at, "RGB/HSB conversion function takes 3 arguments");
    Value v = joined(args, true);
    std::string in = temp(), out = temp();
    v.pre += "const double " + in + "[3] = {" + v.parts[0] + ", " + v.parts[1] + ", " + v.parts[2] + "}; double " + out +
             "[3]; __cf_colour(" + (f == "hsb2rgb" ? "1" : "0") + ", " + in + ", " + out + "); ";
    v.parts = {out + "[0]", out + "[1]", out + "[2]"};
    return v;
  }
  if (f == "vec") {
    // vec(n, a…): n numbers, a… repeated.
    if (e.args.size() < 2) fail(e.at, "vec() function at least two arguments");
    const int length = int(std::floor(constantNumber(*e.args[0], "vec()'s length")));
    if (length < 2 || length > 99) fail(e.args[0]->at, "vec() function length argument must be >= 2 and <= 99");
    Value v = joined(args, true);
    std::vector<std::string> from(v.parts.begin() + 1, v.parts.end());
    v.parts.clear();
    for (int k = 0; k < length; ++k) v.parts.push_back(from[size_t(k) % from.size()]);
    return v;
  }
  if (f == "isNatural") {
    // An integer from 0 to CF::MaxNatural; anything is natural in an impure design.
    if (n != 1) fail(e.at, f + "() takes one number");
    if (impure_) return wrap("((void)(" + all.parts[0] + "), 1.0)");
    return wrap("__cf_fn2(c, __cf_IsNatural, " + all.parts[0] + ", " + literal(maxNatural_) + ")");
  }
  if (auto it = kFunctions1.find(f); it != kFunctions1.end()) {
    if (n != 1 && !(f == "infinity" && n == 0)) fail(e.at, f + "() takes one number");
    if (f == "factorial")  // of a whole number from 0 to 18 (the last whose value is a whole double), impure or not
      return wrap("__cf_fn1(c, __cf_Factorial, " + wholeChecked(all.parts[0], 18, e.at, "Illegal argument for factorial") + ")");
    return wrap("__cf_fn1(c, " + it->second + ", " + (n == 0 ? std::string("1.0") : all.parts[0]) + ")");
  }
  if (auto it = kFunctions2.find(f); it != kFunctions2.end()) {
    if (n != 2) fail(e.at, f + "() takes two numbers");
    return wrap(ord(all.parts, "__cf_fn2(c, " + it->second + ", $0, $1)"));
  }
  fail(e.at, "'" + f + "' is not a function lcjit knows");
}

// A call of function `b` of the design with the arguments `exprs` (their values `args`).
Value Translator::userCall(const Binding& fb, std::vector<Value> args, const std::vector<ExprP>& exprs, const Place& at) {
  const Binding* b = &fb;
  const Definition& fn = *b->function;
  const std::string& f = fn.name;
  bool pure = true;
  for (const auto& v : args) pure &= v.pure;
  Arguments a = arguments(args);
  // Context Free's errors for a wrong number of arguments.
  if (fn.params.empty() && !exprs.empty()) fail(exprs[0]->at, "Arguments are not expected.");
  if (!fn.params.empty() && exprs.empty()) fail(at, "Arguments are expected.");
  // Numbers fill the parameters in order (a vector parameter takes as many), an adjustment
  // the adjustment parameter.
  size_t item = 0;
  for (const auto& p : fn.params) {
    if (item >= a.items.size()) fail(exprs[0]->at, "Not enough arguments.");
    if (p.type == "adjustment") {
      if (!a.adjustment[item]) fail(at, "function '" + f + "' takes an adjustment here");
      ++item;
      continue;
    }
    for (int k = 0; k < p.width; ++k, ++item)
      if (item >= a.items.size() || a.adjustment[item]) fail(at, "function '" + f + "' takes numbers here");
  }
  if (item != a.items.size()) fail(exprs[0]->at, "Too many arguments");
  parameterRequirements(fn.params, exprs, false);
  checkNaturals(fn.params, exprs, args, a);
  if (fn.type == "adjustment") {
    // Context Free applies (or merges) the function's adjustment where it is called.
    Value v;
    v.parts.clear();
    v.adjustment = true;
    v.constant = false;
    v.pure = false;
    std::string cpp = b->cpp;
    const std::vector<ExprP>* given = &exprs;
    v.apply = [this, given, cpp](const std::string& state, bool merge) {
      std::vector<Value> values;
      for (const auto& a : *given) values.push_back(expr(*a));
      Arguments a = arguments(values, true);
      std::string call = cpp + "(c, &" + state + ", " + (merge ? "1" : "0");
      for (auto& item : a.items) call += ", " + item;
      line("{ " + a.pre + call + "); }");
    };
    return v;
  }
  std::string combine = b->cpp + "(c";
  for (size_t k = 0; k < a.items.size(); ++k) combine += ", $" + std::to_string(k);
  combine += ")";
  const int width = functionWidth(fn);
  if (width == 1) return {{combined(a, combine)}, false, pure && b->constant};
  // A vector: the call once, its numbers named.
  Value v;
  v.constant = false;
  v.pure = pure && b->constant;
  std::string t = temp();
  v.pre = a.pre + "const __cf_V<" + std::to_string(width) + "> " + t + " = " +
          ordered(a.items, combine, a.pure || a.settled) + "; ";
  for (int k = 0; k < width; ++k) v.parts.push_back(t + ".v[" + std::to_string(k) + "]");
  return v;
}

// The numbers a function of the design gives: its type's (vectorN: N), 1 for a number.
int Translator::functionWidth(const Definition& fn) {
  if (fn.type.rfind("vector", 0) == 0) return std::atoi(fn.type.c_str() + 6);
  return 1;
}

// The C++ signature of a function of the design, without its closing parenthesis: a number's
// or a vector's function returns it; an adjustment's applies its adjustment to `state` (or
// merges it in). A parameter is a number, a vector's numbers one by one, or an adjustment.
std::string Translator::functionSignature(const Definition& fn, const std::string& name) {
  const int width = functionWidth(fn);
  std::string signature = fn.type == "adjustment" ? "void " + name + "(__cf_Ctx* c, __cf_State* state, int merge"
                                                   : (width == 1 ? "double " : "__cf_V<" + std::to_string(width) + "> ") +
                                                         name + "(__cf_Ctx* c";
  for (const auto& p : fn.params) {
    std::string pn = "a_" + identifier(p.name);
    if (p.type == "adjustment") {
      signature += ", __cf_State " + pn;
    } else if (p.width == 1) {
      signature += ", double " + pn;
    } else {
      for (int k = 0; k < p.width; ++k) signature += ", double " + pn + "_" + std::to_string(k);
    }
  }
  return signature;
}

// if(c, a, b) and select(i, a, b, …): the value chosen (only it is evaluated), numbers (all of
// one length) or adjustments.
Value Translator::choice(const Expr& e, std::vector<Value> args) {
  const std::string& f = e.text;
  if (f == "if" && args.size() != 3) fail(e.at, "if() takes a condition and two values");
  if (args.size() < 3) fail(e.at, "select()/if() function requires arguments");
  Value selector = scalar(*e.args[0]);
  const size_t n = args.size() - 1;
  for (size_t k = 2; k <= n; ++k) {
    if (args[k].adjustment != args[1].adjustment) fail(e.args[k]->at, "select()/if() choices must be of one type");
    if (!args[k].adjustment && args[k].parts.size() != args[1].parts.size())
      fail(e.args[k]->at, "select()/if() choices must be of one length");
  }
  // The condition for choice k (1…n), on the selector's value named s.
  auto test = [isIf = f == "if", n](const std::string& s, size_t k) -> std::string {
    return isIf ? (k == 1 ? s + " != 0.0" : "") : (k == n ? "" : s + " < " + std::to_string(k));
  };
  if (args[1].adjustment) {
    Value v;
    v.parts.clear();
    v.adjustment = true;
    v.constant = false;
    v.apply = [this, &e, selector, n, test](const std::string& state, bool merge) {
      std::string s = temp();
      line("{ const double " + s + " = " + selector.parts[0] + ";");
      for (size_t k = 1; k <= n; ++k) {
        std::string t = test(s, k);
        line(std::string(k == 1 ? "" : "} else ") + (t.empty() ? "{" : "if (" + t + ") {"));
        expr(*e.args[k]).apply(state, merge);
        if (t.empty()) break;
      }
      line("} }");
    };
    return v;
  }
  const size_t width = args[1].parts.size();
  bool constant = selector.constant, pure = selector.pure;
  for (size_t k = 1; k <= n; ++k) constant &= args[k].constant, pure &= args[k].pure;
  std::string s = temp();
  std::string r = "({ const double " + s + " = " + selector.parts[0] + "; ";
  std::string type = width == 1 ? "double" : "__cf_V<" + std::to_string(width) + ">";
  for (size_t k = 1; k <= n; ++k) {
    std::string t = test(s, k);
    Value c = args[k];
    std::string value;
    if (width == 1) {
      value = single(c).parts[0];
    } else {
      std::string list;
      for (auto& p : c.parts) list += p + ", ";
      value = "({ " + c.pre + type + "{{" + list + "}}; })";
    }
    r += (t.empty() ? "" : "(" + t + ") ? ") + std::string("(") + value + ")" + (t.empty() ? "" : " : ");
    if (t.empty()) break;
  }
  r += "; })";
  Value v;
  v.constant = constant;
  v.pure = pure;
  if (width == 1) {
    v.parts = {r};
    return v;
  }
  std::string t = temp();
  v.pre = "const " + type + " " + t + " = " + r + "; ";
  for (size_t k = 0; k < width; ++k) v.parts.push_back(t + ".v[" + std::to_string(k) + "]");
  return v;
}

}  // namespace lcjit::frontend::cfdg::translate
