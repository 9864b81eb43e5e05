// The turtle's motion and module dispatch (see Turtle.h). Conventions are lpfg's (research notes
// from its source): Left turns H towards L about U, Up turns H towards U about L, RollR turns L
// towards U about H; `corrected rotation: off` flips Up/Down/RollL/RollR. F applies tropisms,
// moves, records a polygon vertex, then applies the simple tropism.
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

template <class R> size_t p0() { return offsetof(R, p0); }
template <class R> size_t p1() { return offsetof(R, p1); }

V3f cross(V3f a, V3f b) { return a % b; }

V3f toV3f(const char* rec, size_t off, int kind) {
  switch (kind) {
    case 0: { V2f v = param<V2f>(rec, off); return V3f(v.x, v.y, 0); }
    case 1: { V2d v = param<V2d>(rec, off); return V3f((float)v.x, (float)v.y, 0); }
    case 2: return param<V3f>(rec, off);
    default: { V3d v = param<V3d>(rec, off); return V3f((float)v.x, (float)v.y, (float)v.z); }
  }
}

// Rodrigues rotation of v about a unit axis.
V3f rotated(V3f v, V3f axis, float radians) {
  float c = std::cos(radians), s = std::sin(radians);
  return v * c + cross(axis, v) * s + axis * ((axis * v) * (1 - c));
}

}  // namespace

void Turtle::reset(const TurtleSetup& setup, Geometry* out) {
  setup_ = setup;
  view_ = setup.view ? setup.view : &defaults_;
  out_ = out;
  state_ = TurtleState();
  for (size_t i = 0; i < view_->tropisms.size() && i < kMaxTropisms; ++i)
    state_.elasticity[i] = view_->tropisms[i].elasticity;
  if (view_->simpleTropism) {
    state_.simpleTropism = view_->simpleTropism->direction;
    state_.simpleElasticity = view_->simpleTropism->elasticity;
  }
  stack_.clear();
  polygonOn_ = false;
  polygon_.clear();
  // The engine reuses its turtles: nothing may carry over (contours change between runs).
  transcript_ = nullptr;
  for (V3tf& p : userPatch_) p = V3f();
  rings_.clear();
}

void Turtle::finish() {
  polygonOn_ = false;
  polygon_.clear();
}

void Turtle::rotate(V3f& a, V3f& b, float degrees) {
  double r = degrees * kDegrees;
  float c = (float)std::cos(r), s = (float)std::sin(r);
  V3f na = a * c + b * s;
  V3f nb = b * c - a * s;
  a = na;
  b = nb;
}

void Turtle::rotateAbout(V3f axis, float degrees) {
  float len = axis.Length();
  if (len < kEpsilon) return;
  axis /= len;
  float r = (float)(degrees * kDegrees);
  state_.heading = rotated(state_.heading, axis, r);
  state_.left = rotated(state_.left, axis, r);
  state_.up = rotated(state_.up, axis, r);
}

V3f Turtle::mapDirection(V3f d) const {
  const TurtleState& t = state_;
  return t.csX * -d.x + t.csY * d.y + t.csZ * d.z;
}

V3f Turtle::mapPoint(V3f p) const { return state_.csOrigin + mapDirection(p) * state_.csScale; }

// Tropisms of the view file, applied before every F/f move (lpfg's rules, docs/graphics.md):
// the heading bends towards the combined tropism vector by min(|H × D|, 1) radians, and torques
// roll U about H away from their vector.
void Turtle::applyTropisms() {
  const auto& tropisms = view_->tropisms;
  if (tropisms.empty()) return;
  TurtleState& t = state_;
  V3f d(0, 0, 0), w(0, 0, 0);
  bool bend = false;
  for (size_t i = 0; i < tropisms.size() && i < kMaxTropisms; ++i) {
    const Tropism& tr = tropisms[i];
    V3f T = tr.direction * tr.intensity;
    float e = t.elasticity[i];
    if (tr.torque) {
      w += T * e;
      continue;
    }
    bend = true;
    float a = (float)(tr.angle * kDegrees);
    d += T * (e * std::cos(a));
    if (std::sin(a) != 0) {
      V3f hxt = cross(t.heading, T);
      float len = hxt.Length();
      V3f perp = len < kEpsilon ? cross(T, t.left) : cross(T, hxt) / len;
      d += perp * (e * std::sin(a));
    }
  }
  if (bend) {
    V3f r = cross(t.heading, d);
    float len = r.Length();
    if (len >= kEpsilon) {
      V3f axis = r / len;
      float alpha = len < 1 ? len : 1;
      t.heading = rotated(t.heading, axis, alpha).Normalized();
      t.up = rotated(t.up, axis, alpha).Normalized();
      t.left = cross(t.up, t.heading);
    }
  }
  float wl = w.Length();
  if (wl > 0) {
    V3f v = cross(t.heading, w);
    if (v.Length() > kEpsilon) {
      V3f wp = cross(v, t.heading).Normalized() * wl;
      V3f axis = cross(t.up, wp);
      float len = axis.Length();
      if (len > kEpsilon) {
        t.up = rotated(t.up, axis / len, -(len < 1 ? len : 1)).Normalized();
        t.left = cross(t.up, t.heading);
      }
    }
  }
}

// `stropism:` / Elasticity(e): after the move, H leans towards the direction by e·(D·U) and
// e·(D·L).
void Turtle::applySimpleTropism() {
  TurtleState& t = state_;
  float e = t.simpleElasticity;
  if (e == 0) return;
  float s1 = e * (t.simpleTropism * t.up);
  if (std::fabs(s1) <= 1) {
    float c1 = std::sqrt(1 - s1 * s1);
    V3f h = t.heading * c1 + t.up * s1;
    t.up = t.up * c1 - t.heading * s1;
    t.heading = h;
  }
  float s2 = e * (t.simpleTropism * t.left);
  if (std::fabs(s2) <= 1) {
    float c2 = std::sqrt(1 - s2 * s2);
    V3f h = t.heading * c2 + t.left * s2;
    t.left = t.left * c2 - t.heading * s2;
    t.heading = h;
  }
}

void Turtle::forward(float d, bool draw, bool polygonVertex) {
  TurtleState before = state_;
  applyTropisms();
  TurtleState& t = state_;
  V3f from = t.position;
  t.position += t.heading * d;
  if (polygonVertex && polygonOn_) {
    polygon_.push_back({t.position, t.up, t.color});
    extend(t.position);
  }
  applySimpleTropism();
  if (!out_) return;
  if (!draw) {
    extend(from);
    extend(t.position);
    return;
  }
  bool cylinders = view_->lineStyle == LineStyle::Cylinder;
  if (cylinders && t.cylinderOn) {
    CylinderPoint here = cylinderHere();
    drawFrustum(t.cylinder, here, d, true);
    t.cylinder = here;
  } else {
    drawSegment(before, d);
  }
}

// LineTo & co.: head for the target, draw an F of the distance, then restore the frame
// (lpfg routes them through F, so tropisms and the polygon flag apply).
void Turtle::lineTo(V3f target) {
  TurtleState& t = state_;
  V3f delta = target - t.position;
  float len = delta.Length();
  if (len < kEpsilon) return;
  V3f h0 = t.heading, l0 = t.left, u0 = t.up;
  t.heading = delta / len;
  V3f l = cross(t.up, t.heading);
  if (l.Length() < kEpsilon) l = V3f(-t.heading.y, t.heading.x, 0);
  if (l.Length() < kEpsilon) l = V3f(1, 0, 0);
  t.left = l.Normalized();
  t.up = cross(t.heading, t.left);
  forward(len, true, true);
  t.heading = h0;
  t.left = l0;
  t.up = u0;
}

void Turtle::pushBranch() {
  stack_.push_back(state_);
  if (state_.cylinderOn) state_.cylinderInherited = true;
}

void Turtle::popBranch() {
  if (stack_.empty()) return;  // lpfg: message, ignored
  state_ = stack_.back();
  stack_.pop_back();
}

void Turtle::execute(char* rec) {
  if (!transcript_) return executeModule(rec);
  TurtleState before = state_;
  executeModule(rec);
  describeTurtleCommand(*transcript_, rec, before, state_);
}

void Turtle::executeModule(char* rec) {
  TurtleState& t = state_;
  __lc_ModuleId id = ModuleTable::idAt(rec);
  auto f0 = [&] { return param<float>(rec, p0<__lc_R_F>()); };
  auto i0 = [&] { return param<int>(rec, p0<__lc_R_SetColor>()); };
  bool corrected = view_->correctedRotation;
  switch (id) {
    case __lc_id_SB: pushBranch(); break;
    case __lc_id_EB: popBranch(); break;
    case __lc_id_F: forward(f0(), true, true); break;
    case __lc_id_G: forward(f0(), true, false); break;
    case __lc_id_f: forward(f0(), false, true); break;
    case __lc_id_g: forward(f0(), false, false); break;
    case __lc_id_Left: rotate(t.heading, t.left, f0()); break;
    case __lc_id_Right: rotate(t.heading, t.left, -f0()); break;
    case __lc_id_Up: rotate(t.heading, t.up, corrected ? f0() : -f0()); break;
    case __lc_id_Down: rotate(t.heading, t.up, corrected ? -f0() : f0()); break;
    case __lc_id_RollR: rotate(t.left, t.up, corrected ? f0() : -f0()); break;
    case __lc_id_RollL: rotate(t.left, t.up, corrected ? -f0() : f0()); break;
    case __lc_id_TurnAround: rotate(t.heading, t.left, 180); break;
    case __lc_id_IncColor: t.color = t.color >= 255 ? 1 : t.color + 1; break;
    case __lc_id_DecColor: t.color = t.color <= 1 ? 255 : t.color - 1; break;
    case __lc_id_SetColor: {
      int c = i0();
      if (c >= 1 && c <= 255) t.color = c;
      break;
    }
    case __lc_id_SetWidth: {
      // Any value, as lpfg (zero and negative widths too: a function dipping below zero).
      t.width = t.widthUp = param<float>(rec, p0<__lc_R_SetWidth>());
      break;
    }
    case __lc_id_ScaleContour:
      t.width = param<float>(rec, p0<__lc_R_ScaleContour>());
      t.widthUp = param<float>(rec, p1<__lc_R_ScaleContour>());
      break;
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
      t.position = mapPoint(V3f(param<float>(rec, offsetof(__lc_R_MoveTo, p0)), param<float>(rec, offsetof(__lc_R_MoveTo, p1)),
                                param<float>(rec, offsetof(__lc_R_MoveTo, p2))));
      break;
    case __lc_id_MoveTo2f: t.position = mapPoint(toV3f(rec, p0<__lc_R_MoveTo2f>(), 0)); break;
    case __lc_id_MoveTo2d: t.position = mapPoint(toV3f(rec, p0<__lc_R_MoveTo2d>(), 1)); break;
    case __lc_id_MoveTo3f: t.position = mapPoint(toV3f(rec, p0<__lc_R_MoveTo3f>(), 2)); break;
    case __lc_id_MoveTo3d: t.position = mapPoint(toV3f(rec, p0<__lc_R_MoveTo3d>(), 3)); break;
    // Relative moves are directions in the coordinate system (lpfg also adds its origin: a bug
    // not reproduced).
    case __lc_id_MoveRel2f: t.position += mapDirection(toV3f(rec, p0<__lc_R_MoveRel2f>(), 0)) * t.csScale; break;
    case __lc_id_MoveRel2d: t.position += mapDirection(toV3f(rec, p0<__lc_R_MoveRel2d>(), 1)) * t.csScale; break;
    case __lc_id_MoveRel3f: t.position += mapDirection(toV3f(rec, p0<__lc_R_MoveRel3f>(), 2)) * t.csScale; break;
    case __lc_id_MoveRel3d: t.position += mapDirection(toV3f(rec, p0<__lc_R_MoveRel3d>(), 3)) * t.csScale; break;
    case __lc_id_LineTo:
      lineTo(mapPoint(V3f(param<float>(rec, offsetof(__lc_R_LineTo, p0)), param<float>(rec, offsetof(__lc_R_LineTo, p1)),
                          param<float>(rec, offsetof(__lc_R_LineTo, p2)))));
      break;
    case __lc_id_LineTo2f: lineTo(mapPoint(toV3f(rec, p0<__lc_R_LineTo2f>(), 0))); break;
    case __lc_id_LineTo2d: lineTo(mapPoint(toV3f(rec, p0<__lc_R_LineTo2d>(), 1))); break;
    case __lc_id_LineTo3f: lineTo(mapPoint(toV3f(rec, p0<__lc_R_LineTo3f>(), 2))); break;
    case __lc_id_LineTo3d: lineTo(mapPoint(toV3f(rec, p0<__lc_R_LineTo3d>(), 3))); break;
    case __lc_id_LineRel2f: lineTo(t.position + mapDirection(toV3f(rec, p0<__lc_R_LineRel2f>(), 0)) * t.csScale); break;
    case __lc_id_LineRel2d: lineTo(t.position + mapDirection(toV3f(rec, p0<__lc_R_LineRel2d>(), 1)) * t.csScale); break;
    case __lc_id_LineRel3f: lineTo(t.position + mapDirection(toV3f(rec, p0<__lc_R_LineRel3f>(), 2)) * t.csScale); break;
    case __lc_id_LineRel3d: lineTo(t.position + mapDirection(toV3f(rec, p0<__lc_R_LineRel3d>(), 3)) * t.csScale); break;
    case __lc_id_Line2f:
      t.position = mapPoint(toV3f(rec, p0<__lc_R_Line2f>(), 0));
      lineTo(mapPoint(toV3f(rec, p1<__lc_R_Line2f>(), 0)));
      break;
    case __lc_id_Line2d:
      t.position = mapPoint(toV3f(rec, p0<__lc_R_Line2d>(), 1));
      lineTo(mapPoint(toV3f(rec, p1<__lc_R_Line2d>(), 1)));
      break;
    case __lc_id_Line3f:
      t.position = mapPoint(toV3f(rec, p0<__lc_R_Line3f>(), 2));
      lineTo(mapPoint(toV3f(rec, p1<__lc_R_Line3f>(), 2)));
      break;
    case __lc_id_Line3d:
      t.position = mapPoint(toV3f(rec, p0<__lc_R_Line3d>(), 3));
      lineTo(mapPoint(toV3f(rec, p1<__lc_R_Line3d>(), 3)));
      break;
    case __lc_id_SetCoordinateSystem:
      t.csScale = param<float>(rec, p0<__lc_R_SetCoordinateSystem>());
      t.csOrigin = t.position;
      t.csX = t.left;
      t.csY = t.heading;
      t.csZ = t.up;
      break;
    case __lc_id_RollToVert: {
      V3f l = cross(V3f(0, 1, 0), t.heading);
      float len = l.Length();
      t.left = len < kEpsilon ? V3f(-1, 0, 0) : l / len;
      t.up = cross(t.heading, t.left);
      break;
    }
    case __lc_id_SetHead: {
      V3f h = mapDirection(V3f(param<float>(rec, offsetof(__lc_R_SetHead, p0)), param<float>(rec, offsetof(__lc_R_SetHead, p1)),
                               param<float>(rec, offsetof(__lc_R_SetHead, p2))));
      V3f u = mapDirection(V3f(param<float>(rec, offsetof(__lc_R_SetHead, p3)), param<float>(rec, offsetof(__lc_R_SetHead, p4)),
                               param<float>(rec, offsetof(__lc_R_SetHead, p5))));
      if (h.Length() < kEpsilon || u.Length() < kEpsilon) break;
      h.Normalize();
      u.Normalize();
      V3f l = cross(u, h);
      if (l.Length() < kEpsilon) break;
      t.heading = h;
      t.left = l.Normalized();
      t.up = cross(t.heading, t.left);
      break;
    }
    case __lc_id_SetHead3f: {
      V3f h = mapDirection(param<V3f>(rec, p0<__lc_R_SetHead3f>()));
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
    case __lc_id_RotateXYZ:
      rotateAbout(param<V3f>(rec, p0<__lc_R_RotateXYZ>()), param<float>(rec, p1<__lc_R_RotateXYZ>()));
      break;
    case __lc_id_RotateHLU:
    case __lc_id_Rotate: {
      V3f a = param<V3f>(rec, p0<__lc_R_RotateHLU>());
      rotateAbout(t.heading * a.x + t.left * a.y + t.up * a.z, param<float>(rec, p1<__lc_R_RotateHLU>()));
      break;
    }
    // ---- tropisms (manual §5.8)
    case __lc_id_SetElasticity: {
      int i = param<int>(rec, p0<__lc_R_SetElasticity>());
      if (i >= 0 && i < kMaxTropisms && i < (int)view_->tropisms.size())
        t.elasticity[i] = param<float>(rec, p1<__lc_R_SetElasticity>());
      break;
    }
    case __lc_id_IncElasticity:
    case __lc_id_DecElasticity: {
      // lpfg steps by the view file's `S:` value.
      int i = param<int>(rec, p0<__lc_R_IncElasticity>());
      if (i >= 0 && i < kMaxTropisms && i < (int)view_->tropisms.size())
        t.elasticity[i] += (id == __lc_id_IncElasticity ? 1 : -1) * view_->tropisms[i].step;
      break;
    }
    case __lc_id_Elasticity: t.simpleElasticity = param<float>(rec, p0<__lc_R_Elasticity>()); break;
    case __lc_id_SetTropismDirection3f: t.simpleTropism = param<V3f>(rec, p0<__lc_R_SetTropismDirection3f>()); break;
    // ---- generalized cylinders (§5.7)
    case __lc_id_CurrentContour:
      t.contour = t.contour2 = i0();
      t.blend = 0;
      break;
    case __lc_id_BlendedContour: {
      t.contour = param<int>(rec, p0<__lc_R_BlendedContour>());
      t.contour2 = param<int>(rec, p1<__lc_R_BlendedContour>());
      float b = param<float>(rec, offsetof(__lc_R_BlendedContour, p2));
      t.blend = b < 0 ? 0 : b > 1 ? 1 : b;
      break;
    }
    case __lc_id_ContourSides: {
      int n = i0();
      if (t.cylinderOn || n < 3) break;
      t.contourSides = n > 9999 ? 10000 : n;
      break;
    }
    case __lc_id_CurrentTexture: {
      int id = i0();
      int known = setup_.view ? (int)setup_.view->textures.size() : 0;
      if (id != -1 && (id < 0 || id >= known)) {  // lpfg: a message, the module ignored ...
        t.textureSet = false;  // ... and the surfaces' own textures again
        break;
      }
      t.texture = id;
      t.textureSet = true;
      t.textureV = 0;
      break;
    }
    case __lc_id_TextureVCoeff: {
      float v = param<float>(rec, p0<__lc_R_TextureVCoeff>());
      if (v >= 0) t.textureVCoeff = v;
      break;
    }
    case __lc_id_StartGC: startCylinder(); break;
    case __lc_id_PointGC:
      if (t.cylinderOn) t.cylinder = cylinderHere();
      break;
    case __lc_id_EndGC: endCylinder(); break;
    // ---- surfaces (§5.6)
    case __lc_id_SetUPrecision:
    case __lc_id_SetVPrecision: {
      int p = i0();
      if (p < 2 || p > 64) break;  // lpfg ignores 0 too (the manual says it resets)
      (id == __lc_id_SetUPrecision ? t.uPrecision : t.vPrecision) = p;
      break;
    }
    default:
      if (out_) {
        switch (id) {
          case __lc_id_Circle: drawCircle(f0(), false, 0); break;
          case __lc_id_Circle0: drawCircle(t.width / 2, false, 0); break;
          case __lc_id_CircleFront: drawCircle(f0(), true, 0); break;
          case __lc_id_CircleFront0: drawCircle(t.width / 2, true, 0); break;
          case __lc_id_CircleB: drawCircle(f0() + t.width / 2, false, f0() - t.width / 2); break;
          case __lc_id_CircleFrontB: drawCircle(f0() + t.width / 2, true, f0() - t.width / 2); break;
          case __lc_id_Sphere: drawSphere(f0()); break;
          case __lc_id_Sphere0: drawSphere(t.width / 2); break;
          case __lc_id_Rhombus: drawRhombus(f0(), param<float>(rec, p1<__lc_R_Rhombus>())); break;
          case __lc_id_Triangle: drawTriangle(f0(), param<float>(rec, p1<__lc_R_Triangle>())); break;
          case __lc_id_SP:
            polygonOn_ = true;  // lpfg: one polygon at a time; a second SP restarts it
            polygon_.clear();
            break;
          case __lc_id_PP:
            if (polygonOn_) {
              polygon_.push_back({t.position, t.up, t.color});
              extend(t.position);
            }
            break;
          case __lc_id_EP: endPolygon(); break;
          case __lc_id_Surface: {
            float s = param<float>(rec, p1<__lc_R_Surface>());
            drawSurface(i0(), V3f(s, s, s));
            break;
          }
          case __lc_id_Surface3:
            drawSurface(i0(), V3f(param<float>(rec, p1<__lc_R_Surface3>()), param<float>(rec, offsetof(__lc_R_Surface3, p2)),
                                  param<float>(rec, offsetof(__lc_R_Surface3, p3))));
            break;
          case __lc_id_Mesh: {
            float s = param<float>(rec, p1<__lc_R_Mesh>());
            drawMesh(i0(), V3f(s, s, s));
            break;
          }
          case __lc_id_Mesh3:
            drawMesh(i0(), V3f(param<float>(rec, p1<__lc_R_Mesh3>()), param<float>(rec, offsetof(__lc_R_Mesh3, p2)),
                               param<float>(rec, offsetof(__lc_R_Mesh3, p3))));
            break;
          case __lc_id_DSurface: {
            SurfaceObj s = param<SurfaceObj>(rec, p0<__lc_R_DSurface>());
            drawPatch(s.points, true);
            break;
          }
          case __lc_id_InitSurface: break;
          case __lc_id_SurfacePoint: {
            int p = param<int>(rec, p1<__lc_R_SurfacePoint>()), q = param<int>(rec, offsetof(__lc_R_SurfacePoint, p2));
            if (p >= 0 && p < 4 && q >= 0 && q < 4) userPatch_[4 * q + p] = t.position;
            break;
          }
          case __lc_id_DrawSurface: drawPatch(userPatch_, false); break;
          case __lc_id_Label: {
            const char* text = param<const char*>(rec, p0<__lc_R_Label>());
            out_->labels.push_back({t.position, text ? text : "", t.color});
            break;
          }
          case __lc_id_Camera: out_->camera = CameraPose{t.position, t.heading, t.up}; break;
          default: break;
        }
      }
      break;
  }
}

}  // namespace lcjit::runtime
