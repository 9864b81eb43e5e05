// A parsed Context Free design → C++ (Translate.h). Sections:
//   1. Names in scope and values
//   2. Seed bytes of expressions and adjustments
//   3. Expressions → C++
//   4. Adjustments: Context Free's term order, folding of constant terms, run-time terms
//   5. Elements of a body → C++
//   6. The unit: globals, functions, rules, the start shape, the design's table
//   7. Paths: operations, commands, sub-paths
//   8. Picture settings: CF::Tile, CF::Size, CF::Symmetry, the borders, the pixel format,
//      CF::StartShape
#include "frontend/cfdg/Translate.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <set>

#include "frontend/cfdg/Entropy.h"
#include "frontend/cfdg/Parser.h"
#include "runtime/cfdg/Expander.h"  // kSeedBase
#include "runtime/cfdg/Paths.h"     // Context Free's path flags

namespace lcjit::frontend::cfdg {
namespace {

using runtime::cfdg::kSeedBase;

struct TranslateError {
  Place at;
  std::string message;
};
[[noreturn]] void fail(const Place& at, const std::string& message) { throw TranslateError{at, message}; }

// ---------------------------------------------------------------------------------------------
// 1. Names in scope and values
// ---------------------------------------------------------------------------------------------

// What an adjustment value is known to hold when the design is read: Context Free folds a
// constant one into the adjustment it is used in, which then takes its seed and its term classes.
struct AdjustmentInfo {
  int classes = -1;       // the classes of its terms (section 4's termClass); all when not known
  unsigned colours = 0;   // the colour values it sets (1 << channel), for conflicts when folding
  uint64_t seed = 0;      // the seed it brings along when folded
};

struct Binding {
  enum Kind { Param, Local, Global, Function } kind;
  std::string cpp;  // what C++ calls it (Param: the block's first index)
  int width = 1;    // numbers (an adjustment: the room it takes in a parameter block)
  bool constant = false;
  bool shape = false;  // a shape-typed parameter
  const Definition* function = nullptr;
  bool adjustment = false;  // a __cf_State
  AdjustmentInfo info;      // an adjustment's
};

// The C++ of a value of the design: numbers (one, or a vector's), or an adjustment.
struct Value {
  std::vector<std::string> parts;  // C++ expressions, one per number
  bool constant = true;            // Context Free folds it at parse time: no seed effect
  bool pure = true;                // draws no random numbers
  // Statements to run before the parts (a vector's values computed once, in order): then the
  // parts only name what they computed. Numbers alone never have any (see scalar()).
  std::string pre;
  // An adjustment: `apply` writes the statements that change the __cf_State named `state` by it,
  // applied to a shape (`merge` false: Context Free's shape destination) or merged into an
  // adjustment being built (`merge` true: a variable's or parameter's value).
  bool adjustment = false;
  std::function<void(const std::string& state, bool merge)> apply;
  AdjustmentInfo info;
};

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

// A design's name as a C++ identifier: names may hold any UTF-8 letter and `::`.
std::string identifier(const std::string& name) {
  std::string out;
  for (unsigned char ch : name) {
    if (std::isalnum(ch)) {
      out += char(ch);
    } else {
      char b[8];
      std::snprintf(b, sizeof b, "_%02X", ch);
      out += b;
    }
  }
  return out;
}

// A name as written (its seed bytes), given the name and Ast.h's `written` field.
const std::string& asWritten(const std::string& name, const std::string& written) {
  return written.empty() ? name : written;
}

std::string hex64(uint64_t v) {
  char b[32];
  std::snprintf(b, sizeof b, "0x%016llXull", static_cast<unsigned long long>(v));
  return b;
}

class Translator {
 public:
  explicit Translator(const Design& d) : d_(d) {}

  Translation run();

 private:
  const Design& d_;
  Translation out_;
  std::map<std::string, int> shapeIds_;
  std::vector<ShapeDecl> decls_;         // the design's shapes, then those only named (by id - 4)
  std::set<std::string> undeclared_;
  std::vector<std::map<std::string, Binding>> scopes_;
  std::map<std::string, Binding> globals_;
  int temp_ = 0;
  int statics_ = 0;
  std::map<const Expr*, int> staticIndex_;  // each rand_static()'s number, in the order first met
  bool usesSat_ = false;    // a sat term: the picture is in colour
  bool usesBlend_ = false;  // a blend term: the picture is drawn with compositing operators
  double maxNatural_ = 1000;  // CF::MaxNatural
  bool impure_ = false;       // CF::Impure
  bool usesTime_ = false;       // a time term: shapes have their own times in an animation
  bool usesFrameTime_ = false;  // ftime() or frame(): an animation expands the design per frame
  std::map<std::string, const Definition*> timing_;  // CF::Time, CF::FrameTime, CF::Frame
  const Expr* background_ = nullptr;  // CF::Background
  bool inPath_ = false;      // translating a path's body
  size_t currentRule_ = 0;   // the rule being translated (its index in the design)
  std::string code_;  // the body being written
  int indent_ = 1;

  void line(const std::string& s) {
    code_.append(size_t(indent_) * 2, ' ');
    code_ += s;
    code_ += '\n';
  }
  std::string temp() { return "_t" + std::to_string(temp_++); }

  const Binding* lookup(const std::string& name) const {
    for (auto it = scopes_.rbegin(); it != scopes_.rend(); ++it) {
      auto f = it->find(name);
      if (f != it->end()) return &f->second;
    }
    auto g = globals_.find(name);
    return g == globals_.end() ? nullptr : &g->second;
  }
  // A shape named where none is declared is a shape without rules, as in Context Free: an error
  // only if a run reaches it (the engine then names the place it is first used).
  int shapeId(const std::string& name, const Place& at) {
    auto it = shapeIds_.find(name);
    if (it != shapeIds_.end()) return it->second;
    ShapeDecl implicit;
    implicit.name = name;
    implicit.at = at;
    decls_.push_back(implicit);
    undeclared_.insert(name);
    out_.shapes.push_back(name);
    return shapeIds_[name] = int(out_.shapes.size()) - 1;
  }

  // -------------------------------------------------------------------------------------------
  // 2. Seed bytes
  // -------------------------------------------------------------------------------------------

  // The bytes an argument list contributes: each argument in a parenthesis, then the list.
  std::string argBytes(const std::vector<ExprP>& args) {
    std::string b;
    for (const auto& a : args) b += bytes(*a) + hotbits("paren");
    return b + hotbits("cons");
  }

  // A call of the design's function `fn`: its arguments (none: nothing), then its name as its
  // definition writes it.
  std::string functionBytes(const Definition& fn, const std::vector<ExprP>& args) {
    return (args.empty() ? std::string() : argBytes(args)) + asWritten(fn.name, fn.written);
  }

  std::string bytes(const Expr& e) {
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

  // -------------------------------------------------------------------------------------------
  // 3. Expressions → C++
  // -------------------------------------------------------------------------------------------

  // A number as written: a trailing % divides it by 100.
  static double numberValue(const std::string& text) {
    std::string t = text;
    bool percent = !t.empty() && t.back() == '%';
    if (percent) t.pop_back();
    double v = std::strtod(t.c_str(), nullptr);
    if (percent) v /= 100.0;
    return v;
  }
  static std::string number(const std::string& text) { return literal(numberValue(text)); }
  static std::string literal(double v) {
    char b[64];
    std::snprintf(b, sizeof b, "%a", v);
    return std::string("(") + b + ")";
  }

  // Sequences the parts of impure operands: C++ leaves the order of operands open, Context Free
  // draws left to right. `$k` in `combine` is operand k.
  std::string ordered(const std::vector<std::string>& operands, const std::string& combine,
                      bool pure) {
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

  // Translates `e` only to learn what it is (its width, whether it is constant). Translating an
  // expression again writes the same C++ (a rand_static() keeps its number, staticOf).
  Value probe(const Expr& e) { return expr(e); }
  int staticOf(const Expr& e) {
    auto it = staticIndex_.find(&e);
    return it != staticIndex_.end() ? it->second : staticIndex_[&e] = statics_++;
  }

  // The statements `f` writes, as text (for a statement expression).
  std::string captured(const std::function<void()>& f) {
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
  void hoist(Value& v) {
    for (auto& p : v.parts) {
      std::string t = temp();
      v.pre += "const double " + t + " = " + p + "; ";
      p = t;
    }
  }

  // Values taken left to right, their numbers in one list. When `settle`, or when one of them
  // has statements to run first, the numbers that draw random numbers are computed first too, in
  // order: each is drawn once, in its place.
  Value joined(std::vector<Value> values, bool settle) {
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
  Value numbers(const Expr& e) {
    Value v = expr(e);
    if (v.adjustment) fail(e.at, "an adjustment is not a number");
    return v;
  }
  // One number, as one C++ expression.
  Value scalar(const Expr& e) {
    Value v = numbers(e);
    if (v.parts.size() != 1) fail(e.at, "a number is expected here, this has " + std::to_string(v.parts.size()) + " values");
    return single(std::move(v));
  }
  static Value single(Value v) {
    if (!v.pre.empty()) v.parts[0] = "({ " + v.pre + v.parts[0] + "; })";
    v.pre.clear();
    return v;
  }
  // A value's numbers for statements: its own statements written first.
  std::vector<std::string> emitted(Value v) {
    if (!v.pre.empty()) line(v.pre);
    return v.parts;
  }
  // An adjustment value as a __cf_State (merged from the identity, as Context Free stores one).
  std::string adjustmentState(const Value& v) {
    std::string t = temp();
    return "({ __cf_State " + t + "; __cf_identity(&" + t + "); " + captured([&] { v.apply(t, true); }) + t + "; })";
  }

  // A number written as a constant where Context Free needs one when it reads the design.
  double constantNumber(const Expr& e, const std::string& what) {
    if (e.kind == Expr::Paren) return constantNumber(*e.args[0], what);
    if (e.kind == Expr::Unary && e.text == "-") return -constantNumber(*e.args[0], what);
    if (e.kind == Expr::Unary && e.text == "+") return constantNumber(*e.args[0], what);
    if (e.kind != Expr::Number) fail(e.at, what + " must be a number written here for lcjit");
    return numberValue(e.text);
  }

  // An adjustment variable or parameter: its value applied or merged.
  Value adjustmentVariable(const std::string& cpp, const Binding& b) {
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

  Value expr(const Expr& e) {
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
  Value vectorOperation(const Expr& e, Value l, Value r) {
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
  Value index(const Expr& e) {
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
  Value let(const Expr& e) {
    // The definitions' code, binding their names in a new scope (left for the caller to pop).
    auto define = [this, &e](bool& constant, bool& pure) {
      std::string code;
      scopes_.emplace_back();
      for (size_t k = 0; k + 1 < e.args.size(); ++k) {
        Value val = expr(*e.args[k]);
        std::string name = "v_" + identifier(e.names[k]) + "_" + std::to_string(temp_++);
        Binding bound{Binding::Local, name, int(val.parts.size()), val.constant};
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
  Value adjustmentLiteral(const Adjustment& a) {
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

  double settingNumber(const Definition& def);

  std::string flag(const Expr& e) { return number(std::to_string(flagNumber(e))); }

  int flagNumber(const Expr& e) {
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

  // The arguments of a call, left to right: numbers, and adjustments (as __cf_State
  // expressions), with statements to run first. `settled`: each is computed once, in order, by
  // the statements (or draws nothing), so they may be used in any order.
  struct Arguments {
    std::vector<std::string> items;
    std::vector<bool> adjustment;
    std::string pre;
    bool constant = true, pure = true, settled = false;
  };
  Arguments arguments(const std::vector<Value>& values, bool settle = false) {
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
  std::string combined(const Arguments& a, const std::string& combine) {
    std::string r = ordered(a.items, combine, a.pure || a.settled);
    return a.pre.empty() ? r : "({ " + a.pre + r + "; })";
  }
  // A parameter block of `shape`'s parameters from the arguments, as one C++ expression bound
  // by `use` ($b: the block).
  std::string block(const Arguments& a, int count, const std::string& use, const Place& at, const std::string& name) {
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

  Value call(const Expr& e) {
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
      Arguments a = arguments(args, true);
      std::string r = block(a, count, "__cf_bind(c, " + std::to_string(id->second) + ", $b)", e.at, f);
      return {{combined(a, r)}, constant, pure};
    }
    numeric();
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
      return wrap("__cf_fn1(c, " + it->second + ", " + (n == 0 ? std::string("1.0") : all.parts[0]) + ")");
    }
    if (auto it = kFunctions2.find(f); it != kFunctions2.end()) {
      if (n != 2) fail(e.at, f + "() takes two numbers");
      return wrap(ord(all.parts, "__cf_fn2(c, " + it->second + ", $0, $1)"));
    }
    fail(e.at, "'" + f + "' is not a function lcjit knows");
  }

  // A call of function `b` of the design with the arguments `exprs` (their values `args`).
  Value userCall(const Binding& fb, std::vector<Value> args, const std::vector<ExprP>& exprs, const Place& at) {
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
  int functionWidth(const Definition& fn) {
    if (fn.type.rfind("vector", 0) == 0) return std::atoi(fn.type.c_str() + 6);
    return 1;
  }

  // The C++ signature of a function of the design, without its closing parenthesis: a number's
  // or a vector's function returns it; an adjustment's applies its adjustment to `state` (or
  // merges it in). A parameter is a number, a vector's numbers one by one, or an adjustment.
  std::string functionSignature(const Definition& fn, const std::string& name) {
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
  Value choice(const Expr& e, std::vector<Value> args) {
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

  // -------------------------------------------------------------------------------------------
  // 4. Adjustments
  // -------------------------------------------------------------------------------------------

  struct PreparedTerm {
    std::string kind;  // x, y, z, xyz, s, sizexyz, zsize, r, skew, f, trans, h, sat, b, a, blend, time, timescale, |h …
    std::vector<const Expr*> args;
    Place at;
    bool targetForm = false;
  };

  static void flattenArgs(const Term& t, std::vector<const Expr*>& out) {
    for (const auto& a : t.args) {
      if (a->kind == Expr::List)
        for (const auto& x : a->args) out.push_back(x.get());
      else
        out.push_back(a.get());
    }
  }

  // The numbers an argument gives (0 for an adjustment).
  int widthOf(const Expr* e) {
    Value v = probe(*e);
    return v.adjustment ? 0 : int(v.parts.size());
  }
  int widthOf(const std::vector<const Expr*>& args) {
    int n = 0;
    for (const Expr* e : args) n += widthOf(e);
    return n;
  }

  // Context Free's preparation before seeds: `x A y B` (A one number) become one x term; x and s
  // with three numbers split into a z (or zsize) term, then the two-valued one, when the
  // arguments part into two numbers and the rest (else they stay xyz, sizexyz).
  std::vector<PreparedTerm> prepare(const Adjustment& a) {
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

  std::string termBytes(const PreparedTerm& t) {
    std::string b;
    for (const Expr* e : t.args) b += bytes(*e);
    if (t.args.size() > 1 || (t.args.size() == 1 && t.args[0]->kind == Expr::List)) b += hotbits("cons");
    std::string word = t.kind;
    if (t.targetForm) word += "|";
    return b + hotbits(word);
  }

  std::string adjustmentBytes(const std::vector<PreparedTerm>& terms) {
    std::string b;
    for (const auto& t : terms) b += termBytes(t);
    return b;
  }

  static int canonicalRank(const std::string& k) {
    static const std::map<std::string, int> kRank = {{"x", 0}, {"y", 1}, {"z", 2}, {"r", 3}, {"s", 4},
                                                     {"zsize", 5}, {"skew", 6}, {"f", 7}, {"trans", 8}};
    auto it = kRank.find(k);
    return it == kRank.end() ? -1 : it->second;
  }
  static int termClass(const std::string& k) {
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
  static std::string termEnum(const PreparedTerm& t) {
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
  static std::vector<PreparedTerm> canonical(std::vector<PreparedTerm> terms) {
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

  // A constant adjustment value merged into `state` as Context Free folds one (into an
  // adjustment, or a constant variable): its folded part only, without the terms it keeps for the
  // run (a colour value set twice).
  bool foldedOnly_ = false;
  void foldedValue(const Value& v, const std::string& state) {
    foldedOnly_ = true;
    v.apply(state, true);
    foldedOnly_ = false;
  }

  // An adjustment variable `name` (its __cf_State declared by the caller) given adjustment value
  // `v`, written `value`: made from the identity here (a constant value folded, another applied),
  // and bound. Context Free keeps `name = [ … ]` as the adjustment; another expression only when
  // it is constant. A definition's seed is its name's as written.
  Binding adjustmentVariable(const Value& v, const Expr& value, const std::string& name, Binding::Kind kind,
                             uint64_t seed) {
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
  Value termValue(const PreparedTerm& t) {
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
  static unsigned termColours(const std::string& kind, int count) {
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
  uint64_t applyAdjustment(const Adjustment& a, std::vector<PreparedTerm> terms, const std::string& state,
                           bool merge = false) {
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

  // -------------------------------------------------------------------------------------------
  // 5. Elements
  // -------------------------------------------------------------------------------------------

  void body(const Body& b) {
    for (const auto& e : b) element(*e);
  }

  void element(const Element& e) {
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
  bool geometryOnly(const Adjustment& a) {
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
  void transform(const Element& e) {
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
  std::string adjustmentTemp(const Value& v) {
    std::string t = temp();
    line("__cf_State " + t + ";");
    line("__cf_identity(&" + t + ");");
    v.apply(t, true);
    return t;
  }

  // The parameter block of a shape's arguments (numbers; an adjustment in a __cf_State's room),
  // evaluated in order: its name and the numbers it holds.
  std::pair<std::string, int> argumentBlock(const std::vector<ExprP>& args) {
    std::vector<std::pair<std::string, bool>> items;
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
        line("const double " + t + " = " + p + ";");
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
  size_t seedPlaceholder() {
    size_t at = code_.size();
    line("c->cur ^= @SEED@;");
    return at;
  }
  void patchSeed(size_t at, uint64_t seed) {
    size_t p = code_.find("@SEED@", at);
    code_.replace(p, 6, hex64(seed));
  }

  void define(const Element& e) {
    Value v = expr(*e.value);
    std::string name = "v_" + identifier(e.name) + "_" + std::to_string(temp_++);
    if (v.adjustment) {
      const uint64_t seed = seedOf(kSeedBase, asWritten(e.name, e.nameWritten));
      if (!v.constant) line("c->cur ^= " + hex64(seed) + ";");
      line("__cf_State " + name + ";");
      scopes_.back()[e.name] = adjustmentVariable(v, *e.value, name, Binding::Local, seed);
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
  }

  void replacement(const Element& e) {
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
        auto [block, count] = argumentBlock(e.args);
        if (count != paramCount)
          fail(e.shapeAt, "shape '" + e.shape + "' takes " + std::to_string(paramCount) + " parameter values, " +
                              std::to_string(count) + " given");
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

  void loop(const Element& e) {
    scopes_.emplace_back();  // the index is a name in the loop's adjustment
    if (!e.name.empty()) scopes_.back()[e.name] = {Binding::Local, "0.0", 1, false};
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
    if (!e.name.empty()) scopes_.back()[e.name] = {Binding::Local, index, 1, false};
    body(e.body);
    scopes_.pop_back();
    // The loop's adjustment sees the index (`loop i = 1, 5 [x i]`), as it is in this pass, but
    // not the body's names.
    scopes_.emplace_back();
    if (!e.name.empty()) scopes_.back()[e.name] = {Binding::Local, index, 1, false};
    patchSeed(seedAt, seed ^ applyAdjustment(e.adjustment, terms, frame));
    scopes_.pop_back();
    line(index + " += " + step + ";");
    --indent_;
    line("}");
    line("c->frame = &" + frame + ";");
    scopes_.emplace_back();
    if (!e.name.empty()) scopes_.back()[e.name] = {Binding::Local, index, 1, false};
    body(e.otherwise);
    scopes_.pop_back();
    leavePathOps(pathOps);
    line("c->frame = " + outer + ";");
    --indent_;
    line("}");
  }

  // -------------------------------------------------------------------------------------------
  // 7. Paths
  // -------------------------------------------------------------------------------------------

  // What an element or body holds, as Context Free classes them: path operations, path commands,
  // replacements (ORed). A loop of operations only transforms them by its frame.
  enum { kOps = 1, kCommands = 2, kReplacements = 4 };

  int bodyKind(const Body& b) {
    int k = 0;
    for (const auto& e : b) k |= elementKind(*e);
    return k;
  }
  int elementKind(const Element& e) {
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
  int pathBodyOf(int shape) {
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
  int subpathKind(const Element& e) {
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
  std::string enterPathOps(const Element& loop, const std::string& frame) {
    if (!inPath_ || (bodyKind(loop.body) | bodyKind(loop.otherwise)) != kOps) return {};
    std::string saved = temp();
    line("int " + saved + " = __cf_pathEnterOps(c, &" + frame + ");");
    return saved;
  }
  void leavePathOps(const std::string& saved) {
    if (!saved.empty()) line("__cf_pathLeaveOps(c, " + saved + ");");
  }

  // A CF:: flag, or a sum of them (flags combine with +).
  bool isFlag(const Expr& e) const {
    if (e.kind == Expr::Name) return e.text.rfind("CF::", 0) == 0 && e.text != "CF::Infinity";
    if (e.kind == Expr::Paren) return isFlag(*e.args[0]);
    if (e.kind == Expr::Binary && e.text == "+") return isFlag(*e.args[0]) && isFlag(*e.args[1]);
    return false;
  }
  int flagsOf(const Expr& e) {
    if (e.kind == Expr::Paren) return flagsOf(*e.args[0]);
    if (e.kind == Expr::Binary) return flagsOf(*e.args[0]) | flagsOf(*e.args[1]);
    return flagNumber(e);
  }

  void pathOp(const Element& e) {
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
  void pathCommand(const Element& e) {
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
  void subpath(const Element& e) {
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
      if (id >= 4)
        for (const auto& p : decls_[size_t(id - 4)].params) paramCount += p.width;
    }
    if (e.reuseParams) {
      params = "p";
    } else if (e.hasArgs && !e.args.empty()) {
      spec += argBytes(e.args);
      auto [block, count] = argumentBlock(e.args);
      if (!variable && count != paramCount)
        fail(e.shapeAt, "path '" + e.shape + "' takes " + std::to_string(paramCount) + " parameter values, " +
                            std::to_string(count) + " given");
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

  // -------------------------------------------------------------------------------------------
  // 8. Picture settings
  // -------------------------------------------------------------------------------------------

  std::map<std::string, const Definition*> settings_;  // the first definition of each

  // Records a setting this section compiles; false for the others.
  bool pictureSetting(const Definition& def) {
    static const std::set<std::string> kNames = {"CF::Tile",  "CF::Size",  "CF::Symmetry",   "CF::BorderFixed",
                                                 "CF::BorderDynamic", "CF::Color", "CF::Alpha", "CF::ColorDepth",
                                                 "CF::StartShape"};
    if (!kNames.count(def.name)) return false;
    settings_.emplace(def.name, &def);
    return true;
  }
  const Expr* setting(const std::string& name) const {
    auto it = settings_.find(name);
    return it == settings_.end() ? nullptr : it->second->value.get();
  }

  std::string placeString(const Place& at) const {
    std::string text = d_.file + ":" + std::to_string(at.line) + ":" + std::to_string(at.column), out = "\"";
    for (char ch : text) {
      if (ch == '"' || ch == '\\') out += '\\';
      out += ch;
    }
    return out + "\"";
  }

  // Whether Context Free can evaluate `e` when it reads the design (CF::Tile and CF::Size must be
  // such): no random numbers, no functions of the design, only constant names.
  bool constantExpr(const Expr& e) const {
    switch (e.kind) {
      case Expr::Number: return true;
      case Expr::Name: {
        if (e.text.rfind("CF::", 0) == 0) return true;
        const Binding* b = lookup(e.text);
        return b ? b->constant && b->kind != Binding::Function : shapeIds_.count(e.text) > 0;
      }
      case Expr::Binary:
        if (e.text == ".." || e.text == "+/-") return false;
        break;
      case Expr::Call: {
        const Binding* b = lookup(e.text);
        if ((b && b->kind == Binding::Function) || e.text == "rand" || e.text == "randint" ||
            e.text.rfind("rand::", 0) == 0 || e.text.rfind("randint::", 0) == 0)
          return false;
        break;
      }
      case Expr::Modification:
        for (const auto& t : e.adjustment->terms)
          for (const auto& a : t.args)
            if (!constantExpr(*a)) return false;
        return true;
      default: break;
    }
    for (const auto& a : e.args)
      if (!constantExpr(*a)) return false;
    return true;
  }

  // Code setting `state` (a fresh identity) to adjustment `e`; a setting's adjustment.
  void settingAdjustment(const Expr& e, const std::string& name, const std::string& state) {
    if (e.kind != Expr::Modification) fail(e.at, name + " must be an adjustment: [ … ]");
    line("__cf_identity(&" + state + ");");
    applyAdjustment(*e.adjustment, prepare(*e.adjustment), state);
  }

  // The settings' code, run by the start function after the global definitions: the values in
  // __cf_Settings, handed to the engine (which then computes the background).
  std::string settingsCode() {
    code_.clear();
    indent_ = 1;
    scopes_.clear();
    scopes_.emplace_back();
    line("{");
    ++indent_;
    line("__cf_Settings _set;");
    line("__builtin_memset(&_set, 0, sizeof _set);");
    for (const char* name : {"CF::Tile", "CF::Size"}) {
      const Expr* e = setting(name);
      if (!e) continue;
      if (!constantExpr(*e)) fail(e->at, "This expression must be constant");
      std::string field = std::string(name) == "CF::Tile" ? "tile" : "size";
      line("_set.has" + std::string(field == "tile" ? "Tile" : "Size") + " = 1;");
      line("_set." + field + "At = " + placeString(e->at) + ";");
      settingAdjustment(*e, name, "_set." + field);
    }
    // Numbers, in the order Context Free reads them: the borders, then the symmetry list.
    const std::pair<const char*, const char*> numbers[] = {{"CF::BorderFixed", "BorderFixed"},
                                                           {"CF::BorderDynamic", "BorderDynamic"},
                                                           {"CF::Color", "Colour"},
                                                           {"CF::Alpha", "Alpha"},
                                                           {"CF::ColorDepth", "ColourDepth"}};
    for (const auto& [name, field] : numbers) {
      const Expr* e = setting(name);
      if (!e) continue;
      Value v = scalar(*e);
      std::string lower = field;
      lower[0] = char(std::tolower(lower[0]));
      line("_set.has" + std::string(field) + " = 1;");
      line("_set." + lower + " = " + v.parts[0] + ";");
    }
    if (const Expr* e = setting("CF::Symmetry")) {
      std::vector<std::string> items = symmetryItems(*e, false);
      std::string list;
      for (auto& i : items) list += i + ", ";
      line("const __cf_SymmetryItem _sym[] = {" + list + "};");
      line("_set.symmetryCount = " + std::to_string(items.size()) + ";");
      line("_set.symmetry = _sym;");
    }
    line("__cf_configure(c, &_set);");
    --indent_;
    line("}");
    scopes_.clear();
    return code_;
  }

  // A symmetry list's elements as __cf_SymmetryItem initialisers, their values computed in order
  // by code written before them. In a transform statement (`statement`), adjustments other than
  // transforms are not elements (the statement applies them itself).
  std::vector<std::string> symmetryItems(const Expr& list, bool statement) {
    std::vector<const Expr*> elements;
    if (list.kind == Expr::List)
      for (const auto& a : list.args) elements.push_back(a.get());
    else
      elements.push_back(&list);
    std::vector<std::string> items;
    for (const Expr* x : elements) {
      std::string values = temp();
      std::string kind, count;
      if (x->kind == Expr::Name && x->text.rfind("CF::", 0) == 0 && x->text != "CF::Infinity") {
        kind = "__cf_SymmetryFlag";
        count = "1";
        line("static const double " + values + "[] = {" + flag(*x) + "};");
      } else if (Value v = probe(*x); x->kind == Expr::Modification || v.adjustment) {
        // [ … ], or a constant adjustment variable: a transform when it only moves, turns, sizes.
        constexpr int kGeometry = 1 | 4;  // as geometryOnly
        if (x->kind != Expr::Modification && !v.constant) fail(x->at, "Wrong type");
        if (x->kind == Expr::Modification ? !geometryOnly(*x->adjustment) : (v.info.classes & ~kGeometry) != 0) {
          if (statement) continue;
          fail(x->at, "At least one term was invalid");
        }
        std::string state = temp();
        line("__cf_State " + state + ";");
        if (x->kind == Expr::Modification) {
          settingAdjustment(*x, "CF::Symmetry", state);
        } else {
          line("__cf_identity(&" + state + ");");
          foldedValue(v, state);
        }
        kind = "__cf_SymmetryTransform";
        count = "6";
        line("const double " + values + "[] = {" + state + ".sx, " + state + ".shy, " + state + ".shx, " + state + ".sy, " +
             state + ".tx, " + state + ".ty};");
      } else {
        std::vector<std::string> numbers = emitted(this->numbers(*x));
        kind = "__cf_SymmetryNumbers";
        count = std::to_string(numbers.size());
        std::string parts;
        for (auto& p : numbers) parts += p + ", ";
        line("const double " + values + "[] = {" + parts + "};");
      }
      items.push_back("{" + kind + ", " + count + ", " + values + ", " + placeString(x->at) + "}");
    }
    return items;
  }
};

// ---------------------------------------------------------------------------------------------
// 6. The unit
// ---------------------------------------------------------------------------------------------

// A setting's number, read when the design is read: a number written as a constant.
double Translator::settingNumber(const Definition& def) { return constantNumber(*def.value, def.name); }

Translation Translator::run() {
  out_.shapes = {"CIRCLE", "SQUARE", "TRIANGLE", "FILL"};
  for (int k = 0; k < 4; ++k) shapeIds_[out_.shapes[size_t(k)]] = k;
  decls_ = d_.shapes;
  for (const auto& s : d_.shapes) {
    // A design's own shape named like a primitive (rule TRIANGLE { … }) takes the name: its
    // rules run where the design names it, as in Context Free.
    if (shapeIds_.count(s.name) && shapeIds_[s.name] >= 4) fail(s.at, "shape '" + s.name + "' is declared twice");
    shapeIds_[s.name] = int(out_.shapes.size());
    out_.shapes.push_back(s.name);
  }
  // Context Free's predefined constants: π, and symbols that name the primitives (● ■ ▲ …).
  globals_["\xCF\x80"] = {Binding::Global, literal(M_PI), 1, true};
  const std::pair<int, std::vector<const char*>> kSymbols[] = {
      {0, {"\xE2\x9A\xAB", "\xE2\x97\x8F", "\xE2\xAC\xA4"}},
      {1, {"\xE2\xAC\x9B", "\xE2\x97\xBC", "\xE2\x97\xBE", "\xEF\xBF\xAD", "\xE2\x96\xA0"}},
      {2, {"\xE2\x96\xB2", "\xE2\x96\xB4"}}};
  for (const auto& [primitive, names] : kSymbols)
    for (const char* name : names) globals_[name] = {Binding::Global, std::to_string(primitive) + ".0", 1, true};
  std::string unit = "// Generated by lcjit from " + d_.file + "\n#include \"lcjit/cfdg.h\"\nnamespace {\n";
  std::string start;

  // Of a setting written more than once, the one written least deep in imports counts, the first
  // of those; CF::Impure is the last one read (Context Free's rules).
  std::map<std::string, const Definition*> counting;
  const Definition* impure = nullptr;
  for (const auto& def : d_.definitions) {
    if (!def.config) continue;
    const Definition*& first = counting[def.name];
    if (!first || def.depth < first->depth) first = &def;
    if (def.name == "CF::Impure") impure = &def;
  }
  const Definition* maxNatural = counting.count("CF::MaxNatural") ? counting.at("CF::MaxNatural") : nullptr;
  if (maxNatural) {
    maxNatural_ = settingNumber(*maxNatural);
    if (maxNatural_ < 1) fail(maxNatural->value->at, "CF::MaxNatural must be >= 1");
    if (maxNatural_ >= 9007199254740992.0) fail(maxNatural->value->at, "CF::MaxNatural must be < 9007199254740992");
  }
  if (impure) impure_ = settingNumber(*impure) != 0;

  // Functions may call functions written after them: all are known, and declared, first.
  for (const auto& def : d_.definitions) {
    if (!def.isFunction) continue;
    Binding b{Binding::Function, "f_" + identifier(def.name), 1, false};
    b.function = &def;
    globals_[def.name] = b;
    unit += functionSignature(def, b.cpp) + ");\n";
  }

  // Globals and functions, in file order.
  for (const auto& def : d_.definitions) {
    if (def.config && counting.at(def.name) != &def) {
      // Not read, but a sat term in it still makes the picture colour, as Context Free's reading does.
      if (def.value->kind == Expr::Modification)
        for (const Term& t : def.value->adjustment->terms) usesSat_ |= t.word == "sat";
      continue;
    }
    if (def.config && pictureSetting(def)) continue;  // section 8
    if (def.config && def.name == "CF::Background") {
      background_ = def.value.get();  // the picture's background: drawn by the canvas
      continue;
    }
    if (def.config && (def.name == "CF::Time" || def.name == "CF::FrameTime" || def.name == "CF::Frame")) {
      timing_[def.name] = &def;  // the timing function, below
      continue;
    }
    if (def.config) {
      // Settings are constants read at translation time.
      double v = settingNumber(def);
      if (def.name == "CF::MinimumSize") out_.settings.minimumSize = v;
      else if (def.name == "CF::MaxShapes") out_.settings.maxShapes = v;
      else if (def.name == "CF::AllowOverlap" || def.name == "CF::Impure" || def.name == "CF::MaxNatural") {
      } else fail(def.at, def.name + " is not supported by lcjit yet");
      continue;
    }
    if (def.isFunction) {
      std::string name = globals_.at(def.name).cpp;
      code_.clear();
      indent_ = 1;
      scopes_.emplace_back();
      const bool adjustment = def.type == "adjustment";
      const int width = functionWidth(def);
      std::string signature = functionSignature(def, name);
      for (const auto& p : def.params) {
        // A vector's numbers, passed one by one, are gathered in an array.
        std::string pn = "a_" + identifier(p.name);
        Binding bound{Binding::Local, pn, p.width, false};
        bound.adjustment = p.type == "adjustment";
        if (!bound.adjustment && p.width > 1) {
          std::string list;
          for (int k = 0; k < p.width; ++k) list += pn + "_" + std::to_string(k) + ", ";
          line("const double " + pn + "[" + std::to_string(p.width) + "] = {" + list + "};");
        }
        scopes_.back()[p.name] = bound;
      }
      if (adjustment) {
        Value v = expr(*def.value);
        if (!v.adjustment) fail(def.at, "Mismatch between declared and defined type of user function");
        line("if (merge) {");
        v.apply("(*state)", true);
        line("} else {");
        v.apply("(*state)", false);
        line("}");
        scopes_.pop_back();
        unit += signature + ") {\n  (void)c;\n" + code_ + "}\n";
        continue;
      }
      Value v = numbers(*def.value);
      if (int(v.parts.size()) != width)
        fail(def.at, "Mismatch between declared and defined vector length of user function");
      std::string result;
      if (width == 1) {
        result = single(v).parts[0];
      } else {
        for (auto& p : emitted(v)) result += p + ", ";
        result = "__cf_V<" + std::to_string(width) + ">{{" + result + "}}";
      }
      scopes_.pop_back();
      unit += signature + ") {\n  (void)c;\n" + code_ + "  return " + result + ";\n}\n";
      continue;
    }
    code_.clear();
    indent_ = 1;
    Value v = expr(*def.value);
    std::string name = "g_" + identifier(def.name);
    if (!v.constant) line("c->cur ^= " + hex64(seedOf(kSeedBase, asWritten(def.name, def.written))) + ";");
    if (v.adjustment) {
      unit += "__cf_State " + name + ";\n";
      globals_[def.name] =
          adjustmentVariable(v, *def.value, name, Binding::Global, seedOf(kSeedBase, asWritten(def.name, def.written)));
      start += code_;
      continue;
    }
    std::vector<std::string> parts = emitted(v);
    Binding b{Binding::Global, name, int(parts.size()), v.constant};
    unit += "double " + name + (parts.size() > 1 ? "[" + std::to_string(parts.size()) + "]" : "") + ";\n";
    for (size_t k = 0; k < parts.size(); ++k)
      line(name + (parts.size() > 1 ? "[" + std::to_string(k) + "]" : "") + " = " + parts[k] + ";");
    start += code_;
    globals_[def.name] = b;
  }

  // Rules.
  std::string rules;
  for (size_t r = 0; r < d_.rules.size(); ++r) {
    const Rule& rule = d_.rules[r];
    int id = shapeId(rule.shape, rule.at);
    inPath_ = rule.isPath;
    currentRule_ = r;
    const ShapeDecl& decl = decls_[size_t(id - 4)];
    code_.clear();
    indent_ = 1;
    scopes_.clear();
    scopes_.emplace_back();
    int offset = 0;
    for (const auto& p : decl.params) {
      Binding b{Binding::Param, std::to_string(offset), p.width, false};
      b.shape = p.type == "shape";
      b.adjustment = p.type == "adjustment";
      scopes_.back()[p.name] = b;
      offset += p.width;
    }
    body(rule.body);
    inPath_ = false;
    scopes_.clear();
    unit += "void rule_" + std::to_string(r) + "(__cf_Ctx* c, const double* p) {\n  (void)p;\n" + code_ + "}\n";
    char w[64];
    std::snprintf(w, sizeof w, "%a", rule.weight);
    rules += "  {" + std::to_string(id) + ", " + w + ", " + (rule.percent ? "1" : "0") + ", rule_" + std::to_string(r) + "},\n";
  }

  // The settings, then the start shape: named, or the first shape declared without parameters.
  std::string settings = settingsCode();
  std::string startName = d_.startShape;
  Place startAt = d_.startAt;
  const std::vector<ExprP>* startArgs = &d_.startArgs;
  const Adjustment* startAdjustment = &d_.startAdjustment;
  bool startHasAdjustment = d_.startHasAdjustment;
  Adjustment noAdjustment;
  std::string startBytes;  // the start shape's bytes in its seed: its name, as a rule (its arguments too)
  if (const Expr* e = setting("CF::StartShape"); e && startName.empty()) {
    // CF::StartShape = shape[(arguments)][, adjustment]: always with an adjustment (an empty one
    // if none), which its seed takes.
    const Expr* spec = e->kind == Expr::List ? e->args[0].get() : e;
    if (e->kind == Expr::List && e->args.size() > 2)
      fail(e->at, "CF::StartShape expression must have the form shape_spec or shape_spec, [modification]");
    if (spec->kind != Expr::Name && spec->kind != Expr::Call)
      fail(spec->at, "CF::StartShape must start with a shape specification");
    startName = spec->text;
    // Here the shape's arguments count in its seed, as in a replacement.
    startBytes = spec->kind == Expr::Call && !spec->reuseParams && !spec->args.empty() ? startName + argBytes(spec->args)
                                                                                       : startName;
    startAt = spec->at;
    startArgs = &spec->args;
    startHasAdjustment = true;
    startAdjustment = &noAdjustment;
    if (e->kind == Expr::List) {
      const Expr* m = e->args[1].get();
      if (m->kind != Expr::Modification) fail(m->at, "CF::StartShape second term must be a modification");
      startAdjustment = m->adjustment.get();
    }
  }
  if (startName.empty()) {
    for (const auto& s : d_.shapes)
      if (s.params.empty()) {
        startName = s.name;
        startAt = s.at;
        break;
      }
    if (startName.empty()) fail({1, 1}, "no start shape: write `startshape NAME`");
  }
  code_.clear();
  indent_ = 1;
  scopes_.clear();
  scopes_.emplace_back();
  const Binding* startValue = lookup(startName);
  if (startValue && startValue->kind != Binding::Global) startValue = nullptr;
  int startId = startValue ? -1 : shapeId(startName, startAt);
  std::string params = "nullptr";
  if (!startArgs->empty()) params = argumentBlock(*startArgs).first;
  auto terms = prepare(*startAdjustment);
  // With an adjustment (even an empty one) the start shape's seed is its terms' bytes mixed into
  // the base seed, xor the base seed, then its name's bytes (Context Free mixes the terms into the
  // adjustment before the start shape takes it); without, its name's bytes from the base seed.
  uint64_t seed = seedOf(kSeedBase, startName);
  if (startBytes.empty()) startBytes = startName;
  if (startHasAdjustment) {
    int position = 0;
    seed = mixBytes(kSeedBase, adjustmentBytes(terms), position) ^ kSeedBase;
    seed = mixBytes(seed, startBytes, position);
  }
  size_t seedAt = seedPlaceholder();
  line("c->cur = __cf_step(c->cur);");
  line("__cf_State s;");
  line("__cf_identity(&s);");
  line("s.colour[3] = 1; s.target[3] = 1;");
  line("s.tbegin = 0; s.tend = 1;");
  line("c->frame = &s;");
  if (startHasAdjustment) seed ^= applyAdjustment(*startAdjustment, std::move(terms), "s");
  patchSeed(seedAt, seed);
  if (startValue) line("__cf_start_value(c, " + startValue->cpp + ", &s);");
  else line("__cf_start(c, " + std::to_string(startId) + ", &s, " + params + ");");
  unit += "void start(__cf_Ctx* c) {\n" + start + settings + code_ + "}\n";

  // The background: white changed by CF::Background.
  std::string backgroundFn = "nullptr";
  bool backgroundAlpha = false;
  if (background_) {
    if (background_->kind != Expr::Modification) fail(background_->at, "CF::Background must be an adjustment: [ b -1 ]");
    code_.clear();
    indent_ = 1;
    scopes_.clear();
    scopes_.emplace_back();
    auto backgroundTerms = prepare(*background_->adjustment);
    for (const auto& t : backgroundTerms) backgroundAlpha |= t.kind == "a";
    applyAdjustment(*background_->adjustment, std::move(backgroundTerms), "(*s)");
    unit += "void background(__cf_Ctx* c, __cf_State* s) {\n" + code_ + "}\n";
    backgroundFn = "background";
  }

  // The time settings: constants, read before the run (Context Free reads them when it makes
  // its renderer).
  std::string timingFn = "nullptr";
  if (!timing_.empty()) {
    code_.clear();
    indent_ = 1;
    scopes_.clear();
    scopes_.emplace_back();
    line("(void)c;");
    if (auto it = timing_.find("CF::Time"); it != timing_.end()) {
      const Expr& e = *it->second->value;
      if (e.kind != Expr::Modification) fail(e.at, "CF::Time must be an adjustment: [time BEGIN END]");
      if (!constantExpr(e)) fail(e.at, "This expression must be constant");
      line("__cf_State _time;");
      settingAdjustment(e, "CF::Time", "_time");
      line("t->hasTime = 1;");
      line("t->timeBegin = _time.tbegin; t->timeEnd = _time.tend; t->timeScale = _time.tsc;");
      line("t->timeAt = " + placeString(e.at) + ";");
    }
    for (const char* name : {"CF::FrameTime", "CF::Frame"}) {
      auto it = timing_.find(name);
      if (it == timing_.end()) continue;
      const Expr& e = *it->second->value;
      if (!constantExpr(e)) fail(e.at, "This expression must be constant");
      Value v = scalar(e);
      const std::string field = std::string(name) == "CF::Frame" ? "Frame" : "FrameTime";
      line("t->has" + field + " = 1;");
      line("t->" + std::string(field == "Frame" ? "frame" : "frameTime") + " = " + v.parts[0] + ";");
    }
    scopes_.clear();
    unit += "void timing(__cf_Ctx* c, __cf_Timing* t) {\n" + code_ + "}\n";
    timingFn = "timing";
  }

  // The table.
  unit += "const __cf_Shape shapes[] = {\n";
  for (size_t k = 0; k < out_.shapes.size(); ++k) {
    int count = 0;
    bool path = false;
    std::string usedAt = "nullptr";
    int pathBody = 0;
    if (k >= 4) {
      const ShapeDecl& decl = decls_[k - 4];
      for (const auto& p : decl.params) count += p.width;
      path = decl.isPath;
      if (path) pathBody = pathBodyOf(int(k)) & (kOps | kCommands);
      if (undeclared_.count(decl.name))
        usedAt = "\"" + d_.file + ":" + std::to_string(decl.at.line) + ":" + std::to_string(decl.at.column) + "\"";
    }
    unit += "  {\"" + out_.shapes[k] + "\", " + std::to_string(count) + ", " + (path ? "1" : "0") + ", " + usedAt + ", " +
            std::to_string(pathBody) + "},\n";
  }
  unit += "};\nconst __cf_Rule rules[] = {\n" + rules + "  {0, 0, 0, nullptr}\n};\n}  // namespace\n";
  bool colour = usesSat_;
  unit += "extern \"C\" const __cf_Design __cf_design = {__cf_AbiVersion, " + std::to_string(out_.shapes.size()) +
          ", shapes, " + std::to_string(d_.rules.size()) + ", rules, start, " + std::to_string(statics_) + ", " +
          (colour ? "1" : "0") + ", " + (usesTime_ ? "1" : "0") + ", " + backgroundFn + ", " + (usesBlend_ ? "1" : "0") +
          ", " + (backgroundAlpha ? "1" : "0") + ", " + (usesFrameTime_ ? "1" : "0") + ", " + timingFn + "};\n";
  out_.cpp = std::move(unit);
  out_.randStaticCount = statics_;
  return std::move(out_);
}

}  // namespace

llvm::Expected<Translation> translateDesign(const Design& design) {
  try {
    Translator t(design);
    return t.run();
  } catch (TranslateError& e) {
    return llvm::createStringError(design.file + ":" + std::to_string(e.at.line) + ":" + std::to_string(e.at.column) +
                                   ": error: " + e.message);
  }
}

}  // namespace lcjit::frontend::cfdg
