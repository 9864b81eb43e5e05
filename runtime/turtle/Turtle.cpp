// The turtle's motion and module dispatch (see Turtle.h). Conventions are lpfg's (research notes
// from its source): Left turns H towards L about U, Up turns H towards U about L, RollR turns L
// towards U about H; `corrected rotation: off` flips Up/Down/RollL/RollR. F applies tropisms,
// moves, records a polygon vertex, then applies the simple tropism.
#include "runtime/turtle/Turtle.h"

#include "runtime/files/Quaternion.h"

#include <cmath>
#include <cstring>

namespace lcjit::runtime {
namespace {

constexpr float kEpsilon = 1e-5f;

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

// The turtle's arithmetic is lpfg's, operation for operation, because models read the state
// back (GetPos & co.) and lpfg's strings are the reference: float vectors, angles converted as
// (float)(degrees·π/180) with the product in double, cosf/sinf of that float, normalisation by
// one reciprocal and three products, and quaternion rotations where lpfg uses them.

float radians(float degrees) { return static_cast<float>(degrees * M_PI / 180.0); }

// v scaled to length n (lpfg: d = n / |v|, then v·d).
V3f scaledTo(V3f v, float n = 1.0f) {
  float d = n / v.Length();
  return V3f(v.x * d, v.y * d, v.z * d);
}

// Turns v towards `target` (lpfg's Vector3d::RotateTo, used by torques): by half of
// min(|v × target|, 1) as a quaternion angle, or 1 when they point apart.
V3f turnedTowards(V3f v, V3f target) {
  V3f axis = cross(v, target);
  float len = axis.Length();
  if (v * target < 0.0f) len = 1.0f;
  else if (len > 1.0f) len = 1.0f;
  float half = len * 0.5f;
  float s = std::sin(half) / len;
  return rotatedBy(v, Quat{std::cos(half), axis.x * s, axis.y * s, axis.z * s});
}

}  // namespace

void Turtle::reset(const TurtleSetup& setup, Geometry* out, TropismField* tropisms) {
  setup_ = setup;
  view_ = setup.view ? setup.view : &defaults_;
  out_ = out;
  state_ = TurtleState();
  field_ = tropisms ? tropisms : &ownField_;
  if (!tropisms) ownField_.initialised = false;
  for (size_t i = 0; i < view_->tropisms.size() && i < kMaxTropisms; ++i) {
    const Tropism& tr = view_->tropisms[i];
    tropismTerms_[i] = {scaled(tr), std::sin(radians(tr.angle)), std::cos(radians(tr.torque ? 0.0f : tr.angle))};
  }
  if (!field_->initialised) {
    // lpfg adds the view file's tropisms one by one into a global sum (tropismarr.cpp).
    *field_ = TropismField();
    field_->initialised = true;
    for (size_t i = 0; i < view_->tropisms.size() && i < kMaxTropisms; ++i) {
      const Tropism& tr = view_->tropisms[i];
      field_->elasticity[i] = tr.elasticity;
      if (tr.torque) {
        field_->twist += scaled(tr) * tr.elasticity;
        field_->twistLength = field_->twist.Length();
      } else {
        field_->direction += tropismTerms_[i].scaled * tropismTerms_[i].cosA * tr.elasticity;
      }
    }
  }
  // A new lpfg turtle copies the global elasticities.
  state_.elasticity = field_->elasticity;
  if (view_->simpleTropism) {
    state_.simpleTropism = view_->simpleTropism->direction;
    state_.simpleElasticity = view_->simpleTropism->elasticity;
  }
  stack_.clear();
  volume_ = VolumeState();
  polygonOn_ = false;
  polygon_.clear();
  // The engine reuses its turtles: nothing may carry over (contours change between runs).
  transcript_ = nullptr;
  for (V3tf& p : userPatch_) p = V3f();
  rings_.clear();
  frames_.clear();
}

void Turtle::finish() {
  polygonOn_ = false;
  polygon_.clear();
  placeInFrames();
}

void Turtle::rotate(V3f& a, V3f& b, float degrees) {
  float r = radians(degrees);
  float c = std::cos(r), s = std::sin(r);
  V3f na = a * c + b * s;
  V3f nb = b * c - a * s;
  a = na;
  b = nb;
}

// RotateXYZ/RotateHLU: a quaternion of half the angle about the (normalised) axis.
void Turtle::rotateAbout(V3f axis, float degrees) {
  float half = -radians(degrees) * 0.5f;
  V3f v = scaledTo(axis, std::sin(half));
  Quat q{std::cos(half), v.x, v.y, v.z};
  state_.heading = rotatedBy(state_.heading, q);
  state_.up = rotatedBy(state_.up, q);
  state_.left = rotatedBy(state_.left, q);
}

// lpfg's coordinate-system matrix: columns −X, Y, Z and the origin (0 for a direction, still
// added: it turns −0 into +0).
V3f Turtle::transform(V3f p, V3f origin) const {
  const TurtleState& t = state_;
  return V3f(-t.csX.x * p.x + t.csY.x * p.y + t.csZ.x * p.z + origin.x,
             -t.csX.y * p.x + t.csY.y * p.y + t.csZ.y * p.z + origin.y,
             -t.csX.z * p.x + t.csY.z * p.y + t.csZ.z * p.z + origin.z);
}

V3f Turtle::mapDirection(V3f d) const { return transform(d, V3f(0, 0, 0)); }

// Points are scaled first, then mapped, then moved by the origin.
V3f Turtle::mapPoint(V3f p) const { return transform(p * state_.csScale, state_.csOrigin); }

V3f Turtle::scaled(const Tropism& tr) { return tr.direction * tr.intensity; }

// EB: lpfg sets every tropism's elasticity from the restored branch and sums the field again
// from zero, torques included (they only have a twist when added from the view file).
void Turtle::restoreTropismField() {
  const auto& tropisms = view_->tropisms;
  if (tropisms.empty()) return;
  field_->direction = V3f(0, 0, 0);
  for (size_t i = 0; i < tropisms.size() && i < kMaxTropisms; ++i) {
    field_->elasticity[i] = state_.elasticity[i];
    field_->direction += tropismTerms_[i].scaled * tropismTerms_[i].cosA * field_->elasticity[i];
  }
}

// SetElasticity & co.: lpfg adds the change to the field rather than summing it again (for a
// torque too, whose "angle" is 0).
void Turtle::setElasticity(int i, float e) {
  float de = e - field_->elasticity[i];
  field_->elasticity[i] = e;
  state_.elasticity[i] = e;
  field_->direction += tropismTerms_[i].scaled * de * tropismTerms_[i].cosA;
}

// Tropisms of the view file, applied before every F/f move (lpfg's Turtle::_AdjustTropisms):
// the heading turns towards D = field + Σ E·sin A·(T × (H × T))/|H × T| by a quaternion of half
// of min(|H × D|, 1), then torques turn U towards the twist's component across H.
void Turtle::applyTropisms() {
  const auto& tropisms = view_->tropisms;
  if (tropisms.empty()) return;
  TurtleState& t = state_;
  V3f desired = field_->direction;
  bool bend = false;
  for (size_t i = 0; i < tropisms.size() && i < kMaxTropisms; ++i) {
    const Tropism& tr = tropisms[i];
    if (tr.torque) continue;
    bend = true;
    const float sinA = tropismTerms_[i].sinA;
    if (sinA != 0.0f) {
      const V3f& T = tropismTerms_[i].scaled;
      V3f v = cross(t.heading, T);
      float len = v.Length();
      if (len < kEpsilon) {
        v = t.left;
        len = 1.0f;
      }
      desired += cross(T, v) * (field_->elasticity[i] * sinA / len);
    }
  }
  if (bend) {
    V3f v = cross(t.heading, desired);
    float len = v.Length();
    if (len >= kEpsilon) {
      if (len > 1.0f) len = 1.0f;  // v keeps its length then: lpfg turns further
      float angle = -len * 0.5f;
      v *= 1.0f / len;
      v *= std::sin(angle);
      Quat q{std::cos(angle), v.x, v.y, v.z};
      t.heading = rotatedBy(t.heading, q);
      t.up = rotatedBy(t.up, q);
      t.left = cross(t.up, t.heading);
    }
  }
  if (field_->twistLength > 0.0f) {
    V3f v = cross(t.heading, field_->twist);
    if (v.Length() > kEpsilon) {
      V3f target = scaledTo(cross(v, t.heading)) * field_->twistLength;
      t.up = turnedTowards(t.up, target);
      t.left = cross(t.up, t.heading);
    }
  }
}

// `stropism:` / Elasticity(e): after the move, H leans towards the direction by e·(D·U) and
// e·(D·L).
void Turtle::applySimpleTropism() {
  TurtleState& t = state_;
  float e = t.simpleElasticity;
  if (e == 0) return;
  // As in lpfg, |e·(D·U)| > 1 gives NaN (the square root of a negative number).
  float s1 = e * (t.simpleTropism * t.up);
  float c1 = std::sqrt(1 - s1 * s1);
  V3f h = t.heading * c1 + t.up * s1;
  t.up = t.up * c1 - t.heading * s1;
  t.heading = h;
  float s2 = e * (t.simpleTropism * t.left);
  float c2 = std::sqrt(1 - s2 * s2);
  h = t.heading * c2 + t.left * s2;
  t.left = t.left * c2 - t.heading * s2;
  t.heading = h;
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
  extendAlongF(before);
  bool cylinders = view_->lineStyle == LineStyle::Cylinder;
  if (cylinders && t.cylinderOn) {
    CylinderPoint here = cylinderHere();
    drawFrustum(t.cylinder, here, d, true);
    t.cylinder = here;
  } else {
    drawSegment(before, d);
  }
}

// LineTo & co.: head along `delta`, draw an F of its length, then restore the frame (lpfg
// routes them through F, so tropisms and the polygon flag apply).
void Turtle::lineAlong(V3f delta) {
  TurtleState& t = state_;
  float len = delta.Length();
  if (len < kEpsilon) return;
  V3f h0 = t.heading, l0 = t.left, u0 = t.up;
  t.heading = scaledTo(delta);
  V3f l = cross(t.up, t.heading);
  if (l.Length() < kEpsilon) l = V3f(-t.heading.y, t.heading.x, 0);
  t.left = l.Length() < kEpsilon ? V3f(1, 0, 0) : scaledTo(l);
  t.up = cross(t.heading, t.left);
  forward(len, true, true);
  t.heading = h0;
  t.left = l0;
  t.up = u0;
}

void Turtle::lineTo(V3f target) { lineAlong(target - state_.position); }

// Line2f & co.: nothing at all (not even the move to the start) when the ends coincide.
void Turtle::line(V3f from, V3f to) {
  if ((to - from).Length() < kEpsilon) return;
  state_.position = from;
  lineAlong(to - from);
}

void Turtle::pushBranch() {
  stack_.push_back(state_);
  if (state_.cylinderOn) state_.cylinderInherited = true;
}

void Turtle::popBranch() {
  if (stack_.empty()) return;  // lpfg: message, ignored
  state_ = stack_.back();
  stack_.pop_back();
  restoreTropismField();
}

void Turtle::execute(char* rec) {
  if (!transcript_) return executeModule(rec);
  const V3f position = state_.position;  // not the whole state: a copy a module cost -dtf a tenth
  const float width = state_.width;
  executeModule(rec);
  describeTurtleCommand(*transcript_, rec, position, width, state_.position);
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
    case __lc_id_F:
      forward(f0(), true, true);
      t.localStepLength = t.stepLength;  // GroIMP's shoot: the local length served its one shoot
      break;
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
    // not reproduced; with the origin at 0 the bits are lpfg's).
    case __lc_id_MoveRel2f: t.position += mapDirection(toV3f(rec, p0<__lc_R_MoveRel2f>(), 0) * t.csScale); break;
    case __lc_id_MoveRel2d: t.position += mapDirection(toV3f(rec, p0<__lc_R_MoveRel2d>(), 1) * t.csScale); break;
    case __lc_id_MoveRel3f: t.position += mapDirection(toV3f(rec, p0<__lc_R_MoveRel3f>(), 2) * t.csScale); break;
    case __lc_id_MoveRel3d: t.position += mapDirection(toV3f(rec, p0<__lc_R_MoveRel3d>(), 3) * t.csScale); break;
    case __lc_id_LineTo:
      lineTo(mapPoint(V3f(param<float>(rec, offsetof(__lc_R_LineTo, p0)), param<float>(rec, offsetof(__lc_R_LineTo, p1)),
                          param<float>(rec, offsetof(__lc_R_LineTo, p2)))));
      break;
    case __lc_id_LineTo2f: lineTo(mapPoint(toV3f(rec, p0<__lc_R_LineTo2f>(), 0))); break;
    case __lc_id_LineTo2d: lineTo(mapPoint(toV3f(rec, p0<__lc_R_LineTo2d>(), 1))); break;
    case __lc_id_LineTo3f: lineTo(mapPoint(toV3f(rec, p0<__lc_R_LineTo3f>(), 2))); break;
    case __lc_id_LineTo3d: lineTo(mapPoint(toV3f(rec, p0<__lc_R_LineTo3d>(), 3))); break;
    case __lc_id_LineRel2f: lineAlong(mapDirection(toV3f(rec, p0<__lc_R_LineRel2f>(), 0) * t.csScale)); break;
    case __lc_id_LineRel2d: lineAlong(mapDirection(toV3f(rec, p0<__lc_R_LineRel2d>(), 1) * t.csScale)); break;
    case __lc_id_LineRel3f: lineAlong(mapDirection(toV3f(rec, p0<__lc_R_LineRel3f>(), 2) * t.csScale)); break;
    case __lc_id_LineRel3d: lineAlong(mapDirection(toV3f(rec, p0<__lc_R_LineRel3d>(), 3) * t.csScale)); break;
    case __lc_id_Line2f:
      line(mapPoint(toV3f(rec, p0<__lc_R_Line2f>(), 0)), mapPoint(toV3f(rec, p1<__lc_R_Line2f>(), 0)));
      break;
    case __lc_id_Line2d:
      line(mapPoint(toV3f(rec, p0<__lc_R_Line2d>(), 1)), mapPoint(toV3f(rec, p1<__lc_R_Line2d>(), 1)));
      break;
    case __lc_id_Line3f:
      line(mapPoint(toV3f(rec, p0<__lc_R_Line3f>(), 2)), mapPoint(toV3f(rec, p1<__lc_R_Line3f>(), 2)));
      break;
    case __lc_id_Line3d:
      line(mapPoint(toV3f(rec, p0<__lc_R_Line3d>(), 3)), mapPoint(toV3f(rec, p1<__lc_R_Line3d>(), 3)));
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
      t.left = l.Length() < kEpsilon ? V3f(-1, 0, 0) : scaledTo(l);
      t.up = cross(t.heading, t.left);
      break;
    }
    case __lc_id_SetHead: {
      // lpfg normalises H and U, maps them, and keeps L = U × H as it comes (not normalised:
      // H and U need not be perpendicular); U is then H × L.
      V3f h(param<float>(rec, offsetof(__lc_R_SetHead, p0)), param<float>(rec, offsetof(__lc_R_SetHead, p1)),
            param<float>(rec, offsetof(__lc_R_SetHead, p2)));
      V3f u(param<float>(rec, offsetof(__lc_R_SetHead, p3)), param<float>(rec, offsetof(__lc_R_SetHead, p4)),
            param<float>(rec, offsetof(__lc_R_SetHead, p5)));
      if (h.Length() < kEpsilon || u.Length() < kEpsilon) break;
      h = mapDirection(scaledTo(h));
      u = mapDirection(scaledTo(u));
      V3f l = cross(u, h);
      if (l.Length() < kEpsilon) break;
      t.heading = h;
      t.left = l;
      t.up = cross(t.heading, t.left);
      break;
    }
    case __lc_id_SetHead3f: {
      // lpfg: the quaternion turning the old heading into the new one, half angle from acosf of
      // the cosine; (anti)parallel headings: nothing, or Left(180).
      V3f h = param<V3f>(rec, p0<__lc_R_SetHead3f>());
      if (h.Length() < kEpsilon) break;
      V3f from = scaledTo(t.heading), to = scaledTo(mapDirection(h));
      float c = from * to;
      if (std::fabs(c) < 1.0f - kEpsilon) {
        V3f axis = scaledTo(cross(from, to));
        float half = static_cast<float>(-0.5 * std::acos(c));
        float s = std::sin(half);
        Quat q{std::cos(half), s * axis.x, s * axis.y, s * axis.z};
        t.heading = rotatedBy(t.heading, q);
        t.up = rotatedBy(t.up, q);
        t.left = rotatedBy(t.left, q);
      } else if (c < 0.0f) {
        rotate(t.heading, t.left, 180);
      }
      break;
    }
    // lpfg interprets Rotate as RotateXYZ.
    case __lc_id_RotateXYZ:
    case __lc_id_Rotate: {
      V3f a = param<V3f>(rec, p0<__lc_R_RotateXYZ>());
      if (a.Length() >= kEpsilon) rotateAbout(a, param<float>(rec, p1<__lc_R_RotateXYZ>()));
      break;
    }
    case __lc_id_RotateHLU: {
      V3f a = param<V3f>(rec, p0<__lc_R_RotateHLU>());
      if (a.Length() >= kEpsilon)
        rotateAbout(a.x * t.heading + a.y * t.left + a.z * t.up, param<float>(rec, p1<__lc_R_RotateHLU>()));
      break;
    }
    // ---- tropisms (manual §5.8)
    case __lc_id_SetElasticity: {
      int i = param<int>(rec, p0<__lc_R_SetElasticity>());
      if (i >= 0 && i < kMaxTropisms && i < (int)view_->tropisms.size())
        setElasticity(i, param<float>(rec, p1<__lc_R_SetElasticity>()));
      break;
    }
    case __lc_id_IncElasticity:
    case __lc_id_DecElasticity: {
      // lpfg steps by the view file's `S:` value.
      int i = param<int>(rec, p0<__lc_R_IncElasticity>());
      if (i >= 0 && i < kMaxTropisms && i < (int)view_->tropisms.size()) {
        float step = view_->tropisms[i].step;
        setElasticity(i, id == __lc_id_IncElasticity ? field_->elasticity[i] + step : field_->elasticity[i] - step);
      }
      break;
    }
    case __lc_id_Elasticity: t.simpleElasticity = param<float>(rec, p0<__lc_R_Elasticity>()); break;
    case __lc_id_SetTropismDirection3f: t.simpleTropism = param<V3f>(rec, p0<__lc_R_SetTropismDirection3f>()); break;
    // ---- generalized cylinders (§5.7)
    case __lc_id_CurrentContour:
      t.contour = t.contour2 = i0();
      t.blend = 0;
      selectContourExtent(t.contour, t.contour, 0);
      break;
    case __lc_id_BlendedContour: {
      t.contour = param<int>(rec, p0<__lc_R_BlendedContour>());
      t.contour2 = param<int>(rec, p1<__lc_R_BlendedContour>());
      float b = param<float>(rec, offsetof(__lc_R_BlendedContour, p2));
      t.blend = b < 0 ? 0 : b > 1 ? 1 : b;
      selectContourExtent(t.contour, t.contour2, t.blend);
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
    case __lc_id_StartGC:
      volume_.inCylinder = true;
      volume_.width = t.width;
      volume_.widthUp = t.widthUp;
      startCylinder();
      break;
    case __lc_id_PointGC:
      if (t.cylinderOn) t.cylinder = cylinderHere();
      break;
    case __lc_id_EndGC:
      volume_.inCylinder = false;
      endCylinder();
      break;
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
          case __lc_id_BSurface: drawBSurface(i0(), param<float>(rec, p1<__lc_R_BSurface>())); break;
          case __lc_id_DBSurfaceS: {
            BsurfaceObjS b = param<BsurfaceObjS>(rec, p0<__lc_R_DBSurfaceS>());
            drawDynamicBSurface(reinterpret_cast<const float*>(&b), 10, 10, b.RowCount(), b.ColumnCount());
            break;
          }
          case __lc_id_DBSurfaceM: {
            auto b = std::make_unique<BsurfaceObjM>(param<BsurfaceObjM>(rec, p0<__lc_R_DBSurfaceM>()));
            drawDynamicBSurface(reinterpret_cast<const float*>(b.get()), 32, 32, b->RowCount(), b->ColumnCount());
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
            out_->addLabel({t.position, text ? text : "", t.color});
            break;
          }
          case __lc_id_Camera: out_->camera = CameraPose{t.position, t.heading, t.up}; break;
          case __lc_id_Terrain: drawTerrain(param<CameraPosition>(rec, p0<__lc_R_Terrain>())); break;
          default: break;
        }
      }
      break;
  }
}

}  // namespace lcjit::runtime
