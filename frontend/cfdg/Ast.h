// A Context Free design as parsed: shapes and their rules, paths, definitions and functions, and
// the elements of their bodies, each with the place it was written (errors name it) and the
// source text its random seed is made from.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "frontend/cfdg/Lexer.h"

namespace lcjit::frontend::cfdg {

struct Expr;
using ExprP = std::unique_ptr<Expr>;
struct Adjustment;

struct Expr {
  enum Kind {
    Number,      // text: as written
    Name,        // a variable, parameter, loop index, constant or shape
    Unary,       // text: "-", "+", "!"
    Binary,      // text: the operator
    Paren,       // ( e )
    List,        // a, b, …
    Call,        // text: function or shape name; args
    Index,       // text: vector name; args[0]: the index
    Let,         // names/args: definitions, args.back(): the value
    Modification // an adjustment used as a value: [ … ]
  } kind;
  Place at;
  Place opAt;           // Binary: the operator's place
  std::string text;     // a name: with the namespace of the file it is written in (`ns::NAME`)
  std::string written;  // a name as written (its seed bytes), when that differs from text
  std::vector<ExprP> args;
  std::vector<std::string> names;  // Let: the defined names, in order
  std::shared_ptr<Adjustment> adjustment;
  bool reuseParams = false;  // NAME(=)
};

struct Term {
  std::string word;  // as written: x, size, hue, |b …
  Place at;
  std::vector<ExprP> args;
  bool targetForm = false;  // `b 0.5|` (CFDG 2)
};

struct Adjustment {
  bool ordered = false;  // [[ … ]]: terms in the order written
  Place at;
  std::vector<Term> terms;
};

struct Param {
  std::string type;  // number, natural, adjustment, shape, vectorN
  std::string name;
  Place at;
  int width = 1;     // numbers it takes in a parameter block (an adjustment: a __cf_State's room)
};

struct Element;
using Body = std::vector<std::unique_ptr<Element>>;

struct Element {
  enum Kind { Replace, Define, Loop, If, Switch, Transform, Clone, PathOp, PathCommand } kind;
  Place at;
  // Replace: `shape(args) [adj]`; or `if(...)`/`select(...)`/`let` choosing the shape (shapeExpr).
  std::string shape;         // with the file's namespace, as Expr::text
  std::string shapeWritten;  // as written, when that differs
  Place shapeAt;
  std::vector<ExprP> args;
  bool hasArgs = false;
  bool reuseParams = false;
  ExprP shapeExpr;
  Adjustment adjustment;
  // Define: name = value.  Loop: index name ("" if none), args = value, adjustment, body, finally.
  std::string name;         // with the file's namespace, as Expr::text
  std::string nameWritten;  // as written, when that differs
  ExprP value;
  Body body, otherwise;  // loop body and finally / if's then and else / transform's body
  // Switch.
  struct Case {
    std::vector<ExprP> values;  // empty: else
    Body body;
  };
  std::vector<Case> cases;
  bool v2Loop = false;
  std::string v2Count;  // CFDG 2 `N *`: the count as written
  // Paths. PathOp: name (MOVETO …), value (the arguments, null for none). PathCommand: name
  // (STROKE, FILL), args (width, flags), adjustment. Replace with subpath: `path NAME [adj]`.
  bool subpath = false;
  int flags = 0;  // CFDG 2 path operations: the flags their `p` words name
};

struct Rule {
  std::string shape;
  std::string file;  // the file it is written in (the design, or one it imports)
  Place at;
  double weight = 1;
  bool percent = false;
  Body body;
  bool isPath = false;
};

struct ShapeDecl {
  std::string name;
  Place at;
  std::vector<Param> params;
  bool isPath = false;
  int firstRule = -1;
};

struct Definition {
  std::string name;     // with the file's namespace, as Expr::text
  std::string written;  // as written, when that differs
  std::string type;  // "" for plain `name = value`
  Place at;
  Place declaredAt;  // where it begins: its type, else its name (Context Free's errors of a function's type)
  std::vector<Param> params;  // a function's
  bool isFunction = false;
  ExprP value;
  bool config = false;  // CF::Name = …
  bool commandLine = false;  // -D NAME=VALUE: the design's own definition of NAME is dropped
  int depth = 0;  // how deep in imports it is written (-D: -1): of two settings the shallower counts
};

struct Design {
  std::string file;
  int version = 3;
  std::string startShape;
  Place startAt;
  std::vector<ExprP> startArgs;
  bool startHasAdjustment = false;
  Adjustment startAdjustment;
  std::vector<ShapeDecl> shapes;
  std::vector<Rule> rules;
  std::vector<Definition> definitions;  // global, in file order (configs included)
  std::vector<std::string> imports;  // the files imported or included, as read (paths)
};

}  // namespace lcjit::frontend::cfdg
