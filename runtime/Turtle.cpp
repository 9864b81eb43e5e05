// The turtle core (see Turtle.h). Rotation conventions are those of the brief and lpfg's
// corrected rotations: Left turns H towards L about U, Up turns H towards U about L,
// RollR turns L towards U about H.
#include "Turtle.h"

#include <cmath>
#include <cstring>

namespace lcjit::runtime {
namespace {

constexpr float kEpsilon = 1e-5f;
constexpr double kDegrees = 3.14159265358979323846 / 180.0;

template <class T> T param(const char* rec, size_t offset) {
  T v;
  std::memcpy(&v, rec + offset, sizeof v);
  return v;
}
template <class T> void setParam(char* rec, size_t offset, T v) { std::memcpy(rec + offset, &v, sizeof v); }

// Offsets of the parameters in predefined module records (lpfg's layout).
template <class R> size_t p0() { return offsetof(R, p0); }

V3f cross(V3f a, V3f b) { return a % b; }

V3f toV3f(const char* rec, size_t off, __lc_ModuleId kind) {
  switch (kind) {
    case 0: { V2f v = param<V2f>(rec, off); return V3f(v.x, v.y, 0); }
    case 1: { V2d v = param<V2d>(rec, off); return V3f((float)v.x, (float)v.y, 0); }
    case 2: return param<V3f>(rec, off);
    default: { V3d v = param<V3d>(rec, off); return V3f((float)v.x, (float)v.y, (float)v.z); }
  }
}

}  // namespace

void Turtle::reset() {
  state_ = TurtleState();
  stack_.clear();
}

void Turtle::rotate(V3f& a, V3f& b, float degrees) {
  double r = degrees * kDegrees;
  float c = (float)std::cos(r), s = (float)std::sin(r);
  V3f na = a * c + b * s;
  V3f nb = b * c - a * s;
  a = na;
  b = nb;
}

// Rodrigues rotation of the whole frame about a world-space axis.
void Turtle::rotateAbout(V3f axis, float degrees) {
  float len = axis.Length();
  if (len < kEpsilon) return;
  axis /= len;
  double r = degrees * kDegrees;
  float c = (float)std::cos(r), s = (float)std::sin(r);
  auto rot = [&](V3f v) { return v * c + cross(axis, v) * s + axis * ((axis * v) * (1 - c)); };
  state_.heading = rot(state_.heading);
  state_.left = rot(state_.left);
  state_.up = rot(state_.up);
}

V3f Turtle::mapPoint(V3f p) const {
  if (!state_.hasCoordinateSystem) return p;
  return state_.csOrigin + state_.csX * p.x + state_.csY * p.y + state_.csZ * p.z;
}

void Turtle::execute(char* rec) {
  TurtleState& t = state_;
  __lc_ModuleId id = ModuleTable::idAt(rec);
  auto f0 = [&] { return param<float>(rec, p0<__lc_R_F>()); };
  switch (id) {
    case __lc_id_SB: stack_.push_back(t); break;
    case __lc_id_EB:
      if (!stack_.empty()) {
        t = stack_.back();
        stack_.pop_back();
      }
      break;
    case __lc_id_F:
    case __lc_id_f:
    case __lc_id_G:
    case __lc_id_g: t.position += t.heading * f0(); break;
    case __lc_id_Left: rotate(t.heading, t.left, f0()); break;
    case __lc_id_Right: rotate(t.heading, t.left, -f0()); break;
    case __lc_id_Up: rotate(t.heading, t.up, f0()); break;
    case __lc_id_Down: rotate(t.heading, t.up, -f0()); break;
    case __lc_id_RollR: rotate(t.left, t.up, f0()); break;
    case __lc_id_RollL: rotate(t.left, t.up, -f0()); break;
    case __lc_id_TurnAround: rotate(t.heading, t.left, 180); break;
    case __lc_id_IncColor: t.color = t.color >= 255 ? 1 : t.color + 1; break;
    case __lc_id_DecColor: t.color = t.color <= 1 ? 255 : t.color - 1; break;
    case __lc_id_SetColor: {
      int c = param<int>(rec, p0<__lc_R_SetColor>());
      if (c >= 1 && c <= 255) t.color = c;
      break;
    }
    case __lc_id_SetWidth: {
      float w = param<float>(rec, p0<__lc_R_SetWidth>());
      if (w > 0) t.width = w;
      break;
    }
    case __lc_id_GetPos:
    case __lc_id_GetHead:
    case __lc_id_GetLeft:
    case __lc_id_GetUp: {
      V3f v = id == __lc_id_GetPos ? t.position : id == __lc_id_GetHead ? t.heading : id == __lc_id_GetLeft ? t.left : t.up;
      setParam(rec, offsetof(__lc_R_GetPos, p0), v.x);
      setParam(rec, offsetof(__lc_R_GetPos, p1), v.y);
      setParam(rec, offsetof(__lc_R_GetPos, p2), v.z);
      break;
    }
    case __lc_id_MoveTo:
    case __lc_id_LineTo:
      t.position = V3f(param<float>(rec, offsetof(__lc_R_MoveTo, p0)), param<float>(rec, offsetof(__lc_R_MoveTo, p1)),
                       param<float>(rec, offsetof(__lc_R_MoveTo, p2)));
      if (id == __lc_id_LineTo) t.position = mapPoint(t.position);
      break;
    case __lc_id_MoveTo2f: t.position = toV3f(rec, p0<__lc_R_MoveTo2f>(), 0); break;
    case __lc_id_MoveTo2d: t.position = toV3f(rec, p0<__lc_R_MoveTo2d>(), 1); break;
    case __lc_id_MoveTo3f: t.position = toV3f(rec, p0<__lc_R_MoveTo3f>(), 2); break;
    case __lc_id_MoveTo3d: t.position = toV3f(rec, p0<__lc_R_MoveTo3d>(), 3); break;
    case __lc_id_MoveRel2f: t.position += toV3f(rec, p0<__lc_R_MoveRel2f>(), 0); break;
    case __lc_id_MoveRel2d: t.position += toV3f(rec, p0<__lc_R_MoveRel2d>(), 1); break;
    case __lc_id_MoveRel3f: t.position += toV3f(rec, p0<__lc_R_MoveRel3f>(), 2); break;
    case __lc_id_MoveRel3d: t.position += toV3f(rec, p0<__lc_R_MoveRel3d>(), 3); break;
    case __lc_id_LineTo2f: t.position = mapPoint(toV3f(rec, p0<__lc_R_LineTo2f>(), 0)); break;
    case __lc_id_LineTo2d: t.position = mapPoint(toV3f(rec, p0<__lc_R_LineTo2d>(), 1)); break;
    case __lc_id_LineTo3f: t.position = mapPoint(toV3f(rec, p0<__lc_R_LineTo3f>(), 2)); break;
    case __lc_id_LineTo3d: t.position = mapPoint(toV3f(rec, p0<__lc_R_LineTo3d>(), 3)); break;
    case __lc_id_LineRel2f: t.position += toV3f(rec, p0<__lc_R_LineRel2f>(), 0); break;
    case __lc_id_LineRel2d: t.position += toV3f(rec, p0<__lc_R_LineRel2d>(), 1); break;
    case __lc_id_LineRel3f: t.position += toV3f(rec, p0<__lc_R_LineRel3f>(), 2); break;
    case __lc_id_LineRel3d: t.position += toV3f(rec, p0<__lc_R_LineRel3d>(), 3); break;
    case __lc_id_Line2f: t.position = mapPoint(toV3f(rec, offsetof(__lc_R_Line2f, p1), 0)); break;
    case __lc_id_Line2d: t.position = mapPoint(toV3f(rec, offsetof(__lc_R_Line2d, p1), 1)); break;
    case __lc_id_Line3f: t.position = mapPoint(toV3f(rec, offsetof(__lc_R_Line3f, p1), 2)); break;
    case __lc_id_Line3d: t.position = mapPoint(toV3f(rec, offsetof(__lc_R_Line3d, p1), 3)); break;
    case __lc_id_SetCoordinateSystem: {
      float s = param<float>(rec, p0<__lc_R_SetCoordinateSystem>());
      t.hasCoordinateSystem = true;
      t.csOrigin = t.position;
      t.csX = t.heading * s;
      t.csY = t.left * s;
      t.csZ = t.up * s;
      break;
    }
    case __lc_id_RollToVert: {
      V3f l = cross(V3f(0, 1, 0), t.heading);
      float len = l.Length();
      if (len < kEpsilon) break;
      t.left = l / len;
      t.up = cross(t.heading, t.left);
      break;
    }
    case __lc_id_SetHead: {
      V3f h(param<float>(rec, offsetof(__lc_R_SetHead, p0)), param<float>(rec, offsetof(__lc_R_SetHead, p1)),
            param<float>(rec, offsetof(__lc_R_SetHead, p2)));
      V3f u(param<float>(rec, offsetof(__lc_R_SetHead, p3)), param<float>(rec, offsetof(__lc_R_SetHead, p4)),
            param<float>(rec, offsetof(__lc_R_SetHead, p5)));
      V3f l = cross(u, h);
      if (h.Length() < kEpsilon || u.Length() < kEpsilon || l.Length() < kEpsilon) break;
      t.heading = h.Normalized();
      t.up = u.Normalized();
      t.left = cross(t.up, t.heading).Normalized();
      break;
    }
    case __lc_id_SetHead3f: {
      V3f h = param<V3f>(rec, p0<__lc_R_SetHead3f>());
      if (h.Length() < kEpsilon) break;
      h.Normalize();
      V3f axis = cross(t.heading, h);
      float s = axis.Length(), c = t.heading * h;
      if (s < kEpsilon) {
        if (c < 0) rotate(t.heading, t.left, 180);
        break;
      }
      rotateAbout(axis, (float)(std::atan2(s, c) / kDegrees));
      break;
    }
    case __lc_id_RotateXYZ: {
      V3f axis = param<V3f>(rec, p0<__lc_R_RotateXYZ>());
      rotateAbout(axis, param<float>(rec, offsetof(__lc_R_RotateXYZ, p1)));
      break;
    }
    case __lc_id_RotateHLU:
    case __lc_id_Rotate: {
      V3f a = param<V3f>(rec, p0<__lc_R_RotateHLU>());
      rotateAbout(t.heading * a.x + t.left * a.y + t.up * a.z, param<float>(rec, offsetof(__lc_R_RotateHLU, p1)));
      break;
    }
    default: break;  // drawing, surfaces, tropisms...: the graphics layer's business
  }
}

}  // namespace lcjit::runtime
