// The translator of XL into L+C (Translate.h), internal to frontend/xl. A model is read whole
// into declarations and rule blocks, then written as L+C in the order lpfg's language wants it:
// the modules, the derivation length, the axiom (init()'s `Axiom ==> …`), the productions (the
// step method's rules), the interpretation rules (how a module that extends one of GroIMP's
// turtle commands, and the turtle commands lcjit has under another name, are drawn). What lcjit
// does not run yet is an error at the construct.
//
// A module's fields are its parameters and the fields it inherits from the turtle command it
// extends (F's length, diameter and colour, M's length, RU's angle…): all of them are parameters
// of its L+C module, those it does not declare (`super.length` declares one) set from the
// arguments of its `extends` (or the command's defaults) when it is made. A label (`t:Trieb`)
// names a copy of the matched node's fields (`t[length]`, `t.alter`), which the rule's code
// blocks may change and the node keeps when the right side names it again (`t`).
//
// Where each part is:
//   TranslateReading.cpp  reading: the model's declarations, modules, methods and rules
//   TranslateRules.cpp    a rule: its labels, its Java, its right side, the L+C production it
//                         becomes
//   TranslateQueries.cpp  graph queries (`count((* F *))`), in rules and in Java
//   Translate.cpp         GroIMP's turtle commands looked up, the L+C written whole, and the
//                         front end's entry points
#pragma once
#include <algorithm>
#include <cctype>
#include <deque>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "frontend/xl/Java.h"
#include "frontend/xl/LcWriter.h"
#include "frontend/xl/Model.h"
#include "frontend/xl/Tokens.h"
#include "frontend/xl/Turtle.h"

namespace lcjit::frontend::xl {

class Translator {
public:
  // `run`: the rule method each step applies; empty: the first.
  Translator(std::vector<Token> tokens, std::string run) : t_(std::move(tokens)), run_(std::move(run)) {}

  std::string run();
  // After run(): the model's rule methods, in its order, each with its production group.
  std::vector<std::pair<std::string, int>> ruleMethods() const;

private:
  // ---- reading (TranslateReading.cpp) ----
  const Token& cur() const { return t_[p_]; }
  bool accept(const char* s);
  void expect(const char* s, const std::string& where);
  size_t identifier(const std::string& what);
  [[noreturn]] void notYet(const Token& at, const std::string& what);
  // How a token changes the depth of brackets of any kind: ( [ { open, ) ] } close.
  static int nesting(const Token& t);
  // From `(` to its `)`, both included; p_ after it.
  Range balanced();
  // `( a, b(c, d), e )` → the arguments' ranges; p_ after the `)`.
  std::vector<Range> arguments();

  void topLevel();

  // The rule method a step applies: the one --run names, else the first (GroIMP's first button).
  void chooseMethod();

  // A model without init() whose rule method has `Axiom ==> …` (the RGG tutorial's and XL's own
  // manual's form): GroIMP's graph starts as the one node Axiom, which that rule rewrites in the
  // first step. lcjit's axiom is then a module Axiom (XL_Axiom in the L+C, L+C's `Axiom:` being
  // its axiom), and the rule one of the step's.
  void axiomNode();

  // The token after the parentheses that open at `i`; npos when they do not close.
  size_t afterParentheses(size_t i) const;
  // Whether the method starting at `void` has rules (`[`) after its parameters.
  bool methodOfRules() const;
  // A field or a method of Java statements.
  void declaration(bool constant);
  // A method's parameters, after its `(`, and its statements `{ … }` (no rules among them).
  void methodRest(Declaration& d);

  void module();
  // `.(setShader(X))` after a node or a module's base (`on` says which, for the error): X; p_
  // after it. Nothing when no `.(` is there.
  std::optional<Range> dotShader(const std::string& on);
  // A base's field as a module extending it inherits it: `field` the turtle command's field it is
  // (empty: none), `parameter` whether `extends Base(…)` sets it (a turtle command's fields, a
  // module's parameters), `fallback` its value in a base made without arguments.
  struct BaseField {
    std::string name, type, fallback, field;
    bool parameter;
  };
  static std::vector<BaseField> baseFieldsOf(std::string_view command);
  std::vector<BaseField> baseFieldsOf(const Module& base) const;
  // The value of `base`'s field `f` in a module that extends `base` with the arguments `args`
  // (tokens in the module's own parameters), as pieces (Inherited::pieces).
  std::vector<std::string> basePieces(const Module& base, const Inherited& f, const std::vector<Range>& args) const;
  // A field's value as pieces: its own pieces, its `extends` argument's tokens, or its fallback.
  std::vector<std::string> valuePieces(const Inherited& f) const;

  // A module's body `{ … }`: fields (`float z;`, `int n = 2;`: each a field of the module, as
  // its parameters are, Java's 0 or its initial value when it is made) and instance initialisers
  // `{ setShader(GREEN); }` (its colour). p_ after the body.
  void moduleBody(std::vector<Inherited>& fields, std::optional<Range>& shader,
                  std::vector<std::pair<size_t, Range>>& assigned, std::vector<Declaration>& methods);

  Rule rule();
  // A right side, from after its arrow to its `;` (or a block ending it): r.right, r.end.
  void rightSide(Rule& r);
  // The `(` of a for's, an if's or an else's group on a right side.
  void openGroup(Rule& r, std::vector<int>& groups, int depth);
  // A node of a pattern: `[label:]Module[(names)]`.
  Node patternNode(const std::string& what);
  // Whether a rule's left side starts here: `[a:]A[(…)]` and more of them, then `,`, or an arrow.
  bool ruleStarts() const;

  // ---- writing (Translate.cpp; a rule: TranslateRules.cpp) ----
  const Module* userModule(const std::string& name) const;
  // GroIMP's turtle command `name` with `arity` arguments; a default argument when it has none.
  const TurtleCommand* turtle(size_t at, int arity, std::vector<std::string>* defaults);
  const TurtleCommand* turtleOrError(const Node& n, std::vector<std::string>* defaults);
  void checkCount(const Node& n, const Module& m);

  // -- a rule's labels: each a copy of its node's fields (a C++ struct of the same names) --
  struct Label {
    const Module* module;
    std::vector<std::string> bound;  // the pattern's names of its fields
  };
  std::map<std::string, Label> labels_;
  // GroIMP's command `c` as a module of its fields (a label on it names them); null: it has none.
  const Module* commandModule(const TurtleCommand& c);
  std::deque<Module> commandModules_;  // commandModule's, kept where labels point at them
  const Label* label(size_t at) const;

  // A left side's node as an L+C pattern: the user's names for the parameters it names, names of
  // the translation's for the others (its inherited fields among them).
  void pattern(const Node& n, size_t index);
  // The name a pattern gives field `field` of its node `node` that the user does not name.
  static std::string unnamedField(size_t node, size_t field);
  // Module `name` with the node's arguments written where the user wrote them (the compiler's
  // errors name them there), then `more`.
  void writtenCall(const Node& n, const std::string& name, const std::vector<std::string>& more);
  // The copies of the labelled nodes' fields, made first in the production.
  void labelCopies();

  // Java in a condition, an argument or a block, as C++: a label's field `t[length]` is `t.length`,
  // Java's Math is C++'s, `boolean` is bool.
  void java(Range r);
  // XL's aggregate graph queries over the whole graph (de.grogra.xl.util.Operators' count, empty,
  // sum, prod, mean, max, min, first, last), in rules and in Java (TranslateQueries.cpp). Returns the token after the
  // query, or `i` for none.
  size_t query(size_t i, Range r);
  // The modules a query's or pattern's type `name` matches: the model's module and those
  // extending it; one of GroIMP's turtle commands in each of its forms and the modules extending
  // it. `fields` gets what a label on it names: the module's fields, the command's.
  struct Matched {
    const Module* module;                // the module in lcjit's string
    std::vector<std::string> fieldsFrom;  // per field of `fields`: its value from the module's
  };
  std::vector<Matched> matchedBy(size_t name, const Module*& fields);
  bool instantiating_ = false;  // writing an instantiation rule (madeNode: setShader on any node)

  // A block of Java statements: the last one's `;` may be missing before `}`.
  // A block of a right side, without its braces: what it declares is seen by the rest of the
  // right side, as in XL (`{ double r = 50 - i * 5; } Leaf(r, r * 0.5)`).
  void block(const Node& n);

  // -- a right side: its arguments computed in order, with its blocks, then produced --
  std::vector<std::string> argumentNames_;  // by right-side node and argument, in order
  size_t temps_ = 0;
  // Each argument of a made node, as a local computed where it is written (blocks after it do not
  // change it, as in XL), then the blocks.
  void rightStatements(const std::vector<Node>& right);
  // The right side's modules (after rightStatements: `arguments` are its locals; in the axiom,
  // the arguments as written).
  void rightModules(const std::vector<Node>& right, bool axiom);
  // Node `n` of a right side, made with the arguments `given`: a label's node as its copy left
  // it, or the module with its inherited fields after `given`.
  void madeNode(const Node& n, std::vector<std::string> given, bool axiom);
  static bool hasBlock(const std::vector<Node>& right);
  static bool hasControl(const std::vector<Node>& right);
  // A right side with for or if, made node by node where it stands (L+C's nproduce): each node's
  // arguments computed, then the node; blocks run in place; for and if as C++'s. The caller ends
  // it with `produce ;`. A label's node is made where it stands, so no block may come after it.
  void stepwise(const std::vector<Node>& right);
  // XL's for on a right side: `for ((a : b))` runs for a, a + 1 … b; `for (int i : a : b)` (or
  // `: (a : b)`) with i each of them; Java's `for (init; condition; update)` as written.
  void forHeader(const Node& n);
  // An inherited field's value for a module made with the arguments `given`: its `extends`
  // argument with the module's parameters replaced by them.
  std::string inheritedValue(const Module& m, const Inherited& f, const std::vector<std::string>& given) const;
  // The node a label names, as its fields' copy left it: `T(t.alter, t.length, …)`.
  static std::string fromLabel(const std::string& label, const Module& m);
  static std::string joined(const std::vector<std::string>& items);
  std::string text(Range r) const;
  // How a command with these arguments is drawn (lpfg's modules).
  static std::string drawn(std::string_view pattern, const std::vector<std::string>& args);

  // -- a rule as an L+C production --
  static size_t rewrittenNode(const Rule& r, const std::vector<Token>& t);
  // The model's modules a rule's pattern also matches: those extending the turtle command it
  // names (a GroIMP pattern F(x) matches every node whose class is F or extends it), its node
  // unlabelled and given its parameters.
  std::vector<const Module*> subclassesMatched(const Rule& r) const;
  // A subclass's pattern for a turtle command's (subclassesMatched): its fields, each of the
  // command's fields the pattern names taking the pattern's name.
  void subclassPattern(const Node& n, const Module& m, size_t index);
  // The model's modules extending `base`, however far down.
  std::vector<const Module*> subclassesOf(const Module& base) const;

  // The production of rule `r`; with `subclass`, the same rule for a module extending the turtle
  // command its pattern names.
  void production(const Rule& r, const Module* subclass = nullptr);
  // An SPO rule's right side, as the production of an L-system. SPO keeps the relations of the
  // nodes both sides name and drops those of the nodes it deletes:
  // - `X ==>> ;` deletes X and what hangs on it (the rest of its branch goes, in this step, by
  //   lcjit_cut_branch()); so does `X ==>> G` (the quick reference's): G, connected to nothing,
  //   is not part of the graph lcjit keeps (GroIMP shows only what hangs on its root);
  // - `x:X ==>> x …` keeps X, its relations with it, and puts … after it, as `==>` would;
  // - `a:A X c:C ==>> a … c` keeps A and C and their relations and puts … between them: X
  //   replaced, with A and C its context.
  // Other SPO rules are refused.
  static bool names(const Node& n, const Node& left, const std::vector<Token>& t);
  static bool deletes(const Rule& r, const std::vector<Token>& t);
  std::vector<Node> spoRight(const Rule& r);

  std::string write();
  // The methods of `m`'s body and of its bases' (a base's that `m` does not override).
  std::vector<const Declaration*> methodsOf(const Module& m) const;
  // The name of the struct of `m`'s fields and methods (a module with methods has one).
  static std::string fieldsStruct(const Module& m);
  // The instantiation rule of `m`, or of the nearest of its bases with one; null: none.
  const Rule* instantiationOf(const Module& m) const;
  // Module `m` as an interpretation rule's pattern: each field by its name.
  std::string pattern(const Module& m) const;
  // What a module extending one of GroIMP's turtle commands draws; empty: nothing.
  std::string ownDrawing(const Module& m);

  std::string signature(const Declaration& d) const;
  // The Java type at token `at` as C++, an array's `[]` after it included (`int[][]` is
  // lcjit/xl.h's __xl_Array<__xl_Array<int>>).
  std::string javaTypeAt(size_t at) const;

  std::vector<Token> t_;
  size_t p_ = 0;
  std::vector<Declaration> declarations_;
  std::vector<Module> modules_;
  std::optional<Method> init_, step_;
  std::vector<Method> methods_;  // the rule methods besides init(), in the model's order
  // The production group of methods_[k]: k + 1 when there are several, else 0 (write()).
  int groupOf(size_t k) const { return methods_.size() > 1 ? int(k) + 1 : 0; }
  // Instantiation rules (`module Bud ==> Sphere(0.1);`): what a module's nodes are drawn as.
  std::map<std::string, Rule> instantiations_;
  std::string run_;
  int classes_ = 0;  // `class M extends RGG {` read and not yet closed
  bool axiomIsNode_ = false;  // no init(): the axiom is the node Axiom (axiomNode)
  size_t axiomNameAt_ = 0;
  // Where the axiom is written: init()'s name, or the Axiom the rule rewrites.
  size_t axiomAt() const { return init_ ? init_->name : axiomNameAt_; }
  std::set<const TurtleCommand*> used_;
  LcWriter w_{t_};
};

}  // namespace lcjit::frontend::xl
