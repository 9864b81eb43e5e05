// Host functions for model code: each forwards to the engine that is running the model (and to
// what the engine was given: its functions, its session's window state).
#include "runtime/HostFunctions.h"

#include <array>
#include <utility>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

#include "runtime/Engine.h"
#include "runtime/Functions.h"
#include "runtime/turtle/Shapes.h"
#include "runtime/Terrain.h"
#include "runtime/WindowInput.h"

using lcjit::runtime::Engine;

namespace {
Engine* engine() { return Engine::current(); }
const lcjit::runtime::FunctionStore* functions() {
  Engine* e = engine();
  return e ? e->functions() : nullptr;
}
lcjit::runtime::Contour* curve(int id) {
  Engine* e = engine();
  return e && e->curves() ? e->curves()->get(id) : nullptr;
}
const lcjit::runtime::ShapeLibrary* shapes() {
  Engine* e = engine();
  return e ? e->turtleSetup().shapes : nullptr;
}
// The running session's window state; null outside a run (or for an engine without a session):
// then the functions answer as with no window.
lcjit::runtime::WindowInput* window() {
  Engine* e = engine();
  return e ? e->windowInput() : nullptr;
}
// What C++ typed at the REPL printed (lcjit/repl.h), on the REPL's thread.
std::string& replOutput() {
  static std::string text;
  return text;
}

// A successor context that keeps nothing: produce/nproduce outside every rule write here.
struct ModuleBufferHolder {
  __lc_Buffer buffer{nullptr, 0, 0};
  __lc_Ctx ctx{&buffer, 0, nullptr, nullptr};
  ~ModuleBufferHolder() { std::free(buffer.data); }
  __lc_Ctx* fresh() {
    buffer.size = 0;
    ctx.produced = 0;
    return &ctx;
  }
};

// Random streams outlive engines: lpfg keeps one per process.
lcjit::runtime::Rand48& fallbackRandom() {
  static lcjit::runtime::Rand48 r;
  return r;
}
}  // namespace

extern "C" {

void lcjit_repl_output(const char* text) { replOutput() += text; }

void lcjit_buffer_reserve(__lc_Buffer* b, size_t extra) {
  if (b->cap - b->size >= extra) return;
  // A successor growing without end (nproduce in a loop) stops at the memory limit.
  if (Engine* e = Engine::current()) e->checkGrowth(e->string().size() + b->size + extra);
  lcjit::runtime::growBuffer(*b, extra);
}

int lcjit_in_context(__lc_Ctx* c, int side, const __lc_ModuleId* ids, int n, const char** params) {
  Engine* e = static_cast<Engine*>(c->engine);
  return e && e->inContext(c, side, ids, n, params) ? 1 : 0;
}

__lc_Ctx* lcjit_current_ctx() {
  Engine* e = engine();
  if (e && e->activeContext()) return e->activeContext();
  // No rule is running: a successor that nothing reads, emptied each time.
  static thread_local ModuleBufferHolder discarded;
  return discarded.fresh();
}

void lcjit_use_group(int g) {
  if (Engine* e = engine()) e->useGroup(g);
}
void lcjit_cut_branch() {
  if (Engine* e = engine()) e->cutBranch();
}
void lcjit_derive_sequentially(int on) {
  if (Engine* e = engine()) e->setSequential(on != 0);
}
const char* lcjit_find_module(__lc_Ctx* c, __lc_ModuleId id, size_t* at) {
  // Outside every rule (lcjit_current_ctx's context of no engine): the running engine's string.
  Engine* e = c && c->engine ? static_cast<Engine*>(c->engine) : engine();
  return e ? e->findModule(c, id, at) : nullptr;
}
namespace {
// The field of the interpreting turtle's state (lcjit_turtle_field); null outside interpretation.
float* turtleField(int field) {
  Engine* e = engine();
  lcjit::runtime::Turtle* turtle = e ? e->interpretingTurtle() : nullptr;
  if (!turtle) return nullptr;
  lcjit::runtime::TurtleState& t = turtle->state();
  switch (field) {
    case __lc_TurtleStepLength: return &t.stepLength;
    case __lc_TurtleLocalStepLength: return &t.localStepLength;
    case __lc_TurtleWidth: return &t.width;
    case __lc_TurtleHeadingX: return &t.heading.x;
    case __lc_TurtleHeadingX + 1: return &t.heading.y;
    case __lc_TurtleHeadingX + 2: return &t.heading.z;
    case __lc_TurtleUpX: return &t.up.x;
    case __lc_TurtleUpX + 1: return &t.up.y;
    case __lc_TurtleUpX + 2: return &t.up.z;
  }
  return nullptr;
}
}  // namespace

float lcjit_turtle_field(int field) {
  float* f = turtleField(field);
  return f ? *f : 0.0f;
}
void lcjit_set_turtle_field(int field, float value) {
  if (field >= __lc_TurtleHeadingX) return;  // the frame is read only: SetHead turns it whole
  if (float* f = turtleField(field)) {
    *f = value;
    // SetWidth's: both of the contour's scales.
    if (field == __lc_TurtleWidth) engine()->interpretingTurtle()->state().widthUp = value;
  }
}
int lcjit_current_group() { return engine() ? engine()->currentGroup() : 0; }
void lcjit_forward() {
  if (Engine* e = engine()) e->setForward(true);
}
void lcjit_backward() {
  if (Engine* e = engine()) e->setForward(false);
}
int lcjit_is_forward() { return engine() ? engine()->forward() : 1; }
void lcjit_stop() {
  if (Engine* e = engine()) e->stop();
}
int lcjit_step_no() { return engine() ? engine()->stepNo() : 0; }

double lcjit_ran(double range) { return (engine() ? engine()->random() : fallbackRandom()).next() * range; }
void lcjit_sran(long seed) { (engine() ? engine()->random() : fallbackRandom()).seed(seed); }
void lcjit_report(const char* name, double value) {
  if (Engine* e = engine(); e && name) e->report(name, value);
}
void lcjit_seed_gillespie(long seed) {
  if (Engine* e = engine()) e->gillespieRandom().seed(seed);
}
double lcjit_gillespie_time() { return engine() ? engine()->gillespieTime() : 0; }
void lcjit_reset_gillespie() {
  if (Engine* e = engine()) e->resetGillespieTime();
}

float lcjit_func(int id, float x) { return functions() ? functions()->func(id, x) : 0; }
float lcjit_func_named(const char* name, float x) { return functions() && name ? functions()->func(name, x) : 0; }
float lcjit_pfunc(int id, float x, float mn, float mx) { return functions() ? functions()->pfunc(id, x, mn, mx) : 0; }
float lcjit_pfunc_named(const char* name, float x, float mn, float mx) {
  return functions() && name ? functions()->pfunc(name, x, mn, mx) : 0;
}
float lcjit_tfunc(int id, float x) { return functions() ? functions()->tfunc(id, x) : 0; }
float lcjit_tfunc_named(const char* name, float x) { return functions() && name ? functions()->tfunc(name, x) : 0; }
float lcjit_val(int id) { return functions() ? functions()->val(id) : 0; }
float lcjit_val_named(const char* name) { return functions() && name ? functions()->val(name) : 0; }
float lcjit_tunable(const char* name, float value, float min, float max) {
  if (auto* w = window()) return w->tunables.get(name, value, min, max);
  return name ? lcjit::runtime::Tunables::codeValue(value, min, max) : value;
}
void lcjit_func_tangent(int id, float x, float* out2) {
  std::array<float, 2> t{0, 0};
  if (functions()) t = functions()->funcTangent(id, x);
  out2[0] = t[0];
  out2[1] = t[1];
}

void lcjit_print(const char* text) {
  if (Engine* e = engine()) e->print(text);
  else std::fputs(text, stdout);
}

void lcjit_output_string(const char* path) {
  Engine* e = engine();
  if (!e || !path) return;
  if (auto err = e->writeBinary(path)) e->print((llvm::toString(std::move(err)) + "\n").c_str());
}

void lcjit_output_frame(const char* path) {
  if (Engine* e = engine(); e && path) e->outputFrame(path);
}

void lcjit_curve(int id, float t, int what, float* out) {
  V3f v;
  if (auto* c = curve(id)) v = what == 1 ? c->normalAt(t) : c->pointAt(t);
  out[0] = v.x;
  out[1] = v.y;
  out[2] = v.z;
}

float lcjit_curve_length(int id) {
  auto* c = curve(id);
  return c ? c->arcLength() : 0;
}

void lcjit_curve_op(int op, int id, int p, float x, float y, float z) {
  auto* c = curve(id);
  if (!c) return;
  switch (op) {
    case 0: c->scale(V3f(x, y, z)); break;
    case 1: c->setControlPoint(p, V3f(x, y, z)); break;
    case 2: c->recalculate(); break;
    default: c->reset(); break;
  }
}

void lcjit_get_surface(int id, float* points48) {
  SurfaceObj s;
  if (auto* lib = shapes(); lib && id >= 0 && id < (int)lib->surfaces.size()) s = lib->surfaces[id].surface.first();
  std::memcpy(points48, s.points, sizeof s.points);
}

void lcjit_get_surface_point(int id, int k, float* out) {
  V3f v;
  if (auto* lib = shapes(); lib && id >= 0 && id < (int)lib->surfaces.size()) v = lib->surfaces[id].surface.controlPoint(k);
  out[0] = v.x;
  out[1] = v.y;
  out[2] = v.z;
}

void lcjit_user_menu_item(const char* label, int code) {
  if (auto* w = window()) w->menu.add(label ? label : "", code);
}
void lcjit_use_view(int id, int open) {
  if (Engine* e = engine()) open ? e->useView(id) : e->closeView(id);
}
int lcjit_num_of_views() {
  Engine* e = engine();
  return e ? e->numOfViews() : 1;
}
// Without a window state: a zero box, scale 1, no camera (as Views says of an unknown view).
float lcjit_view_box(int id, int axis, int max) {
  auto* w = window();
  return w ? w->views.box(id, axis, max != 0) : 0;
}
float lcjit_view_scale(int id) {
  auto* w = window();
  return w ? w->views.scale(id) : 1;
}
void lcjit_camera_position(int id, CameraPosition* out) {
  auto* w = window();
  *out = w ? w->views.camera(id) : CameraPosition{};
}
void lcjit_animation_request(int what) {
  auto* w = window();
  if (!w) return;
  if (what == 0) w->animation.requestDisplay();
  else if (what == 1) w->animation.requestRun();
  else w->animation.requestPause();
}
void lcjit_mouse_status(MouseStatus* out) {
  auto* w = window();
  *out = w ? w->mouse.take() : MouseStatus{};
}
int lcjit_user_menu_choice() {
  auto* w = window();
  return w ? w->menu.choice() : -1;
}
void lcjit_user_menu_clear() {
  if (auto* w = window()) w->menu.clear();
}

int lcjit_model_value(int what) {
  Engine* e = engine();
  if (!e) return 0;
  switch (what) {
    case 0: return e->modelDerivationLength();
    case 1: return e->modelDecompositionDepth();
    case 2: return e->modelInterpretationDepth();
    default: return e->modelRingLsystem() ? 1 : 0;
  }
}

void lcjit_run(const char* command) {
  if (!command) return;
  // Two forks, so that the command is nobody's child here and leaves no zombie.
  pid_t child = fork();
  if (child == 0) {
    if (fork() == 0) {
      execl("/bin/sh", "sh", "-c", command, (char*)nullptr);
      _exit(127);
    }
    _exit(0);
  }
  if (child > 0) waitpid(child, nullptr, 0);
}

void lcjit_get_bsurface(int id, int maxRows, int maxColumns, int* rows, int* columns, float* points) {
  *rows = *columns = 0;
  const std::string name = std::string("GetBsurface") + (maxRows <= 10 ? "S" : "M");
  auto* lib = shapes();
  if (!lib || id < 0 || id >= (int)lib->bsplines.size()) {
    if (Engine* e = engine())
      e->print((name + ": invalid id = " + std::to_string(id) + ". Returning uninitialized object.\n").c_str());
    return;
  }
  if (!lcjit::runtime::bsplineToRecord(lib->bsplines[id].net, maxRows, maxColumns, points, rows, columns))
    if (Engine* e = engine()) e->print((name + ": lpfg cannot resize this surface to fit (it would not return)\n").c_str());
}

void lcjit_bsurface_op(int op, int maxRows, int maxColumns, const float* l, int lRows, int lColumns, const float* r,
                       int rRows, int rColumns, float alpha, int rows, int columns, float* out, int* outRows,
                       int* outColumns) {
  using lcjit::runtime::BSplineNet;
  BSplineNet a = lcjit::runtime::bsplineFromRecord(l, maxRows, maxColumns, lRows, lColumns);
  BSplineNet b = lcjit::runtime::bsplineFromRecord(r, maxRows, maxColumns, rRows, rColumns);
  BSplineNet s = op == 0 ? BSplineNet::add(a, b)
                         : BSplineNet::interpolate(a, b, alpha, std::min(rows, maxRows), std::min(columns, maxColumns));
  if (!lcjit::runtime::bsplineToRecord(std::move(s), maxRows, maxColumns, out, outRows, outColumns))
    if (Engine* e = engine())
      e->print(op == 0 ? "BsurfaceObj operator+: lpfg cannot resize the sum to fit (it would not return)\n"
                       : "Interpolate: lpfg cannot resize the result to fit (it would not return)\n");
}

void lcjit_tablet_status(TabletStatus* out) {
  auto* w = window();
  *out = w ? w->mouse.tablet() : TabletStatus{};
}

namespace {
// The view file's terrain, or null after lpfg's message.
lcjit::runtime::Terrain* terrain(const char* function) {
  Engine* e = engine();
  if (e && e->turtleSetup().terrain) return e->turtleSetup().terrain;
  if (e) e->print((std::string(function) + ": Terrain Not Loaded\n").c_str());
  return nullptr;
}
}  // namespace
int lcjit_terrain_query(int what, const float* world, float* out) {
  auto* t = terrain("terrainHeightAt");  // lpfg names this one for terrainNormalAt too
  if (!t) return 0;
  V3f w(world[0], world[1], world[2]), r;
  bool hit = what == 0 ? t->heightAt(w, r) : t->normalAt(w, r);
  if (hit) out[0] = r.x, out[1] = r.y, out[2] = r.z;  // lpfg leaves it as it was on a miss
  return hit ? 1 : 0;
}
// No point: every patch (terrainVisibilityAll); else the patch under the point (the level is
// unused, as in lpfg).
void lcjit_terrain_visibility(int mode, int, const float* world) {
  auto* t = terrain(world ? "terrainVisibilityPatch" : "terrainVisibilityAll");
  if (!t) return;
  if (world) t->visibilityPatch(VisibilityMode(mode), V3f(world[0], world[1], world[2]));
  else t->visibilityAll(VisibilityMode(mode));
}
void lcjit_terrain_scale(float factor) {
  if (auto* t = terrain("scaleTerrainBy")) t->scaleBy(factor);
}

int lcjit_environment(int op) {
  Engine* e = engine();
  if (!e) return 0;
  if (op < 2) e->setIgnoreEnvironment(op == 1);
  return e->ignoreEnvironment() ? 1 : 0;
}

void lcjit_load_string(const char* path) {
  Engine* e = engine();
  if (!e || !path) return;
  if (auto err = e->readBinary(path)) e->print((llvm::toString(std::move(err)) + "\n").c_str());
}
}

namespace lcjit::runtime {

std::string takeReplOutput() { return std::exchange(replOutput(), {}); }

std::vector<std::pair<std::string, void*>> hostFunctions() {
#define LCJIT_HOST(f) {#f, reinterpret_cast<void*>(&f)}
  std::vector<std::pair<std::string, void*>> functions = {
      LCJIT_HOST(lcjit_repl_output),      LCJIT_HOST(lcjit_buffer_reserve), LCJIT_HOST(lcjit_in_context),     LCJIT_HOST(lcjit_use_group), LCJIT_HOST(lcjit_cut_branch), LCJIT_HOST(lcjit_derive_sequentially), LCJIT_HOST(lcjit_find_module), LCJIT_HOST(lcjit_turtle_field), LCJIT_HOST(lcjit_set_turtle_field),
      LCJIT_HOST(lcjit_current_group),  LCJIT_HOST(lcjit_forward),        LCJIT_HOST(lcjit_backward),
      LCJIT_HOST(lcjit_is_forward),     LCJIT_HOST(lcjit_stop),           LCJIT_HOST(lcjit_step_no),
      LCJIT_HOST(lcjit_ran),            LCJIT_HOST(lcjit_sran),           LCJIT_HOST(lcjit_seed_gillespie), LCJIT_HOST(lcjit_report),
      LCJIT_HOST(lcjit_gillespie_time), LCJIT_HOST(lcjit_reset_gillespie), LCJIT_HOST(lcjit_func),           LCJIT_HOST(lcjit_func_named),
      LCJIT_HOST(lcjit_pfunc),          LCJIT_HOST(lcjit_pfunc_named),    LCJIT_HOST(lcjit_tfunc),
      LCJIT_HOST(lcjit_tfunc_named),    LCJIT_HOST(lcjit_val),            LCJIT_HOST(lcjit_val_named),
      LCJIT_HOST(lcjit_tunable),
      LCJIT_HOST(lcjit_func_tangent),
      LCJIT_HOST(lcjit_bsurface_op),
      LCJIT_HOST(lcjit_print),          LCJIT_HOST(lcjit_output_string),  LCJIT_HOST(lcjit_load_string),
      LCJIT_HOST(lcjit_output_frame),   LCJIT_HOST(lcjit_curve),          LCJIT_HOST(lcjit_curve_length),
      LCJIT_HOST(lcjit_curve_op),       LCJIT_HOST(lcjit_get_surface),    LCJIT_HOST(lcjit_get_surface_point),
      LCJIT_HOST(lcjit_user_menu_item), LCJIT_HOST(lcjit_user_menu_choice), LCJIT_HOST(lcjit_user_menu_clear),
      LCJIT_HOST(lcjit_mouse_status),   LCJIT_HOST(lcjit_animation_request), LCJIT_HOST(lcjit_use_view), LCJIT_HOST(lcjit_num_of_views),
      LCJIT_HOST(lcjit_view_box),       LCJIT_HOST(lcjit_view_scale),     LCJIT_HOST(lcjit_camera_position),
      LCJIT_HOST(lcjit_current_ctx),    LCJIT_HOST(lcjit_model_value),    LCJIT_HOST(lcjit_run),
      LCJIT_HOST(lcjit_get_bsurface),   LCJIT_HOST(lcjit_tablet_status),  LCJIT_HOST(lcjit_terrain_query),
      LCJIT_HOST(lcjit_terrain_visibility), LCJIT_HOST(lcjit_terrain_scale), LCJIT_HOST(lcjit_environment),
  };
#undef LCJIT_HOST
  // operator new and malloc & co. of model code: stoppable (ModelGuard.h).
  addModelCodeHooks(functions);
  return functions;
}

}  // namespace lcjit::runtime
