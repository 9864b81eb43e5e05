// How the values of a Context Free design depend on the parameters of the shape or function they
// are written in (Translator.h, section 9), and the rule Context Free makes of it: a number
// parameter of a shape is given a constant, or a parameter as it was given, or a value computed
// without parameters; and a natural parameter (of a shape or a function) a natural number. An
// impure design (CF::Impure) has neither rule. lcjit refuses what Context Free 3.4 refuses, where
// it does, in its words.
#include "frontend/cfdg/Translator.h"

#include <cmath>

namespace lcjit::frontend::cfdg::translate {

// ---------------------------------------------------------------------------------------------
// 9. Purity
// ---------------------------------------------------------------------------------------------

namespace {

Locality both(Locality a, Locality b) { return Locality(a & b); }

// An operator or function applied to a parameter as given computes a new value from it.
Locality computed(Locality a) { return a == kPureNonlocal ? kImpureNonlocal : a; }

// A number written as such (signed, in parentheses): its value.
bool written(const Expr& e, double& v) {
  if (e.kind == Expr::Number) return v = numberValue(e.text), true;
  if (e.kind == Expr::Paren || (e.kind == Expr::Unary && e.text == "+")) return written(*e.args[0], v);
  if (e.kind == Expr::Unary && e.text == "-" && written(*e.args[0], v)) return v = -v, true;
  return false;
}

}  // namespace

// Where Context Free places an expression in an error: where its first operand is, but a signed
// or parenthesized one where what it holds is, and a random range (`a..b`, `a+/-b`) at its
// operator.
const Place& placeOf(const Expr& e) {
  if (e.kind == Expr::Binary && (e.text == ".." || e.text == "+/-")) return e.opAt;
  if (e.kind == Expr::Paren || e.kind == Expr::Unary || e.kind == Expr::Binary || e.kind == Expr::List)
    return placeOf(*e.args[0]);
  return e.at;
}

// The items of a list, or the arguments of a call: theirs ANDed (none: pure local).
Locality Translator::localityOf(const std::vector<ExprP>& list) {
  Locality l = kPureLocal;
  for (const auto& a : list) l = both(l, locality(*a));
  return l;
}

Locality Translator::locality(const Expr& e) {
  switch (e.kind) {
    case Expr::Number: return kPureLocal;
    case Expr::Name: {
      const Binding* b = lookup(e.text);
      return b ? b->locality : kPureLocal;  // CF:: names, shapes: constants
    }
    case Expr::Paren:
    case Expr::List: return localityOf(e.args);
    case Expr::Unary:
    case Expr::Binary: return computed(localityOf(e.args));
    case Expr::Index: {
      // The vector's, and its index's (a stride or a length is a constant).
      const Binding* b = lookup(e.text);
      return both(b ? b->locality : kPureLocal, locality(*e.args[0]));
    }
    case Expr::Let: {
      // The value's, with the names bound to their definitions' localities.
      scopes_.emplace_back();
      for (size_t k = 0; k + 1 < e.args.size(); ++k) {
        Binding bound{Binding::Local, "", 1, false};
        bound.locality = locality(*e.args[k]);
        scopes_.back()[e.names[k]] = bound;
      }
      Locality l = locality(*e.args.back());
      scopes_.pop_back();
      return l;
    }
    case Expr::Modification: {
      Locality l = kPureLocal;
      for (const auto& t : e.adjustment->terms) l = both(l, localityOf(t.args));
      return l;
    }
    case Expr::Call: {
      if (e.text == "if" || e.text == "select") return choiceLocality(e);
      const Binding* b = lookup(e.text);
      if (b && b->kind == Binding::Function) {
        // A function of the design: its arguments' (they are its parameters as given), but a
        // function computing a new value from its parameters computes one from parameters
        // given to it as they were given.
        Locality l = localityOf(e.args);
        if (l == kPureNonlocal && functionLocality(*b->function) == kImpureNonlocal) l = kImpureNonlocal;
        return l;
      }
      if (shapeIds_.count(e.text)) return e.reuseParams ? kPureNonlocal : localityOf(e.args);  // a shape value
      return computed(localityOf(e.args));  // a function of Context Free's
    }
  }
  return kPureLocal;
}

// if()/select(): its selector's and its values' together, as Context Free knows no more of which
// value it gives; when the selector is a constant the choice is known: that value's.
Locality Translator::choiceLocality(const Expr& e) {
  if (e.args.size() < 3) return kPureLocal;  // an error elsewhere
  if (double v; written(*e.args[0], v)) {
    const size_t n = e.args.size() - 1;
    size_t k = e.text == "if" ? (v != 0.0 ? 1 : 2) : v < 1 ? 1 : v >= double(n) ? n : size_t(v) + 1;
    return locality(*e.args[k]);
  }
  if (constantExpr(*e.args[0])) {
    // A constant lcjit does not compute here: the choice that satisfies the most.
    int l = 0;
    for (size_t k = 1; k < e.args.size(); ++k) l |= locality(*e.args[k]);
    return Locality(l);
  }
  return localityOf(e.args);
}

// A function's value's locality, its parameters pure non-local (memoised; while it is being found,
// a call of the function itself counts as pure).
Locality Translator::functionLocality(const Definition& fn) {
  auto known = functionLocality_.find(&fn);
  if (known != functionLocality_.end()) return known->second;
  functionLocality_[&fn] = kPureLocal;
  std::vector<std::map<std::string, Binding>> outer;
  outer.swap(scopes_);  // the function sees its parameters and the globals only
  scopes_.emplace_back();
  for (const auto& p : fn.params) {
    Binding bound{Binding::Local, "", p.width, false};
    bound.locality = kPureNonlocal;
    scopes_.back()[p.name] = bound;
  }
  Locality l = locality(*fn.value);
  scopes_.swap(outer);
  return functionLocality_[&fn] = l;
}

// Whether Context Free knows `e` to be a natural number (an integer from 0 up) when it reads the
// design: a whole number written so, a natural parameter or variable, and what its operators and
// functions keep natural.
bool Translator::natural(const Expr& e) {
  auto all = [this](const std::vector<ExprP>& list) {
    for (const auto& a : list)
      if (!natural(*a)) return false;
    return true;
  };
  switch (e.kind) {
    case Expr::Number: {
      double v = numberValue(e.text);
      return v >= 0 && v < 9007199254740992.0 && v == std::floor(v);  // below 2^53: whole
    }
    case Expr::Name:
    case Expr::Index: {
      const Binding* b = lookup(e.text);
      return b && b->natural;
    }
    case Expr::Paren:
    case Expr::List: return all(e.args);
    case Expr::Unary: return e.text == "!" && all(e.args);
    case Expr::Binary: {
      static const std::set<std::string> kNatural = {"+", "--", "*", "^", "<", ">", "<=", ">=", "==", "<>", "&&", "||", "^^"};
      return kNatural.count(e.text) && all(e.args);
    }
    case Expr::Let: {
      scopes_.emplace_back();
      for (size_t k = 0; k + 1 < e.args.size(); ++k) {
        Binding bound{Binding::Local, "", 1, false};
        bound.natural = natural(*e.args[k]);
        scopes_.back()[e.names[k]] = bound;
      }
      bool n = natural(*e.args.back());
      scopes_.pop_back();
      return n;
    }
    case Expr::Modification: return false;
    case Expr::Call: {
      const std::string& f = e.text;
      if (f == "if" || f == "select") {
        if (e.args.size() < 3) return false;
        if (double v; written(*e.args[0], v)) {
          const size_t n = e.args.size() - 1;
          return natural(*e.args[f == "if" ? (v != 0.0 ? 1 : 2) : v < 1 ? 1 : v >= double(n) ? n : size_t(v) + 1]);
        }
        for (size_t k = 1; k < e.args.size(); ++k)
          if (!natural(*e.args[k])) return false;
        return true;
      }
      const Binding* b = lookup(f);
      if (b && b->kind == Binding::Function) return b->function->type == "natural";
      // Functions that keep natural arguments natural, and those whose values are natural.
      static const std::set<std::string> kKeep = {"mod",    "abs",    "min",     "max",      "bitnot", "bitor",
                                                  "bitand", "bitxor", "bitleft", "bitright", "randint"};
      static const std::set<std::string> kMake = {"factorial", "sg", "isNatural", "div", "divides", "randint::discrete"};
      if (kKeep.count(f)) return all(e.args);
      if (kMake.count(f)) return true;
      if (f == "randint::binomial" || f == "randint::negbinomial") return e.args.size() == 2 && natural(*e.args[0]);
      return false;
    }
  }
  return false;
}

// Whether a loop's index is natural, given its count (end; start, end; or start, end, step):
// all natural, or its start and end natural and its step natural or -1.
bool Translator::naturalLoopIndex(const Expr& count) {
  const Expr* c = &count;
  while (c->kind == Expr::Paren) c = c->args[0].get();
  if (c->kind != Expr::List) return natural(*c);
  const auto& items = c->args;
  if (items.empty() || !natural(*items[0])) return false;
  if (items.size() > 1 && !natural(*items[1])) return false;
  if (items.size() > 2 && !natural(*items[2])) {
    double v;
    return written(*items[2], v) && v == -1.0;
  }
  return true;
}

// Context Free's requirements on the arguments `args` given to `params` (a shape's, or a
// function's): a natural parameter is given a natural number, and (`numbers`: a shape's) a number
// or vector parameter a pure value. An impure design has neither.
void Translator::parameterRequirements(const std::vector<Param>& params, const std::vector<ExprP>& args, bool numbers) {
  if (impure_) return;
  for (size_t k = 0; k < args.size() && k < params.size(); ++k) {
    const std::string& type = params[k].type;
    if (type == "natural" && !natural(*args[k]))
      fail(placeOf(*args[k]), "this expression does not satisfy the natural number requirement");
    if (!numbers || (type != "number" && type.rfind("vector", 0) != 0)) continue;
    Locality l = locality(*args[k]);
    if (l != kPureLocal && l != kPureNonlocal)
      fail(placeOf(*args[k]), "This expression does not satisfy the number parameter requirement");
  }
}

// What must be natural wherever it is written, as the design is read: the operands of proper
// subtraction (`--`), and the arguments of the functions defined on natural numbers only. An
// impure design has no such rule.
void Translator::naturalOperands(const Expr& e) {
  if (impure_) return;
  if (e.kind == Expr::Binary && e.text == "--" && !natural(e))
    fail(placeOf(e), "Proper subtraction operands must be natural");
  static const std::set<std::string> kNaturalOnly = {"factorial", "sg", "isNatural", "div", "divides"};
  if (e.kind == Expr::Call && kNaturalOnly.count(e.text) && !e.args.empty())
    for (const auto& a : e.args)
      if (!natural(*a)) fail(placeOf(*e.args[0]), "function is defined over natural numbers only");
}

// Which of the numbers given to `params` (an adjustment counts as one) go to natural parameters.
std::vector<bool> Translator::naturalSlots(const std::vector<Param>& params) const {
  std::vector<bool> slots;
  for (const auto& p : params) {
    const int n = p.type == "adjustment" ? 1 : p.width;
    for (int k = 0; k < n; ++k) slots.push_back(p.type == "natural");
  }
  return slots;
}

// The arguments `a` (made of `values`, the values of `exprs`) of a call of a shape or function
// with `params`: those given to natural parameters checked (naturalChecked).
void Translator::checkNaturals(const std::vector<Param>& params, const std::vector<ExprP>& exprs,
                               const std::vector<Value>& values, Arguments& a) {
  const std::vector<bool> natural = naturalSlots(params);
  size_t item = 0;
  for (size_t k = 0; k < values.size() && k < exprs.size(); ++k) {
    const size_t n = values[k].adjustment ? 1 : values[k].parts.size();
    for (size_t j = 0; j < n && item < a.items.size(); ++j, ++item)
      if (item < natural.size() && natural[item] && !a.adjustment[item])
        a.items[item] = naturalChecked(a.items[item], placeOf(*exprs[k]));
  }
}

// The value given to a natural parameter, checked as Context Free checks it when the shape or
// function is called: a whole number from 0 to CF::MaxNatural, else an error at the argument.
// An impure design's are not checked.
std::string Translator::naturalChecked(const std::string& value, const Place& at) {
  if (impure_) return value;
  return wholeChecked(value, maxNatural_, at, "Expression does not evaluate to a legal natural number");
}

// `value` as one C++ expression that is it when it is a whole number from 0 to `most`, and
// otherwise fails the run with `message` at `at`.
std::string Translator::wholeChecked(const std::string& value, double most, const Place& at, const std::string& message) {
  const std::string n = temp();
  return "({ const double " + n + " = " + value + "; if (!(" + n + " >= 0.0 && " + n + " <= " + literal(most) + " && " + n +
         " == __builtin_floor(" + n + "))) __cf_fail_at(c, " + placeString(at) + ", \"" + message + "\"); " + n + "; })";
}

}  // namespace lcjit::frontend::cfdg::translate
