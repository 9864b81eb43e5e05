// Predefined L+C data types that appear as module parameters or function results (manual §5-§7):
// text, surfaces, mouse status, camera position, environment arrays. Shared by model code and host.
#pragma once
#include <cstdint>
#include <cstring>
#include "vectors.h"

typedef const char* __lc_Text;

// A single bicubic Bézier patch (manual §7.1): 16 control points, row-major.
struct SurfaceObj {
  V3f points[16];
  void Set(int id, const float* arr) { if (id >= 0 && id < 16) points[id] = V3f(arr[0], arr[1], arr[2]); }
  void Set(int id, const V3f& v) { if (id >= 0 && id < 16) points[id] = v; }
  V3f Get(int id) const { return (id >= 0 && id < 16) ? points[id] : V3f(); }
  void Scale(V3f s) { for (auto& p : points) { p.x *= s.x; p.y *= s.y; p.z *= s.z; } }
  SurfaceObj operator*(float r) const { SurfaceObj o = *this; for (auto& p : o.points) p *= r; return o; }
  friend SurfaceObj operator*(float r, const SurfaceObj& s) { return s * r; }
  friend SurfaceObj operator+(const SurfaceObj& l, const SurfaceObj& r) {
    SurfaceObj o = l; for (int i = 0; i < 16; ++i) o.points[i] += r.points[i]; return o;
  }
};

// B-spline surfaces (manual §10.1, deprecated); only their identity matters in batch mode.
struct BsurfaceObjS { int id; };
struct BsurfaceObjM { int id; };

struct MouseStatus {
  int viewNum;
  int viewX, viewY;
  V3d atFront, atRear, atMiddle;
  bool lbDown, lbPushed, lbReleased;
  bool mbDown, mbPushed, mbReleased;
  bool rbDown, rbPushed, rbReleased;
};

struct CameraPosition {
  V3f position, lookat;
  V3f head, left, up;
  float scale;
};

// Environment exchange array (Environment Programs manual): 20 values.
struct EA20Array { float data[20]; float& operator[](int i) { return data[i]; } float operator[](int i) const { return data[i]; } };

enum POVRayMeshMode { POVRayMeshModeNone = 0 };
