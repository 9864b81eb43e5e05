// The contract between a compiled model (JIT'd C++ generated from L+C) and the host runtime:
// the model describes itself with a __lc_Model table; rule bodies write successors through
// __lc_Ctx; everything else the model needs from the host is a C-linkage lcjit_* function.
#pragma once
#include "modules.h"

enum { __lc_AbiVersion = 4 };

struct __lc_Buffer {
  char* data;
  size_t size;
  size_t cap;
};

// State of one rule application, passed to the generated body.
struct __lc_Ctx {
  __lc_Buffer* out;  // successor modules are appended here
  int produced;      // set by produce: the rule applied
  void* engine;      // host-owned
  void* match;       // host-owned matching state (for InLeftContext & co.)
};

enum __lc_RuleKind : uint8_t { __lc_Production = 0, __lc_Decomposition = 1, __lc_Interpretation = 2 };
enum __lc_GroupKind : uint8_t { __lc_NormalGroup = 0, __lc_GillespieGroup = 1 };

struct __lc_Rule {
  uint8_t kind;
  uint8_t groupKind;
  // The production group (`group N:`, `ggroup N:`) and the view group (`vgroup N:`) in force
  // where the rule is written; as in lpfg, one does not end the other, and only interpretation
  // rules look at the view group.
  int16_t group;
  int16_t vgroup;
  // The predecessor, in source order: new left context, left context, strict predecessor,
  // right context, new right context. `pattern` holds their module ids concatenated.
  uint8_t nNewLeft, nLeft, nStrict, nRight, nNewRight;
  int16_t filter;  // index into __lc_Model::filters (ignore:/consider: in force), or -1
  const __lc_ModuleId* pattern;
  // Parameters of the matched modules are passed as pointers, in pattern order.
  void (*body)(__lc_Ctx*, const char* const*);
  int line;  // source line of the predecessor
  // The predecessor as written ("A(x) < B") and its file: fault messages name the rule.
  const char* predecessor;
  const char* file;
};

struct __lc_Filter {
  uint8_t consider;  // 1: consider: list, 0: ignore: list
  uint16_t n;
  const __lc_ModuleId* ids;
};

struct __lc_Model {
  uint32_t abiVersion;
  uint32_t nModules;                // user modules, ids __lc_FirstUserModule...
  const __lc_ModuleInfo* modules;
  uint32_t nRules;
  const __lc_Rule* rules;
  uint32_t nFilters;
  const __lc_Filter* filters;
  void (*axiom)(__lc_Ctx*);
  int (*derivationLength)();
  int (*ringLsystem)();           // null when the model is not a ring L-system
  int (*decompositionDepth)();    // null: 1
  int (*interpretationDepth)();   // null: 1
  void (*start)();
  void (*startEach)();
  void (*endEach)();
  void (*end)();
  const char* sourceFile;
  // VerifyString: (manual §10.4): the module ids the final string must have, in order.
  uint32_t nVerify;
  const __lc_ModuleId* verify;
  // NumOfViews(): the highest `vgroup` number the model declares, plus 1 (1 without any), as
  // lpfg's translator counts them; UseView takes 0 .. NumOfViews() - 1.
  int (*numOfViews)();
};

// Which context an InXContext(...) expression tests.
enum __lc_ContextSide { __lc_InLeft = 0, __lc_InRight = 1, __lc_InNewLeft = 2, __lc_InNewRight = 3 };

// Host functions callable from model code. Every one is listed in runtime/HostFunctions.cpp.
extern "C" {
void lcjit_buffer_reserve(__lc_Buffer* b, size_t extra);
// Not zero while a guarded run has been asked to stop (a limit, Ctrl-C): emitting a module then
// calls lcjit_checkpoint(), which unwinds the run if it is the one asked (runtime/ModelGuard).
extern const volatile int lcjit_stops_asked;
void lcjit_checkpoint();
int lcjit_in_context(__lc_Ctx* c, int side, const __lc_ModuleId* ids, int n, const char** params);
// The context of the rule running on this thread, for produce/nproduce in functions it calls;
// outside every rule a context whose successor is thrown away.
__lc_Ctx* lcjit_current_ctx();
void lcjit_use_group(int g);
int lcjit_current_group();
// lcjit's own, for XL's SPO deletion (`X ==>> ;`): the running production's predecessor goes with
// the rest of its branch, in this step (lpfg's Cut module waits for the next one). Forward
// derivation only; elsewhere nothing.
void lcjit_cut_branch();
// lcjit's own, for XL's sequential derivation mode (GroIMP's setDerivationMode(SEQUENTIAL_MODE)):
// from the next step on, a step applies one production, the first of the group's, in their
// order, that applies anywhere, where it first applies in the string; 0: every production where
// it applies (L+C's, XL's PARALLEL_MODE). Each run starts with 0.
void lcjit_derive_sequentially(int on);
// lcjit's own InString (the rewriter's): the next module `id` of the string as the step found it
// (the predecessor while it derives, else the string), from byte `*at` on, which it moves past it;
// null when there is none.
const char* lcjit_find_module(__lc_Ctx* c, __lc_ModuleId id, size_t* at);
// lcjit's own, for GroIMP's turtle state (XL's L, D, F0, MRel …): a field of the turtle that is
// interpreting the string, where an interpretation rule runs (the turtle has done what comes
// before it). Anywhere else the field reads 0 and setting it does nothing; the frame's fields are
// only read.
enum __lc_TurtleField {
  __lc_TurtleStepLength = 0,       // GroIMP's state length, 100 at first
  __lc_TurtleLocalStepLength = 1,  // its local form: for the next shoot alone
  __lc_TurtleWidth = 2,            // the line width (SetWidth's)
  __lc_TurtleHeadingX = 3,         // the heading H's coordinates (3, 4, 5), and the up U's
  __lc_TurtleUpX = 6,              // (6, 7, 8): to read (SetHead sets them)
};
float lcjit_turtle_field(int field);
void lcjit_set_turtle_field(int field, float value);
void lcjit_forward();
void lcjit_backward();
int lcjit_is_forward();
void lcjit_stop();
int lcjit_step_no();
double lcjit_ran(double range);
void lcjit_sran(long seed);
void lcjit_report(const char* name, double value);
void lcjit_seed_gillespie(long seed);
double lcjit_gillespie_time();
void lcjit_reset_gillespie();
float lcjit_func(int id, float x);
float lcjit_func_named(const char* name, float x);
float lcjit_pfunc(int id, float x, float min, float max);
float lcjit_pfunc_named(const char* name, float x, float min, float max);
float lcjit_tfunc(int id, float x);
float lcjit_tfunc_named(const char* name, float x);
float lcjit_val(int id);
float lcjit_val_named(const char* name);
float lcjit_tunable(const char* name, float value, float min, float max);
void lcjit_func_tangent(int id, float x, float* out2);
void lcjit_print(const char* text);
void lcjit_output_string(const char* path);
void lcjit_load_string(const char* path);
void lcjit_output_frame(const char* path);
// Curve functions (§6.3): what = 0 point, 1 normal, into out[3]; ops 0 scale (x,y,z),
// 1 set point p, 2 recalculate, 3 reset.
void lcjit_curve(int id, float t, int what, float* out);
float lcjit_curve_length(int id);
void lcjit_curve_op(int op, int id, int p, float x, float y, float z);
void lcjit_get_surface(int id, float* points48);
void lcjit_get_surface_point(int id, int k, float* out);
void lcjit_user_menu_item(const char* label, int code);
int lcjit_user_menu_choice();
void lcjit_user_menu_clear();
void lcjit_mouse_status(struct MouseStatus* out);
// §6.5: 0 DisplayFrame, 1 RunSimulation, 2 PauseSimulation (the window acts on them).
void lcjit_animation_request(int what);
void lcjit_use_view(int id, int open);  // UseView (open = 1) / CloseView (0)
int lcjit_num_of_views();
float lcjit_view_box(int id, int axis, int max);
float lcjit_view_scale(int id);
void lcjit_camera_position(int id, struct CameraPosition* out);
// The model's statements: 0 derivation length, 1 decomposition and 2 interpretation maximum
// depth, 3 ring L-system (1 or 0).
int lcjit_model_value(int what);
// Starts `/bin/sh -c command` without waiting for it.
void lcjit_run(const char* command);
// B-spline surface `id` of the view file: at most maxRows x maxColumns control points go to
// `points` (rows of maxColumns V3tf); the size used to rows/columns (0 x 0 if there is none).
void lcjit_get_bsurface(int id, int maxRows, int maxColumns, int* rows, int* columns, float* points);
// Arithmetic of two such records (l, r of lRows x lColumns, rRows x rColumns): op 0 l + r,
// op 1 Interpolate(l, r, alpha, rows, columns); the result to `out`, its size to outRows/outColumns.
void lcjit_bsurface_op(int op, int maxRows, int maxColumns, const float* l, int lRows, int lColumns, const float* r,
                       int rRows, int rColumns, float alpha, int rows, int columns, float* out, int* outRows,
                       int* outColumns);
void lcjit_tablet_status(struct TabletStatus* out);
// Terrain (§10.3): what = 0 height, 1 normal at world[3], into out[3]; returns whether the
// terrain was hit (out is left alone on a miss). visibility: world null means every patch.
int lcjit_terrain_query(int what, const float* world, float* out);
void lcjit_terrain_visibility(int mode, int level, const float* world);
void lcjit_terrain_scale(float factor);
// 0 Environment(), 1 NoEnvironment(), 2 IgnoreEnvironment(): 1 after NoEnvironment().
int lcjit_environment(int op);
}

// Appends a module record of `size` bytes (zeroed first, so that padding bytes in strings and
// .strb files are deterministic; id and id2 set) to the successor being built. Its last two
// bytes repeat the id, for reading the string backwards.
//
// Not a template over the record type, and the records are never passed or returned by value:
// the generated code of every module would otherwise instantiate its own copies in every
// compile, and -O0 code is selected by FastISel, which gives up on small structs by value and
// 16-bit arguments and hands the block to the far slower SelectionDAG.
//
// A stop asked for while a rule emits modules (nproduce in a loop growing the string past
// --max-memory) is seen here, at the produce or nproduce that was running, rather than forced
// wherever in the loop the watchdog's signal lands.
inline void __lc_put(__lc_Ctx* c, void* r, unsigned size) {
  if (__builtin_expect(lcjit_stops_asked != 0, 0)) lcjit_checkpoint();
  __builtin_memcpy(static_cast<char*>(r) + size - sizeof(__lc_ModuleId), r, sizeof(__lc_ModuleId));
  __lc_Buffer* b = c->out;
  if (b->cap - b->size < size) lcjit_buffer_reserve(b, size);
  __builtin_memcpy(b->data + b->size, r, size);
  b->size += size;
}
