// lpfg's quaternions (lpfg/quaternion.h) as its Vector3d::RotateBy uses them: the turtle's
// rotations and the view file's deprecated `view:` angles rotate vectors the same way, with the
// same float operations.
#pragma once
#include "runtime/include/lcjit/vectors.h"

namespace lcjit::runtime {

struct Quat {
  float a, x, y, z;
};

inline Quat operator*(const Quat& p, const Quat& q) {
  return {p.a * q.a - (p.x * q.x + p.y * q.y + p.z * q.z), p.a * q.x + q.a * p.x + p.y * q.z - p.z * q.y,
          p.a * q.y + q.a * p.y + p.z * q.x - p.x * q.z, p.a * q.z + q.a * p.z + p.x * q.y - p.y * q.x};
}

// v rotated by q: q⁻¹·(0,v)·q with q⁻¹ = conj(q)·(1/|q|²), the reciprocal multiplied as lpfg's
// Quaternion::Invert does (so q need not be a unit quaternion, and the sense is opposite to
// q·v·q⁻¹).
inline V3f rotatedBy(V3f v, const Quat& q) {
  float n = 1.0f / (q.a * q.a + q.x * q.x + q.y * q.y + q.z * q.z);
  Quat inv{q.a * n, q.x * -n, q.y * -n, q.z * -n};
  Quat r = (inv * Quat{0.0f, v.x, v.y, v.z}) * q;
  return V3f(r.x, r.y, r.z);
}

}  // namespace lcjit::runtime
