// The translator of a Context Free design into C++ (translateDesign, Translate.h): what it keeps
// while it reads a design and the values it builds, shared by the files that hold its parts.
// Internal to frontend/cfdg. Its sections, and the file that defines each:
//   1. Names in scope and values                                    Translate.cpp
//   2. Seed bytes of expressions and adjustments                    TranslateExpressions.cpp
//   3. Expressions → C++                                            TranslateExpressions.cpp
//   4. Adjustments: Context Free's term order, folding of constant
//      terms, run-time terms                                        TranslateAdjustments.cpp
//   5. Elements of a body → C++                                     TranslateElements.cpp
//   6. The unit: globals, functions, rules, the start shape, the
//      design's table                                               Translate.cpp
//   7. Paths: operations, commands, sub-paths                       TranslatePaths.cpp
//   8. Picture settings: CF::Tile, CF::Size, CF::Symmetry, the
//      borders, the pixel format, CF::StartShape                    TranslateSettings.cpp
//   9. Purity: how expressions depend on parameters, natural
//      numbers, the parameter requirements                          TranslatePurity.cpp
#pragma once
#include <cstdint>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "frontend/cfdg/Ast.h"
#include "frontend/cfdg/Lexer.h"  // numberValue
#include "frontend/cfdg/Translate.h"

namespace lcjit::frontend::cfdg::translate {

struct TranslateError {
  Place at;
  std::string message;
};
[[noreturn]] inline void fail(const Place& at, const std::string& message) { throw TranslateError{at, message}; }

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

// How a value depends on the parameters of the shape (or function) it is written in, in Context
// Free's terms: not at all (pure local), on parameters as given (pure non-local), or on values
// computed from them (impure non-local). Each is a mask of the one before it, so the locality
// of a value made of several is theirs ANDed (section 9).
enum Locality : int { kImpureNonlocal = 1, kPureNonlocal = 3, kPureLocal = 7 };

struct Binding {
  enum Kind { Param, Local, Global, Function } kind;
  std::string cpp;  // what C++ calls it (Param: the block's first index)
  int width = 1;    // numbers (an adjustment: the room it takes in a parameter block)
  bool constant = false;
  bool shape = false;  // a shape-typed parameter
  const Definition* function = nullptr;
  bool adjustment = false;  // a __cf_State
  AdjustmentInfo info;      // an adjustment's
  Locality locality = kPureLocal;  // a parameter: pure non-local; a variable: its value's (section 9)
  bool natural = false;            // a natural number, as Context Free knows it (section 9)
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

// A design's name as a C++ identifier: names may hold any UTF-8 letter and `::`.
std::string identifier(const std::string& name);

// A name as written (its seed bytes), given the name and Ast.h's `written` field.
inline const std::string& asWritten(const std::string& name, const std::string& written) {
  return written.empty() ? name : written;
}

// A seed as a C++ literal.
std::string hex64(uint64_t v);

// Where Context Free places an expression in an error (TranslatePurity.cpp).
const Place& placeOf(const Expr& e);

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

  void line(const std::string& s);
  std::string temp() { return "_t" + std::to_string(temp_++); }

  const Binding* lookup(const std::string& name) const;
  int shapeId(const std::string& name, const Place& at);

  // -------------------------------------------------------------------------------------------
  // 2. Seed bytes
  // -------------------------------------------------------------------------------------------

  std::string argBytes(const std::vector<ExprP>& args);

  std::string functionBytes(const Definition& fn, const std::vector<ExprP>& args);

  std::string bytes(const Expr& e);

  // -------------------------------------------------------------------------------------------
  // 3. Expressions → C++
  // -------------------------------------------------------------------------------------------

  static std::string number(const std::string& text) { return literal(numberValue(text)); }
  static std::string literal(double v);

  std::string ordered(const std::vector<std::string>& operands, const std::string& combine, bool pure);

  // Translates `e` only to learn what it is (its width, whether it is constant). Translating an
  // expression again writes the same C++ (a rand_static() keeps its number, staticOf).
  Value probe(const Expr& e) { return expr(e); }
  int staticOf(const Expr& e);

  std::string captured(const std::function<void()>& f);

  void hoist(Value& v);

  Value joined(std::vector<Value> values, bool settle);

  Value numbers(const Expr& e);
  Value scalar(const Expr& e);
  static Value single(Value v);
  std::vector<std::string> emitted(Value v);
  std::string adjustmentState(const Value& v);

  double constantNumber(const Expr& e, const std::string& what);

  Value adjustmentVariable(const std::string& cpp, const Binding& b);

  Value expr(const Expr& e);

  Value vectorOperation(const Expr& e, Value l, Value r);

  Value index(const Expr& e);

  Value let(const Expr& e);

  Value adjustmentLiteral(const Adjustment& a);

  double settingNumber(const Definition& def);

  std::string flag(const Expr& e) { return number(std::to_string(flagNumber(e))); }

  int flagNumber(const Expr& e);

  // The arguments of a call, left to right: numbers, and adjustments (as __cf_State
  // expressions), with statements to run first. `settled`: each is computed once, in order, by
  // the statements (or draws nothing), so they may be used in any order.
  struct Arguments {
    std::vector<std::string> items;
    std::vector<bool> adjustment;
    std::string pre;
    bool constant = true, pure = true, settled = false;
  };
  Arguments arguments(const std::vector<Value>& values, bool settle = false);
  std::string combined(const Arguments& a, const std::string& combine);
  std::string block(const Arguments& a, int count, const std::string& use, const Place& at, const std::string& name);

  Value call(const Expr& e);

  Value userCall(const Binding& fb, std::vector<Value> args, const std::vector<ExprP>& exprs, const Place& at);

  int functionWidth(const Definition& fn);

  std::string functionSignature(const Definition& fn, const std::string& name);

  Value choice(const Expr& e, std::vector<Value> args);

  // -------------------------------------------------------------------------------------------
  // 4. Adjustments
  // -------------------------------------------------------------------------------------------

  struct PreparedTerm {
    std::string kind;  // x, y, z, xyz, s, sizexyz, zsize, r, skew, f, trans, h, sat, b, a, blend, time, timescale, |h …
    std::vector<const Expr*> args;
    Place at;
    bool targetForm = false;
  };

  static void flattenArgs(const Term& t, std::vector<const Expr*>& out);

  int widthOf(const Expr* e);
  int widthOf(const std::vector<const Expr*>& args);

  std::vector<PreparedTerm> prepare(const Adjustment& a);

  std::string termBytes(const PreparedTerm& t);

  std::string adjustmentBytes(const std::vector<PreparedTerm>& terms);

  static int canonicalRank(const std::string& k);
  static int termClass(const std::string& k);
  static std::string termEnum(const PreparedTerm& t);

  static std::vector<PreparedTerm> canonical(std::vector<PreparedTerm> terms);

  // A constant adjustment value merged into `state` as Context Free folds one (into an
  // adjustment, or a constant variable): its folded part only, without the terms it keeps for the
  // run (a colour value set twice).
  bool foldedOnly_ = false;
  void foldedValue(const Value& v, const std::string& state);

  Binding adjustmentVariable(const Value& v, const Expr& value, const std::string& name, Binding::Kind kind, uint64_t seed);

  Value termValue(const PreparedTerm& t);

  static unsigned termColours(const std::string& kind, int count);

  uint64_t applyAdjustment(const Adjustment& a, std::vector<PreparedTerm> terms, const std::string& state, bool merge = false);

  // -------------------------------------------------------------------------------------------
  // 5. Elements
  // -------------------------------------------------------------------------------------------

  void body(const Body& b);

  void element(const Element& e);

  bool geometryOnly(const Adjustment& a);

  void transform(const Element& e);

  std::string adjustmentTemp(const Value& v);

  std::pair<std::string, int> argumentBlock(const std::vector<ExprP>& args, const std::vector<Param>* params);

  size_t seedPlaceholder();
  void patchSeed(size_t at, uint64_t seed);

  void define(const Element& e);

  void replacement(const Element& e);

  void loop(const Element& e);

  // -------------------------------------------------------------------------------------------
  // 7. Paths
  // -------------------------------------------------------------------------------------------

  // What an element or body holds, as Context Free classes them: path operations, path commands,
  // replacements (ORed). A loop of operations only transforms them by its frame.
  enum { kOps = 1, kCommands = 2, kReplacements = 4 };

  int bodyKind(const Body& b);
  int elementKind(const Element& e);

  int pathBodyOf(int shape);

  int subpathKind(const Element& e);

  std::string enterPathOps(const Element& loop, const std::string& frame);
  void leavePathOps(const std::string& saved);

  bool isFlag(const Expr& e) const;
  int flagsOf(const Expr& e);

  void pathOp(const Element& e);

  void pathCommand(const Element& e);

  void subpath(const Element& e);

  // -------------------------------------------------------------------------------------------
  // 8. Picture settings
  // -------------------------------------------------------------------------------------------

  std::map<std::string, const Definition*> settings_;  // the first definition of each

  bool pictureSetting(const Definition& def);
  const Expr* setting(const std::string& name) const;

  std::string placeString(const Place& at) const;
  // The same in `file` (a rule of an imported file).
  static std::string placeString(const Place& at, const std::string& file);

  bool constantExpr(const Expr& e) const;

  void settingAdjustment(const Expr& e, const std::string& name, const std::string& state);

  std::string settingsCode();

  std::vector<std::string> symmetryItems(const Expr& list, bool statement);

  // -------------------------------------------------------------------------------------------
  // 9. Purity
  // -------------------------------------------------------------------------------------------

  Locality locality(const Expr& e);
  Locality localityOf(const std::vector<ExprP>& list);
  Locality choiceLocality(const Expr& e);

  std::map<const Definition*, Locality> functionLocality_;  // each function's value's, once known
  Locality functionLocality(const Definition& fn);

  bool natural(const Expr& e);
  bool naturalLoopIndex(const Expr& count);

  void parameterRequirements(const std::vector<Param>& params, const std::vector<ExprP>& args, bool numbers);
  void naturalOperands(const Expr& e);
  std::vector<bool> naturalSlots(const std::vector<Param>& params) const;
  std::string naturalChecked(const std::string& value, const Place& at);
  std::string wholeChecked(const std::string& value, double most, const Place& at, const std::string& message);
  void checkNaturals(const std::vector<Param>& params, const std::vector<ExprP>& exprs, const std::vector<Value>& values,
                     Arguments& a);
};

}  // namespace lcjit::frontend::cfdg::translate
