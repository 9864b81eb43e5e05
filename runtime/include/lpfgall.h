// lcjit's model API header, the counterpart of lpfg's <lpfgall.h>: what L+C model code may use
// (manual §5-§7). Precompiled once; every model translation unit is compiled against it.
#ifndef LCJIT_LPFGALL_H
#define LCJIT_LPFGALL_H

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "lcjit/abi.h"
#include "lcjit/repl.h"

// Successor writers of the predefined modules: produce F(x) calls __lc_emit_F(ctx, x).
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

// §6.5 Animation functions: Stop works everywhere; the rest need a window.
inline void Stop() { lcjit_stop(); }
inline int StepNo() { return lcjit_step_no(); }
inline void DisplayFrame() { lcjit_animation_request(0); }
inline void OutputFrame(const char* path) { lcjit_output_frame(path); }
inline void RunSimulation() { lcjit_animation_request(1); }
inline void PauseSimulation() { lcjit_animation_request(2); }
inline void DelayWrite() {}
inline void Write() {}
inline void StartPerformance() {}
inline void StopPerformance() {}

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

// §6.9 Input and output.
inline void Printf(const char* fmt, ...) {
  char small[512];
  va_list ap;
  va_start(ap, fmt);
  int n = std::vsnprintf(small, sizeof small, fmt, ap);
  va_end(ap);
  if (n < (int)sizeof small) {
    lcjit_print(small);
    return;
  }
  std::vector<char> big(n + 1);
  va_start(ap, fmt);
  std::vsnprintf(big.data(), big.size(), fmt, ap);
  va_end(ap);
  lcjit_print(big.data());
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
inline V2f curveXY(int id, float t) { V3f v = __lc_curve(id, t, 0); return V2f(v.x, v.y); }
inline V3f curveXYZ(int id, float t) { return __lc_curve(id, t, 0); }
inline V3f curveNormal(int id, float t) { return __lc_curve(id, t, 1); }
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

// §6.4 View functions and §6.8 mouse and menu: fed by the window; neutral values without one.
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
  MouseStatus s{};
  lcjit_mouse_status(&s);
  return s;
}
inline void UserMenuItem(const char* label, int code) { lcjit_user_menu_item(label, code); }
inline int UserMenuChoice() { return lcjit_user_menu_choice(); }
inline void UserMenuClear() { lcjit_user_menu_clear(); }

// §6.11 Environment programs are not connected in batch mode.
inline void Environment() {}
inline void NoEnvironment() {}
inline bool IgnoreEnvironment() { return true; }

#endif
