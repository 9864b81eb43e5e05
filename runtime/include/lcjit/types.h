// Predefined L+C data types that appear as module parameters or function results (manual §5-§7,
// §10): text, surfaces, mouse and tablet status, camera position, environment arrays, terrain
// visibility. Their members and layouts are lpfg's, so that models use them as they do there and
// binary strings (.strb) holding them load in both. Shared by model code and the host runtime.
#pragma once
#include "vectors.h"

typedef const char* __lc_Text;

// A single bicubic Bézier patch (manual §7.1): 16 control points, row-major.
class SurfaceObj {
public:
  void Set(int id, const float* arr) {
    points[id].x = arr[0];
    points[id].y = arr[1];
    points[id].z = arr[2];
  }
  void Set(int id, const V3f& v) { points[id] = v; }
  const float* Points() const { return &points[0].x; }
  V3f Get(int i) const { return points[i]; }
  void Scale(V3f s) {
    for (V3tf& p : points) {
      p.x *= s.x;
      p.y *= s.y;
      p.z *= s.z;
    }
  }
  friend SurfaceObj operator*(SurfaceObj s, float r) {
    s.Scale(V3f(r, r, r));
    return s;
  }
  friend SurfaceObj operator*(float r, const SurfaceObj& s) { return s * r; }
  friend SurfaceObj operator+(const SurfaceObj& l, const SurfaceObj& r) {
    SurfaceObj o;
    for (int i = 0; i < 16; ++i) o.points[i] = l.points[i] + r.points[i];
    return o;
  }

  // lpfg keeps them private; lcjit's runtime reads and writes them.
  V3tf points[16];
};

// A B-spline surface of at most N x M control points (manual §10.1): n_u x n_v of them are used.
template <int N, int M> class BsurfaceObjNM {
public:
  friend BsurfaceObjNM operator*(BsurfaceObjNM s, float r) {
    s.Scale(V3f(r, r, r));
    return s;
  }
  friend BsurfaceObjNM operator*(float r, const BsurfaceObjNM& s) { return s * r; }
  // A copy of the control points as new[]'d rows (the caller deletes them), and the size used.
  friend V3f** GetControlPoints(const BsurfaceObjNM& s, int& n, int& m) {
    V3f** t = new V3f*[N];
    n = s.n_u;
    m = s.n_v;
    for (int i = 0; i < N; ++i) {
      t[i] = new V3f[M];
      for (int j = 0; j < M; ++j) t[i][j] = s._v[i][j];
    }
    return t;
  }
  // Fills `res` with n x m points of rows made by GetControlPoints, and deletes the rows.
  friend BsurfaceObjNM& ConstructBsurfaceObj(V3f** t, int n, int m, BsurfaceObjNM& res) {
    res.n_u = n;
    res.n_v = m;
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < m; ++j) res._v[i][j] = t[i][j];
      delete[] t[i];
    }
    delete[] t;
    return res;
  }
  void Scale(V3f s) {
    for (int i = 0; i < N; ++i)
      for (int j = 0; j < M; ++j) _v[i][j].Set(_v[i][j].x * s.x, _v[i][j].y * s.y, _v[i][j].z * s.z);
  }
  const V3f Get(int i, int j) const;
  void Set(int i, int j, const V3f& v);
  int RowCount() const { return n_u; }     // lcjit: rows used (lpfg keeps them private)
  int ColumnCount() const { return n_v; }  // lcjit: columns used
  void Resize(int n, int m) {              // lcjit: how the host fills one in
    n_u = n;
    n_v = m;
  }

private:
  V3tf _v[N][M];
  int n_u;
  int n_v;
};
typedef BsurfaceObjNM<10, 10> BsurfaceObjS;
typedef BsurfaceObjNM<32, 32> BsurfaceObjM;

struct MouseStatus {
  int viewNum;
  int viewX, viewY;
  V3td atFront, atRear, atMiddle;
  double selectDepth;
  V3td selectPoint;
  int keypressed;
  bool lbPushed, lbDown, lbReleased;

  MouseStatus()
      : viewNum(0), viewX(0), viewY(0), atFront(), atRear(), atMiddle(), selectDepth(0), selectPoint(), keypressed(0),
        lbPushed(false), lbDown(false), lbReleased(false) {}
};

// The tablet pointer (manual §10.2); lcjit feeds it from the mouse.
struct TabletStatus {
  bool connected;
  int viewX, viewY;
  float azimuth, altitude;
  double pressure;
  unsigned int cursorT, buttonState;
  V3d atFront, atRear;

  TabletStatus()
      : connected(false), viewX(0), viewY(0), azimuth(0), altitude(0), pressure(0), cursorT(0), buttonState(0),
        atFront(0, 0, 0), atRear(0, 0, 0) {}
};

struct CameraPosition {
  V3tf position, lookat;
  V3tf head, left, up;
  float scale;
};

// Visibility of terrain patches (manual §10.3).
enum VisibilityMode { Shaded, Hidden, Wireframe };
// How PovRayStart writes meshes: one instanced mesh per tree, or one condensed mesh.
enum POVRayMeshMode { Instance, Single };

// A fixed-size array that is a value (an array parameter would decay to a pointer).
template <class T, int length> struct __lc_EncapsulatedArray {
  T data[length];
  const T& operator[](int i) const { return data[i]; }
  T& operator[](int i) { return data[i]; }
  int Length() const { return length; }
  const T* Array() const { return data; }
};
// The parameters of the EA20 environment module.
typedef __lc_EncapsulatedArray<float, 20> EA20Array;
