// The predefined vector types of L+C (manual §6.2), with lpfg's exact surface: the plain structs
// V2t<T>/V3t<T> (V2tf, V3td ..., used as module parameters) carry the operators and methods, and
// V2<T>/V3<T> (V2f, V3d ...) add the constructors, among them the implicit conversions between
// float and double vectors and from 2D to 3D that lpfg models rely on. Operators take and return
// V2t/V3t by value, Normalize() divides by the length without checking it, and operator[] gives
// a double, all as in lpfg, so model code computes what it computes there.
// Shared by model code and the host runtime; a vector is laid out as plain {x,y[,z]}.
#pragma once
#include <cmath>

extern "C" {
// What lpfg's curve functions return (a C struct): convertible to V2f/V2d, V3f/V3d.
struct __lc_V2f {
  float x, y;
};
struct __lc_V3f {
  float x, y, z;
};
}

template <typename T> struct V2t {
  T x, y;

  void Set(T nx, T ny) {
    x = nx;
    y = ny;
  }
  T Length() const { return std::sqrt(x * x + y * y); }
  V2t& Normalize() { return *this /= Length(); }
  V2t Normalized() const {
    V2t r = *this;
    return r /= Length();
  }
  V2t& operator+=(V2t r) {
    x += r.x;
    y += r.y;
    return *this;
  }
  V2t& operator-=(V2t r) {
    x -= r.x;
    y -= r.y;
    return *this;
  }
  V2t& operator*=(T s) {
    x *= s;
    y *= s;
    return *this;
  }
  V2t& operator/=(T s) {
    x /= s;
    y /= s;
    return *this;
  }
  friend V2t operator-(V2t v) { return V2t{-v.x, -v.y}; }
  friend V2t operator+(V2t l, V2t r) { return V2t{l.x + r.x, l.y + r.y}; }
  friend V2t operator-(V2t l, V2t r) { return V2t{l.x - r.x, l.y - r.y}; }
  friend V2t operator*(V2t v, T s) { return V2t{v.x * s, v.y * s}; }
  friend V2t operator*(T s, V2t v) { return v * s; }
  friend V2t operator/(V2t v, T s) { return V2t{v.x / s, v.y / s}; }
  // Dot product.
  friend T operator*(V2t l, V2t r) { return l.x * r.x + l.y * r.y; }
};

template <typename T> struct V3t {
  T x, y, z;

  void Set(T nx, T ny, T nz) {
    x = nx;
    y = ny;
    z = nz;
  }
  T Length() const { return std::sqrt(x * x + y * y + z * z); }
  V3t& Normalize() { return *this /= Length(); }
  V3t Normalized() const {
    V3t r = *this;
    return r /= Length();
  }
  // Component c (0 x, 1 y, anything else z), as a double whatever T is.
  double operator[](int c) const { return c == 0 ? x : c == 1 ? y : z; }
  V3t& operator+=(V3t r) {
    x += r.x;
    y += r.y;
    z += r.z;
    return *this;
  }
  V3t& operator-=(V3t r) {
    x -= r.x;
    y -= r.y;
    z -= r.z;
    return *this;
  }
  V3t& operator*=(T s) {
    x *= s;
    y *= s;
    z *= s;
    return *this;
  }
  V3t& operator/=(T s) {
    x /= s;
    y /= s;
    z /= s;
    return *this;
  }
  friend V3t operator-(V3t v) { return V3t{-v.x, -v.y, -v.z}; }
  friend V3t operator+(V3t l, V3t r) { return V3t{l.x + r.x, l.y + r.y, l.z + r.z}; }
  friend V3t operator-(V3t l, V3t r) { return V3t{l.x - r.x, l.y - r.y, l.z - r.z}; }
  friend V3t operator*(V3t v, T s) { return V3t{v.x * s, v.y * s, v.z * s}; }
  friend V3t operator*(T s, V3t v) { return v * s; }
  friend V3t operator/(V3t v, T s) { return V3t{v.x / s, v.y / s, v.z / s}; }
  // Dot product.
  friend T operator*(V3t l, V3t r) { return l.x * r.x + l.y * r.y + l.z * r.z; }
  // Cross product.
  friend V3t operator%(V3t l, V3t r) {
    return V3t{l.y * r.z - l.z * r.y, l.z * r.x - l.x * r.z, l.x * r.y - l.y * r.x};
  }
};

typedef V2t<float> V2tf;
typedef V2t<double> V2td;
typedef V3t<float> V3tf;
typedef V3t<double> V3td;

template <typename T> struct V2 : V2t<T> {
  V2() : V2t<T>{0, 0} {}
  V2(T nx, T ny) : V2t<T>{nx, ny} {}
  V2(const V2tf& v) : V2t<T>{static_cast<T>(v.x), static_cast<T>(v.y)} {}
  V2(const V2td& v) : V2t<T>{static_cast<T>(v.x), static_cast<T>(v.y)} {}
  V2(const __lc_V2f& v) : V2t<T>{v.x, v.y} {}
};

template <typename T> struct V3 : V3t<T> {
  V3() : V3t<T>{0, 0, 0} {}
  V3(T nx, T ny, T nz) : V3t<T>{nx, ny, nz} {}
  V3(const V3tf& v) : V3t<T>{static_cast<T>(v.x), static_cast<T>(v.y), static_cast<T>(v.z)} {}
  V3(const V3td& v) : V3t<T>{static_cast<T>(v.x), static_cast<T>(v.y), static_cast<T>(v.z)} {}
  // A 2D vector as a 3D one in the z = 0 plane.
  V3(const V2tf& v) : V3t<T>{static_cast<T>(v.x), static_cast<T>(v.y), 0} {}
  V3(const V2td& v) : V3t<T>{static_cast<T>(v.x), static_cast<T>(v.y), 0} {}
  V3(const __lc_V3f& v) : V3t<T>{v.x, v.y, v.z} {}
};

typedef V2<float> V2f;
typedef V2<double> V2d;
typedef V3<float> V3f;
typedef V3<double> V3d;

// lpfg's Normalize(v), and the manual's normalize(v) (§6.2.3): a normalized copy. Templates, so
// that a model's own function of the same name and vector type takes precedence.
template <class Vector> Vector Normalize(Vector v) { return v.Normalize(); }
template <class Vector> Vector normalize(Vector v) { return v.Normalize(); }
