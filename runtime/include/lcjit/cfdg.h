// The contract between a compiled Context Free design (JIT'd C++ generated from a .cfdg file by
// frontend/cfdg) and the shape-expansion engine (runtime/cfdg/Expander). The design describes
// itself with a __cf_Design table; each rule body is a C++ function that replaces its shape by
// others through __cf_replace; the engine owns the queue of unfinished shapes, the random state
// and the finished shapes. The generated unit includes only this header (no PCH), so it stays
// small and quick to parse.
//
// Everything a picture depends on to the last bit (the order of products in a transform, the
// order random numbers are drawn in) is decided by the engine's functions below, so the
// generated code only says which terms, in which order, with which values.
#pragma once

#ifdef __cplusplus
#include <cstdint>
#else
#include <stdint.h>
#endif

enum { __cf_AbiVersion = 2 };

// A shape's state, and what an adjustment changes of it (Context Free's "modification"): the
// 2-D transform (x' = sx·x + shx·y + tx, y' = shy·x + sy·y + ty), the 1-D z transform, the time
// interval, the colour (hue, saturation, brightness, alpha) and the colour target, which terms set
// which colour values (assign), and the blend mode.
struct __cf_State {
  double sx, shy, shx, sy, tx, ty;
  double zsz, ztz;
  double tsc, tbegin, tend;
  double colour[4];
  double target[4];
  unsigned assign;
  int blend;
};

// An adjustment value (a parameter or variable of type adjustment, `[ … ]` written as a value)
// is a __cf_State; in a shape's parameter block it takes __cf_StateDoubles numbers' room.
enum { __cf_StateDoubles = 20 };
#ifdef __cplusplus
static_assert(sizeof(struct __cf_State) == __cf_StateDoubles * sizeof(double), "__cf_StateDoubles");
// A vector value (Context Free's number tuples) returned by a function of the design.
template <int N>
struct __cf_V {
  double v[N];
};
// The adjustment kept at `p` in a parameter block, and one stored there.
inline struct __cf_State __cf_state_at(const double* p) {
  struct __cf_State s;
  __builtin_memcpy(&s, p, sizeof s);
  return s;
}
inline void __cf_state_to(double* p, const struct __cf_State& s) { __builtin_memcpy(p, &s, sizeof s); }
#endif

struct __cf_Ctx;
struct __cf_Timing;
typedef void (*__cf_Body)(struct __cf_Ctx*, const double* params);

struct __cf_Rule {
  int shape;
  double weight;
  int percent;  // the weight was written with % (a share of the whole, not of the rest)
  __cf_Body body;
  const char* at;  // "file:line:col" where the rule (a path: its name) is written: the profile names it
};

struct __cf_Shape {
  const char* name;
  int paramCount;  // numbers in the parameter block (a vector counts its length)
  int isPath;
  const char* usedAt;  // "file:line:col" where a shape that is never declared is first named, or null
  int pathBody;    // a path's body: __cf_PathOps, __cf_PathCommands or both (0: none, or a shape)
};

struct __cf_Design {
  int abiVersion;
  // Shapes 0..3 are the primitives CIRCLE, SQUARE, TRIANGLE, FILL.
  int shapeCount;
  const struct __cf_Shape* shapes;
  int ruleCount;
  const struct __cf_Rule* rules;  // in file order
  // Runs the global definitions that are not constant, then starts the start shape.
  void (*start)(struct __cf_Ctx*);
  int randStaticCount;  // rand_static() values the engine draws before the run, in parse order
  int usesColour;       // a sat term appears: the picture is in colour
  int usesTime;
  // Changes a white, opaque state into the background's colour (CF::Background), or null.
  void (*background)(struct __cf_Ctx*, struct __cf_State*);
  int usesBlend;        // a blend term: drawn with compositing operators
  int backgroundAlpha;  // the background has an alpha term: the picture has alpha
  // ftime() or frame() appears: an animation expands the design again for each frame.
  int usesFrameTime;
  // Writes CF::Time, CF::FrameTime and CF::Frame (constants) into a __cf_Timing; null when the
  // design sets none of them.
  void (*timing)(struct __cf_Ctx*, struct __cf_Timing*);
};

// A design's time settings: CF::Time's interval (the animation's time), CF::FrameTime and
// CF::Frame (what ftime() and frame() give outside an animation).
struct __cf_Timing {
  int hasTime;
  double timeBegin, timeEnd, timeScale;
  const char* timeAt;  // "file:line:col" of CF::Time, for errors
  int hasFrameTime, hasFrame;
  double frameTime, frame;
};

#ifdef __cplusplus
extern "C" {
#endif

// The engine's state for the body being run. `cur` is the running random state Context Free
// calls the current seed; the generated code xors constant seeds into it and draws from it
// through the engine's functions.
struct __cf_Ctx {
  uint64_t cur;
  const struct __cf_State* frame;  // the state children start from (the shape, or a loop's frame)
  const double* statics;            // rand_static() values
  void* engine;
  void* path;  // the path whose body is running (its outline and commands), else null
  double time[2];  // what ftime() and frame() give
};

uint64_t __cf_step(uint64_t s);
// One xorshift64* draw from ctx->cur: the low 52 bits of the output scaled to [0, 1).
double __cf_draw(struct __cf_Ctx* c);

// A fresh identity adjustment.
void __cf_identity(struct __cf_State* m);
// shape = `m` applied to `shape` (`m` first): how a folded constant adjustment is applied.
void __cf_apply(struct __cf_State* shape, const struct __cf_State* m);
// One constant term merged into an adjustment being folded (`m` starts as __cf_identity): how
// Context Free folds the constant terms of an adjustment once, before the run.
void __cf_fold(struct __cf_State* m, int kind, int count, const double* args);
// The copies of a transform statement: whether `m`'s transform is one of the first `count` of
// `transforms` (to 1e-14, as Context Free keeps only distinct ones), and a copy moved by one.
int __cf_seen_transform(const struct __cf_State* transforms, int count, const struct __cf_State* m);
void __cf_transform_by(struct __cf_State* shape, const struct __cf_State* m);
// Adjustment value `v` merged into adjustment `m` as Context Free combines adjustments that are
// values (`[trans a]`, a parameter given `[…]`): transforms compose (`v` first), colour changes
// add; when both change the same colour value (or an assigned one) nothing is merged.
void __cf_merge(struct __cf_State* m, const struct __cf_State* v);
// One adjustment term applied to a shape (or a loop's frame): `kind` is a __cf_Term.
void __cf_term(struct __cf_Ctx* c, struct __cf_State* shape, int kind, int count, const double* args);

enum __cf_Term {
  __cf_X, __cf_Y, __cf_Z, __cf_XYZ, __cf_Transform, __cf_Size, __cf_SizeXYZ, __cf_Rotate, __cf_Skew,
  __cf_Flip, __cf_ZSize, __cf_Blend, __cf_Hue, __cf_Sat, __cf_Bright, __cf_Alpha, __cf_HueTarg,
  __cf_SatTarg, __cf_BrightTarg, __cf_AlphaTarg, __cf_TargHue, __cf_TargSat, __cf_TargBright,
  __cf_TargAlpha, __cf_Time, __cf_TimeScale
};

// The child `shape` with state `s` and parameters `params` (the shape's paramCount numbers)
// replaces part of the running shape: queued when it has rules, drawn when it is a primitive.
void __cf_replace(struct __cf_Ctx* c, int shape, const struct __cf_State* s, const double* params);
// Shape values: a shape with its parameters bound (`foo(0.5)` given for a parameter of type
// shape), kept by the engine for the run; a shape without parameters is its number. Replacing
// with a value takes the shape and parameters it holds.
double __cf_bind(struct __cf_Ctx* c, int shape, const double* params);
void __cf_replace_value(struct __cf_Ctx* c, double value, const struct __cf_State* s);
void __cf_start_value(struct __cf_Ctx* c, double value, const struct __cf_State* s);
// The start shape: its seed is ctx->cur as it is (no further step).
void __cf_start(struct __cf_Ctx* c, int shape, const struct __cf_State* s, const double* params);

// Context Free's functions and distributions, with its constants (degrees, truncated factors).
double __cf_fn1(struct __cf_Ctx* c, int fn, double a);
double __cf_fn2(struct __cf_Ctx* c, int fn, double a, double b);
double __cf_rand(struct __cf_Ctx* c, double a, double b);     // rand(a, b), a..b
double __cf_randpm(struct __cf_Ctx* c, double a, double b);   // a +/- b
double __cf_randint(struct __cf_Ctx* c, double a, double b);
double __cf_pow(double a, double b);
// hsb2rgb (toRgb) and rgb2hsb: three numbers to three, by Context Free's colour conversions.
void __cf_colour(int toRgb, const double* in, double* out);
// The rand::… and randint::… distributions (a __cf_Distribution) with `count` arguments, drawn
// from ctx->cur as Context Free draws them.
double __cf_distribution(struct __cf_Ctx* c, int kind, int count, const double* args);
// ftime() (which 0) and frame() (which 1): the frame's time and place in an animation, else the
// design's CF::FrameTime and CF::Frame (0 when it sets none).
double __cf_time(struct __cf_Ctx* c, int which);
// A runtime error in the design's terms ("file:line:col: error: …"), which stops the run.
void __cf_fail(struct __cf_Ctx* c, const char* message);
// The same at a place of the design ("file:line:col").
void __cf_fail_at(struct __cf_Ctx* c, const char* at, const char* message);

enum __cf_Distribution {
  __cf_RandExponential, __cf_RandGamma, __cf_RandWeibull, __cf_RandExtremeValue, __cf_RandNormal,
  __cf_RandLogNormal, __cf_RandChiSquared, __cf_RandCauchy, __cf_RandFisherF, __cf_RandStudentT,
  __cf_RandBernoulli, __cf_RandBinomial, __cf_RandNegBinomial, __cf_RandPoisson, __cf_RandGeometric,
  __cf_RandDiscrete
};

// ---- Paths ----
// A path's body runs once when the path is finished (its commands measured) and again when it is
// drawn (its commands painted), each time from the path shape's seed. Its operations build the
// path's outline in the path's own units; a command paints (or measures) the operations since
// the previous command with the command's state (the path's, changed by the command's
// adjustment). Inside a loop of operations only, and in a sub-path of operations, the operations'
// points are transformed by the frame (c->frame).
enum __cf_PathOp {
  __cf_MoveTo = 1, __cf_MoveRel, __cf_LineTo, __cf_LineRel, __cf_ArcTo, __cf_ArcRel, __cf_CurveTo,
  __cf_CurveRel, __cf_ClosePoly
};
// What a body (or a sub-path element) holds: path operations, path commands (ORed).
enum __cf_PathBody { __cf_PathOps = 1, __cf_PathCommands = 2 };
// One path operation: `count` numbers in data[0..count) (data has room for 6; the engine uses the
// rest as scratch), `flags` Context Free's CF::ArcCW, CF::ArcLarge, CF::Continuous or CF::Align.
void __cf_pathOp(struct __cf_Ctx* c, int op, int flags, int count, double* data);
// A STROKE or FILL (CF::… flags, with Context Free's bit for FILL) with state `s` and stroke width.
void __cf_pathCommand(struct __cf_Ctx* c, const struct __cf_State* s, int flags, double width);
// Entering a loop of operations only, or a sub-path of operations: from now on operations are
// transformed by the frame; `frame` (the loop's or the sub-path's state) starts from the identity
// transform unless they already were. Returns what __cf_pathLeaveOps restores.
int __cf_pathEnterOps(struct __cf_Ctx* c, struct __cf_State* frame);
void __cf_pathLeaveOps(struct __cf_Ctx* c, int saved);
// A sub-path element (`path NAME(args) [adj]`): path or primitive `shape` with state `s` and
// parameters; `body` what the element was compiled to expect (__cf_PathBody).
void __cf_subpath(struct __cf_Ctx* c, int shape, const struct __cf_State* s, const double* params, int body);
// A sub-path element naming a shape value (a parameter or variable of type shape): the path (or
// primitive) and parameters it holds.
void __cf_subpath_value(struct __cf_Ctx* c, double value, const struct __cf_State* s, int body);

// __cf_IsNatural is a two-argument function: the number, and CF::MaxNatural.
enum __cf_Function {
  __cf_Cos, __cf_Sin, __cf_Tan, __cf_Cot, __cf_Acos, __cf_Asin, __cf_Atan, __cf_Acot, __cf_Cosh,
  __cf_Sinh, __cf_Tanh, __cf_Acosh, __cf_Asinh, __cf_Atanh, __cf_Log, __cf_Log10, __cf_Sqrt,
  __cf_Exp, __cf_Abs, __cf_Floor, __cf_Ceiling, __cf_Infinity, __cf_Factorial, __cf_Sg,
  __cf_IsNatural, __cf_BitNot, __cf_Atan2, __cf_Mod, __cf_Divides, __cf_Div, __cf_Abs2,
  __cf_BitOr, __cf_BitAnd, __cf_BitXor, __cf_BitLeft, __cf_BitRight, __cf_Min, __cf_Max,
  __cf_FunctionCount
};

// ---- Picture settings ----
// The settings that shape the picture (CF::Tile, CF::Size, CF::Symmetry, the borders, the pixel
// format), evaluated as the design's other values are. The start function hands them to the
// engine after the global definitions and before the start shape, where Context Free reads them;
// the engine then computes the background (design.background).

// One element of a symmetry list (CF::Symmetry, or the list of a transform statement): a flag
// (CF::Dihedral …) followed by number elements, or a transform.
enum __cf_SymmetryKind { __cf_SymmetryFlag, __cf_SymmetryNumbers, __cf_SymmetryTransform };
struct __cf_SymmetryItem {
  int kind;
  int count;             // numbers in values (a transform: 6, sx shy shx sy tx ty)
  const double* values;
  const char* at;        // "file:line:col", for errors
};

struct __cf_Settings {
  int hasTile;  // CF::Tile (CFDG 2's tile): the lattice, with the start shape's offset
  struct __cf_State tile;
  const char* tileAt;
  int hasSize;  // CF::Size (CFDG 2's size): the fixed frame, with the start shape's offset
  struct __cf_State size;
  const char* sizeAt;
  int symmetryCount;  // CF::Symmetry
  const struct __cf_SymmetryItem* symmetry;
  int hasBorderFixed, hasBorderDynamic;  // CF::BorderFixed (pixels), CF::BorderDynamic (a factor)
  double borderFixed, borderDynamic;
  int hasColour, hasAlpha, hasColourDepth;  // CF::Color, CF::Alpha, CF::ColorDepth
  double colour, alpha, colourDepth;
};
void __cf_configure(struct __cf_Ctx* c, const struct __cf_Settings* s);

// The transforms a symmetry list makes, in Context Free's order, each kept once (to 1e-14): how
// many, the first `capacity` of them written to `out` (a transform statement asks twice).
int __cf_symmetry(struct __cf_Ctx* c, const struct __cf_SymmetryItem* items, int count, struct __cf_State* out,
                  int capacity);

#ifdef __cplusplus
}
#endif
