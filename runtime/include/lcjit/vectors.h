// The predefined vector types of L+C (manual §6.2): V2f, V2d, V3f, V3d and their operators.
// Shared by model code and the host runtime, so the layout is plain {x,y[,z]}.
#pragma once
#include <cmath>

template <class T> struct __lc_V2 {
  T x = 0, y = 0;
  constexpr __lc_V2() = default;
  constexpr __lc_V2(T ax, T ay) : x(ax), y(ay) {}
  template <class U> constexpr explicit __lc_V2(const __lc_V2<U>& o) : x(T(o.x)), y(T(o.y)) {}
  void Set(T ax, T ay) { x = ax; y = ay; }
  T Length() const { return std::sqrt(x * x + y * y); }
  __lc_V2& Normalize() { T l = Length(); if (l > 0) { x /= l; y /= l; } return *this; }
  __lc_V2 Normalized() const { __lc_V2 v = *this; return v.Normalize(); }
  __lc_V2& operator+=(const __lc_V2& o) { x += o.x; y += o.y; return *this; }
  __lc_V2& operator-=(const __lc_V2& o) { x -= o.x; y -= o.y; return *this; }
  __lc_V2& operator*=(T s) { x *= s; y *= s; return *this; }
  __lc_V2& operator/=(T s) { x /= s; y /= s; return *this; }
  friend __lc_V2 operator+(__lc_V2 a, const __lc_V2& b) { return a += b; }
  friend __lc_V2 operator-(__lc_V2 a, const __lc_V2& b) { return a -= b; }
  friend __lc_V2 operator-(const __lc_V2& a) { return {-a.x, -a.y}; }
  friend __lc_V2 operator*(__lc_V2 a, T s) { return a *= s; }
  friend __lc_V2 operator*(T s, __lc_V2 a) { return a *= s; }
  friend __lc_V2 operator/(__lc_V2 a, T s) { return a /= s; }
  friend T operator*(const __lc_V2& a, const __lc_V2& b) { return a.x * b.x + a.y * b.y; }
  friend bool operator==(const __lc_V2& a, const __lc_V2& b) { return a.x == b.x && a.y == b.y; }
};

template <class T> struct __lc_V3 {
  T x = 0, y = 0, z = 0;
  constexpr __lc_V3() = default;
  constexpr __lc_V3(T ax, T ay, T az) : x(ax), y(ay), z(az) {}
  template <class U> constexpr explicit __lc_V3(const __lc_V3<U>& o) : x(T(o.x)), y(T(o.y)), z(T(o.z)) {}
  void Set(T ax, T ay, T az) { x = ax; y = ay; z = az; }
  T Length() const { return std::sqrt(x * x + y * y + z * z); }
  __lc_V3& Normalize() { T l = Length(); if (l > 0) { x /= l; y /= l; z /= l; } return *this; }
  __lc_V3 Normalized() const { __lc_V3 v = *this; return v.Normalize(); }
  __lc_V3& operator+=(const __lc_V3& o) { x += o.x; y += o.y; z += o.z; return *this; }
  __lc_V3& operator-=(const __lc_V3& o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
  __lc_V3& operator*=(T s) { x *= s; y *= s; z *= s; return *this; }
  __lc_V3& operator/=(T s) { x /= s; y /= s; z /= s; return *this; }
  friend __lc_V3 operator+(__lc_V3 a, const __lc_V3& b) { return a += b; }
  friend __lc_V3 operator-(__lc_V3 a, const __lc_V3& b) { return a -= b; }
  friend __lc_V3 operator-(const __lc_V3& a) { return {-a.x, -a.y, -a.z}; }
  friend __lc_V3 operator*(__lc_V3 a, T s) { return a *= s; }
  friend __lc_V3 operator*(T s, __lc_V3 a) { return a *= s; }
  friend __lc_V3 operator/(__lc_V3 a, T s) { return a /= s; }
  friend T operator*(const __lc_V3& a, const __lc_V3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
  // Cross product.
  friend __lc_V3 operator%(const __lc_V3& a, const __lc_V3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
  }
  friend bool operator==(const __lc_V3& a, const __lc_V3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }
};

typedef __lc_V2<float> V2f;
typedef __lc_V2<double> V2d;
typedef __lc_V3<float> V3f;
typedef __lc_V3<double> V3d;
// lpfg's module declarations name the same types V2tf/V3tf/V2td/V3td.
typedef V2f V2tf;
typedef V2d V2td;
typedef V3f V3tf;
typedef V3d V3td;

inline V2f normalize(V2f v) { return v.Normalize(); }
inline V2d normalize(V2d v) { return v.Normalize(); }
inline V3f normalize(V3f v) { return v.Normalize(); }
inline V3d normalize(V3d v) { return v.Normalize(); }
