// What the XL front end reads of a model (frontend/xl/Translate.cpp): its modules, the rules of
// its methods, its Java declarations, each as the tokens (Tokens.h) they were written with, so
// that the L+C written from them keeps the user's places. Internal to frontend/xl.
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "frontend/xl/Tokens.h"

namespace lcjit::frontend::xl {

struct Param {
  size_t at;  // its name's token
  std::string type, name;
  bool inherited = false;  // `super.length`: the base's field, set by the module's argument
  std::string fallback;    // its value in a node made without arguments: Java's 0, or the base's
};

// A field a module inherits from the turtle command it extends and does not declare: its value
// when the module is made, C++ in the module's parameters (`laenge`, `10`, `-1`).
struct Inherited {
  std::string name, type;
  std::vector<size_t> value;  // tokens of an `extends` argument; empty: `fallback`
  std::string fallback;
  std::string field;  // the turtle command's field it is (`length`); empty for a field of its own
  // Its value when it comes from a base that is one of the model's modules: C++ pieces, each
  // perhaps the name of one of the module's parameters (replaced by its argument when a node is
  // made). Empty: `value`, else `fallback`.
  std::vector<std::string> pieces;
};

// A Java declaration at the top of the model (or a method in a module's body): a field (`final float angle = 30;`) or a method of
// statements (`static float half(float x) { return x / 2; }`), written as C++ before the rules.
struct Declaration {
  size_t type = 0, name = 0;  // tokens
  bool constant = false;      // `final`
  bool method = false;
  std::vector<std::pair<size_t, size_t>> params;  // a method's: (type, name) tokens
  Range rest;                                     // a field's from its name to `;`; a method's body
};

struct Module {
  size_t keyword = 0, name = 0;
  std::string lcName;  // its name in the L+C: its own, unless lcjit has a module of that name
  std::vector<Param> params;
  std::optional<size_t> base;  // after `extends`
  std::string command;         // the turtle command at the root of its bases (`F`); empty: none
  std::vector<Declaration> methods;  // its body's methods, on its fields
  std::vector<Range> baseArgs;
  std::vector<Inherited> inherited;  // after the parameters, in the L+C module
  size_t fieldCount() const { return params.size() + inherited.size(); }
  std::string fieldName(size_t k) const { return k < params.size() ? params[k].name : inherited[k - params.size()].name; }
  std::string fieldType(size_t k) const { return k < params.size() ? params[k].type : inherited[k - params.size()].type; }
  // The L+C name of the base's field `field`: the parameter `super.field`, the inherited field, or
  // empty when it has none.
  std::string baseField(const std::string& field) const {
    for (const Param& p : params)
      if (p.inherited && p.name == field) return p.name;
    for (const Inherited& f : inherited)
      if (f.field == field) return f.name;
    return "";
  }
  // The field named `name`; fieldCount() for none.
  size_t fieldIndex(const std::string& name) const {
    size_t k = 0;
    while (k < fieldCount() && fieldName(k) != name) ++k;
    return k;
  }
};

// An item of a rule's side: a module `A`, `A()`, `A(x, y)` (on the left perhaps labelled `a:A`);
// on the right also a bracket ([ or ]) or a block of Java statements `{ … }`.
// `for (…) ( … )` and `if (…) ( … ) else ( … )` on a right side are items too, in order: the
// header (For, If: `block` its parentheses), Else, and the group's Open and Close.
struct Node {
  enum Kind { Module, Bracket, Block, For, If, Else, Open, Close } kind = Module;
  bool control() const { return kind >= For; }
  std::optional<size_t> label;  // the label's token (`t` of `t:Trieb`)
  size_t name = 0;              // the module's (or the bracket's) token
  bool parens = false;
  std::vector<Range> args;  // on the left, each one identifier
  std::optional<Range> shader;  // on the right, `.(setShader(X))`: X
  Range block;              // a Block's tokens, its braces included
};

struct Rule {
  std::vector<Node> contexts;  // `(* b:Baum *)` written apart (a comma after it): anywhere in the graph
  // Contexts joined to the rule's node: `(* A *) B` (A the node before B), `B (* C *)` (C the
  // node after it).
  std::optional<Node> before, after;
  std::vector<Node> left;
  std::optional<Range> condition;  // `( … )`, its parentheses included
  size_t arrow = 0, end = 0;       // `==>`, `==>>` or `::>`; `;` (or the last token)
  std::vector<Node> right;
  bool is(const std::vector<Token>& t, const char* arrowText) const { return t[arrow].is(arrowText); }
};

struct Method {
  size_t name = 0;
  std::vector<Rule> rules;
  // Blocks of Java statements among its rules (`[ { n = 0; } Axiom ==> A; ]`): XL runs them as
  // it goes through the block, before the rules' derivation.
  std::vector<Range> blocks;
};


}  // namespace lcjit::frontend::xl
