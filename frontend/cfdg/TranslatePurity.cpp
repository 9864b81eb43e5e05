// How the values of a Context Free design depend on the parameters of the shape or function they
// are written in (Translator.h, section 9), and the rule Context Free makes of it: a number
// parameter of a shape is given a constant, or a parameter as it was given, or a value computed
// without parameters, unless the design says CF::Impure. lcjit refuses what Context Free 3.4
// refuses, where it does, in its words.
#include "frontend/cfdg/Translator.h"

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

// Where Context Free places an expression in an error: where its first operand is, but a signed
// or parenthesized one where what it holds is, and a random range (`a..b`, `a+/-b`) at its
// operator.
const Place& placeOf(const Expr& e) {
  if (e.kind == Expr::Binary && (e.text == ".." || e.text == "+/-")) return e.opAt;
  if (e.kind == Expr::Paren || e.kind == Expr::Unary || e.kind == Expr::Binary || e.kind == Expr::List)
    return placeOf(*e.args[0]);
  return e.at;
}

}  // namespace

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

// Context Free's number parameter requirement, for the arguments `args` of a shape with `params`:
// each given to a number (or vector) parameter is pure, unless the design is impure. A natural
// parameter has its own requirement instead.
void Translator::numberParameters(const std::vector<Param>& params, const std::vector<ExprP>& args) {
  if (impure_) return;
  for (size_t k = 0; k < args.size() && k < params.size(); ++k) {
    const std::string& type = params[k].type;
    if (type != "number" && type.rfind("vector", 0) != 0) continue;
    Locality l = locality(*args[k]);
    if (l != kPureLocal && l != kPureNonlocal)
      fail(placeOf(*args[k]), "This expression does not satisfy the number parameter requirement");
  }
}

}  // namespace lcjit::frontend::cfdg::translate
