// lcjit's model API header, in place of lpfg's <lpfgall.h>: what L+C model code may use, with
// lpfg's surface (docs/compatibility.md lists every entry). It includes the standard headers
// lpfg's does, so models use what they declare without including them, defines lpfg's header
// guards and macros, and gives lpfg's types, functions and predefined modules. Precompiled once;
// every model translation unit is compiled against it, and the preprocessor sees its macros.
#ifndef __LPFGALL_H__
#define __LPFGALL_H__

// lpfg's lpfgall.h and lintrfc.h include these, in this order.
#include <memory.h>
#include <stdlib.h>
#include <stdio.h>
#include <cmath>
#include <string>
#include <iostream>

// lparams.h
#define __LPARAMS_H__
enum { __lc_eMaxIdentifierLength = 32, __lc_eMaxParams = 64, __lc_eMaxFormalModules = 32, __lc_eFirstModuleId = 2 };
enum __lc_GroupType { __lc_gtUnspecified, __lc_gtLsystem, __lc_gtGillespie };
#define StartBranchIdent "SB"
#define EndBranchIdent "EB"

// lintrfc.h: the predefined types (lcjit/types.h, lcjit/vectors.h).
#define __LINTRFC_H__
#include "lcjit/abi.h"
#include "lcjit/repl.h"

// lsys.h
#define __LSYS_H__
#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif
#define DECLSPEC extern "C"

// stdmods.h: successor writers of the predefined modules (produce F(x) calls __lc_emit_F(ctx, x)).
#define __STDMODS_H__
#define __LC_EMIT_ARGS_0()
#define __LC_EMIT_ARGS_1(a) , a a0
#define __LC_EMIT_ARGS_2(a, b) , a a0, b a1
#define __LC_EMIT_ARGS_3(a, b, c) , a a0, b a1, c a2
#define __LC_EMIT_ARGS_4(a, b, c, d) , a a0, b a1, c a2, d a3
#define __LC_EMIT_ARGS_6(a, b, c, d, e, f) , a a0, b a1, c a2, d a3, e a4, f a5
#define __LC_SET_0
#define __LC_SET_1 r.p0 = a0;
#define __LC_SET_2 __LC_SET_1 r.p1 = a1;
#define __LC_SET_3 __LC_SET_2 r.p2 = a2;
#define __LC_SET_4 __LC_SET_3 r.p3 = a3;
#define __LC_SET_6 __LC_SET_4 r.p4 = a4; r.p5 = a5;
#define LCJIT_MODULE(N, I, A, ...)                                        \
  inline void __lc_emit_##N(__lc_Ctx* c __LC_EMIT_ARGS_##A(__VA_ARGS__)) { \
    __lc_R_##N r;                                                       \
    __builtin_memset(&r, 0, sizeof r);                                  \
    r.id = r.id2 = I;                                                   \
    __LC_SET_##A __lc_put(c, &r, sizeof r);                             \
  }
#include "lcjit/stdmods.def"
#undef LCJIT_MODULE

// §6.1 Controlling the derivation.
inline void Forward() { lcjit_forward(); }
inline void Backward() { lcjit_backward(); }
inline bool IsForward() { return lcjit_is_forward() != 0; }
inline void UseGroup(int g) { lcjit_use_group(g); }
inline int CurrentGroup() { return lcjit_current_group(); }
// The model's own statements, as lpfg's translated model exports them.
inline int DerivationLength() { return lcjit_model_value(0); }
inline int DecompositionMaxDepth() { return lcjit_model_value(1); }
inline int InterpretationMaxDepth() { return lcjit_model_value(2); }
inline int RingLsystem() { return lcjit_model_value(3); }

// §6.5 Animation functions: Stop works everywhere; the rest need a window.
inline void Stop() { lcjit_stop(); }
inline int StepNo() { return lcjit_step_no(); }
inline void DisplayFrame() { lcjit_animation_request(0); }
inline void OutputFrame(const char* path) { lcjit_output_frame(path); }
inline void RunSimulation() { lcjit_animation_request(1); }
inline void PauseSimulation() { lcjit_animation_request(2); }
// lpfg declares these and does nothing with them.
inline void DelayWrite() {}
inline void Write() {}
inline void StartPerformance() {}
inline void StopPerformance() {}
inline float SetOrGetParameterf(const char*, float) { return 0; }
inline int SetOrGetParameteri(const char*, int) { return 0; }
inline bool ParametersNeedUpdating() { return false; }
inline float GetParameterf(const char*) { return 0; }
inline int GetParameteri(const char*) { return 0; }
inline void SetParameterf(const char*, float) {}
inline void SetParameteri(const char*, int) {}
// Starts a shell command and does not wait for it (lpfg's Run).
inline void Run(const char* command) { lcjit_run(command); }

// §6.6-6.7 Functions and parameters from input files.
inline float func(int id, float x) { return lcjit_func(id, x); }
inline float func(const char* name, float x) { return lcjit_func_named(name, x); }
inline float pfunc(int id, float x, float mn, float mx) { return lcjit_pfunc(id, x, mn, mx); }
inline float pfunc(const char* name, float x, float mn, float mx) { return lcjit_pfunc_named(name, x, mn, mx); }
inline float tfunc(int id, float x) { return lcjit_tfunc(id, x); }
inline float tfunc(const char* name, float x) { return lcjit_tfunc_named(name, x); }
// Parameter names from .vset files (and function names) are predefined as macros expanding to
// their ids, as lpfg does, so val(LENGTH) is val(<id>).
inline float val(int id) { return lcjit_val(id); }
inline float val(const char* name) { return lcjit_val_named(name); }
// lcjit: a value the window's Parameters panel tunes as a slider over [min, max] (docs/studio.md):
// `value` until it is moved there, then the slider's value, from the next run, with no recompile.
inline float tunable(const char* name, float value, float min, float max) {
  return lcjit_tunable(name, value, min, max);
}
inline V2f funcTangent(int id, float x) {
  V2f v;
  lcjit_func_tangent(id, x, &v.x);
  return v;
}

// §6.10 Random numbers.
inline double ran(double range) { return lcjit_ran(range); }
inline void sran(long seed) { lcjit_sran(seed); }
inline void SeedGillespie(long seed) { lcjit_seed_gillespie(seed); }
inline double GillespieTime() { return lcjit_gillespie_time(); }
inline void ResetGillespie() { lcjit_reset_gillespie(); }

// lcjit: a named number this run reports (its last value under each name): what a sweep records
// per run beside the string's own measures (docs/sweeps.md).
inline void Report(const char* name, double value) { lcjit_report(name, value); }

// §6.9 Input and output.
inline void Printf(const char* fmt, ...) {
  char small[512];
  __builtin_va_list ap;
  __builtin_va_start(ap, fmt);
  int n = vsnprintf(small, sizeof small, fmt, ap);
  __builtin_va_end(ap);
  if (n < (int)sizeof small) {
    lcjit_print(small);
    return;
  }
  std::string big(n + 1, '\0');
  __builtin_va_start(ap, fmt);
  vsnprintf(&big[0], big.size(), fmt, ap);
  __builtin_va_end(ap);
  lcjit_print(big.c_str());
}
inline void OutputString(const char* path) { lcjit_output_string(path); }
inline void LoadString(const char* path) { lcjit_load_string(path); }

// §6.3 Curves and surfaces: contours (.con/.cset) and the view file's surfaces.
inline V3f __lc_curve(int id, float t, int what) {
  V3f v;
  lcjit_curve(id, t, what, &v.x);
  return v;
}
inline float curveX(int id, float t) { return __lc_curve(id, t, 0).x; }
inline float curveY(int id, float t) { return __lc_curve(id, t, 0).y; }
inline float curveZ(int id, float t) { return __lc_curve(id, t, 0).z; }
inline V2f curveXY(int id, float t) {
  V3f v = __lc_curve(id, t, 0);
  return V2f(v.x, v.y);
}
inline V3f curveXYZ(int id, float t) { return __lc_curve(id, t, 0); }
inline V3f curveNormal(int id, float t) { return __lc_curve(id, t, 1); }
// lpfg's typed forms of curveXYZ and curveXY.
inline V3f curveXYZf(int id, float t) { return curveXYZ(id, t); }
inline V3d curveXYZd(int id, float t) { return curveXYZ(id, t); }
inline V2f curveXYf(int id, float t) { return curveXY(id, t); }
inline V2d curveXYd(int id, float t) { return curveXY(id, t); }
inline float curveGAL(int id) { return lcjit_curve_length(id); }
inline void curveScale(int id, float x, float y, float z) { lcjit_curve_op(0, id, 0, x, y, z); }
inline void curveSetPoint(int id, int p, float x, float y, float z) { lcjit_curve_op(1, id, p, x, y, z); }
inline void curveRecalculate(int id) { lcjit_curve_op(2, id, 0, 0, 0, 0); }
inline void curveReset(int id) { lcjit_curve_op(3, id, 0, 0, 0, 0); }
inline SurfaceObj GetSurface(int id) {
  SurfaceObj s;
  lcjit_get_surface(id, &s.points[0].x);
  return s;
}
inline V3f GetSurfacePoint(int id, int k) {
  V3f v;
  lcjit_get_surface_point(id, k, &v.x);
  return v;
}

// §10.1 B-spline surfaces: the view file's `bsurface:` entries and operations on them.
template <int N, int M> const V3f BsurfaceObjNM<N, M>::Get(int i, int j) const {
  if (i < N && j < M) return V3f(_v[i][j].x, _v[i][j].y, _v[i][j].z);
  std::cout << "BsurfaceObjNM dimensions exceeded" << std::endl;
  return V3f(0, 0, 0);
}
template <int N, int M> void BsurfaceObjNM<N, M>::Set(int i, int j, const V3f& v) {
  if (i < N && j < M)
    _v[i][j] = v;
  else
    std::cout << "BsurfaceObjNM dimensions exceeded" << std::endl;
}
// lpfg's arithmetic lives in the host (runtime/files/BSplineSurfaces.h): nets of different
// sizes are refined or coarsened first, and sums are taken in double, as lpfg's are. Unused
// entries of a result are 0 (lpfg leaves them uninitialised).
template <int N, int M> BsurfaceObjNM<N, M> __lc_bsurface(int id) {
  BsurfaceObjNM<N, M> s{};
  int rows = 0, columns = 0;
  lcjit_get_bsurface(id, N, M, &rows, &columns, reinterpret_cast<float*>(&s));
  s.Resize(rows, columns);
  return s;
}
template <int N, int M>
BsurfaceObjNM<N, M> __lc_bsurface_op(int op, const BsurfaceObjNM<N, M>& l, const BsurfaceObjNM<N, M>& r, float alpha,
                                     int rows, int columns) {
  BsurfaceObjNM<N, M> s{};
  int n = 0, m = 0;
  lcjit_bsurface_op(op, N, M, reinterpret_cast<const float*>(&l), l.RowCount(), l.ColumnCount(),
                    reinterpret_cast<const float*>(&r), r.RowCount(), r.ColumnCount(), alpha, rows, columns,
                    reinterpret_cast<float*>(&s), &n, &m);
  s.Resize(n, m);
  return s;
}
inline BsurfaceObjS GetBsurfaceS(int id) { return __lc_bsurface<10, 10>(id); }
inline BsurfaceObjM GetBsurfaceM(int id) { return __lc_bsurface<32, 32>(id); }
// The smaller net is refined until the sizes match; the sum has the left operand's size.
template <int N, int M> BsurfaceObjNM<N, M> operator+(const BsurfaceObjNM<N, M>& l, const BsurfaceObjNM<N, M>& r) {
  return __lc_bsurface_op(0, l, r, 0, 0, 0);
}
// l and r resized to rows x columns (at most N x M; lpfg refines while rows >= 2n - 3 and
// coarsens while rows < n and rows >= 10), then (1-alpha)*l + alpha*r.
template <int N, int M>
BsurfaceObjNM<N, M> Interpolate(const BsurfaceObjNM<N, M>& l, const BsurfaceObjNM<N, M>& r, float alpha, int rows,
                                int columns) {
  return __lc_bsurface_op(1, l, r, alpha, rows, columns);
}
template <int N, int M> V3f Get(const BsurfaceObjNM<N, M>& s, int i, int j) { return s.Get(i, j); }
template <int N, int M> BsurfaceObjNM<N, M> Set(const BsurfaceObjNM<N, M>& s, int i, int j, V3f p) {
  BsurfaceObjNM<N, M> r = s;
  r.Set(i, j, p);
  return r;
}

// §6.4 View functions and §6.8 mouse and menu: fed by the window; neutral values without one.
// A view the model has no view group for is not opened (lpfg: "Invalid vgroup id = 1. Ignored").
inline int NumOfViews() { return lcjit_num_of_views(); }
inline void UseView(int id) { lcjit_use_view(id, 1); }
inline void CloseView(int id) { lcjit_use_view(id, 0); }
inline float vvXmin(int id) { return lcjit_view_box(id, 0, 0); }
inline float vvYmin(int id) { return lcjit_view_box(id, 1, 0); }
inline float vvZmin(int id) { return lcjit_view_box(id, 2, 0); }
inline float vvXmax(int id) { return lcjit_view_box(id, 0, 1); }
inline float vvYmax(int id) { return lcjit_view_box(id, 1, 1); }
inline float vvZmax(int id) { return lcjit_view_box(id, 2, 1); }
inline float vvScale(int id) { return lcjit_view_scale(id); }
inline CameraPosition GetCameraPosition(int id) {
  CameraPosition c{};
  lcjit_camera_position(id, &c);
  return c;
}
inline MouseStatus GetMouseStatus() {
  MouseStatus s;
  lcjit_mouse_status(&s);
  return s;
}
// §10.2: lcjit has no tablet driver; the tablet follows the mouse (docs/compatibility.md).
inline TabletStatus GetTabletStatus() {
  TabletStatus s;
  lcjit_tablet_status(&s);
  return s;
}
inline void UserMenuItem(const char* label, unsigned int code) { lcjit_user_menu_item(label, (int)code); }
inline int UserMenuChoice() { return lcjit_user_menu_choice(); }
inline void UserMenuClear() { lcjit_user_menu_clear(); }

// §10.3 Terrain (the view file's `terrain:`).
inline bool terrainHeightAt(V3f world, V3f& onTerrain) { return lcjit_terrain_query(0, &world.x, &onTerrain.x) != 0; }
inline bool terrainNormalAt(V3f world, V3f& normal) { return lcjit_terrain_query(1, &world.x, &normal.x) != 0; }
inline void terrainVisibilityAll(VisibilityMode mode) { lcjit_terrain_visibility((int)mode, -1, nullptr); }
inline void terrainVisibilityPatch(VisibilityMode mode, int level, V3f world) {
  lcjit_terrain_visibility((int)mode, level, &world.x);
}
inline void scaleTerrainBy(float factor) { lcjit_terrain_scale(factor); }

// §6.11 Environment(): interpret for the environment after EndEach; NoEnvironment(): not at
// all; IgnoreEnvironment() says which was called last (false at first, as in lpfg).
inline void Environment() { lcjit_environment(0); }
inline void NoEnvironment() { lcjit_environment(1); }
inline bool IgnoreEnvironment() { return lcjit_environment(2) != 0; }

#endif
