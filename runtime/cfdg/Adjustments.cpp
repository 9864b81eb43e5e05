// Adjustments as compiled designs build and apply them (lcjit/cfdg.h): a shape's state changed
// by terms in order, constant terms folded as Context Free folds them, two adjustments merged, and
// the colour arithmetic of hue, saturation, brightness and alpha with their targets.
#include <agg_trans_affine.h>

#include <cmath>

#include "runtime/cfdg/ExpanderImpl.h"

using namespace lcjit::runtime::cfdg;

namespace {

// Moves `base` toward 0 or 1 (or, with a target, toward or away from it) by `adjustment`.
double adjustValue(double base, double adjustment, bool useTarget = false, double target = 0) {
  if (adjustment == 0.0)
    return base;
  if (useTarget) {
    if (adjustment > 0 && std::fabs(base - target) < 0.00001)
      return base;
    double edge = base < target ? 0 : 1;
    return adjustment < 0 ? base + (base - edge) * adjustment : base + (target - base) * adjustment;
  }
  return adjustment < 0 ? base + base * adjustment : base + (1 - base) * adjustment;
}
double adjustHue(double base, double adjustment, bool useTarget = false, double target = 0) {
  if (adjustment == 0.0)
    return base;
  double h;
  if (useTarget) {
    double t = target;
    if (adjustment < 0) {
      if (t > base) t -= 360;
      h = base + (base - t) * adjustment;
    } else {
      if (t < base) t += 360;
      h = base + (t - base) * adjustment;
    }
  } else {
    h = base + adjustment;
  }
  return h < 0.0 ? std::fmod(h + 360.0, 360.0) : std::fmod(h, 360.0);
}

// Which colour values an adjustment assigns: per channel (h, s, b, a) two bits, 1 = move toward
// the shape's target, 3 = move toward the adjustment's own target (a two-valued term).
constexpr unsigned kTargetBits = 1, kTwoValueBits = 3;

void applyColour(__cf_State& dest, const __cf_State& m) {
  for (int k = 0; k < 4; ++k) {
    unsigned current = (m.assign >> (2 * k)) & 3;
    bool twoValue = current == kTwoValueBits;
    double target = twoValue ? m.target[k] : dest.target[k];
    if (k == 0) {
      dest.colour[0] = adjustHue(dest.colour[0], m.colour[0], current != 0, target);
      if (!twoValue) dest.target[0] = adjustHue(dest.target[0], m.target[0]);
    } else {
      dest.colour[k] = adjustValue(dest.colour[k], m.colour[k], current != 0, target);
      if (!twoValue) dest.target[k] = adjustValue(dest.target[k], m.target[k]);
    }
  }
}

double clampUnit(double v) { return std::fmax(-1.0, std::fmin(1.0, v)); }

}  // namespace

extern "C" {

void __cf_identity(__cf_State* m) {
  *m = __cf_State{};
  m->sx = m->sy = 1;
  m->zsz = 1;
  m->tsc = 1;
}

// `m`'s transform, z and time applied to `s`: m first, then s's own.
static void applyPlacement(__cf_State& s, const __cf_State& m) {
  premultiplyState(s, affineOf(m));
  s.ztz = m.ztz * s.zsz + s.ztz;
  s.zsz = m.zsz * s.zsz;
  s.tbegin = m.tbegin * s.tsc + s.tbegin;
  s.tend = m.tend * s.tsc + s.tend;
  s.tsc = m.tsc * s.tsc;
}

void __cf_apply(__cf_State* s, const __cf_State* m) {
  applyPlacement(*s, *m);
  applyColour(*s, *m);
  if (m->blend) s->blend = m->blend;
}

void __cf_merge(__cf_State* m, const __cf_State* v) {
  constexpr unsigned kHueMask = 3;
  if ((m->assign & v->assign) || ((v->assign & kHueMask) && m->colour[0] != 0.0) ||
      ((m->assign & kHueMask) && v->colour[0] != 0.0))
    return;
  for (int k = 1; k < 4; ++k)
    if (m->colour[k] != 0.0 && v->colour[k] != 0.0) return;
  applyPlacement(*m, *v);
  if (v->blend) m->blend = v->blend;
  for (int k = 0; k < 4; ++k) {
    m->target[k] += v->target[k];
    m->colour[k] += v->colour[k];
  }
  m->assign |= v->assign;
}

void __cf_term(__cf_Ctx* c, __cf_State* m, int kind, int count, const double* v) {
  double args[6] = {0, 0, 0, 0, 0, 0};
  for (int i = 0; i < count && i < 6; ++i) args[i] = v[i];
  auto z = [&](double sz, double tz) {
    m->ztz = tz * m->zsz + m->ztz;
    m->zsz = sz * m->zsz;
  };
  switch (kind) {
    case __cf_X: premultiplyState(*m, Affine::translation(args[0], count > 1 ? args[1] : 0.0)); break;
    case __cf_Y: premultiplyState(*m, Affine::translation(0.0, args[0])); break;
    case __cf_Z: z(1, args[0]); break;
    case __cf_XYZ:
      premultiplyState(*m, Affine::translation(args[0], args[1]));
      z(1, args[2]);
      break;
    case __cf_Size: premultiplyState(*m, Affine::scaling(args[0], count > 1 ? args[1] : args[0])); break;
    case __cf_SizeXYZ:
      premultiplyState(*m, Affine::scaling(args[0], args[1]));
      z(args[2], 0);
      break;
    case __cf_ZSize: z(args[0], 0); break;
    case __cf_Rotate: {
      agg::trans_affine_rotation r(args[0] * kPi / 180.0);
      premultiplyState(*m, {r.sx, r.shy, r.shx, r.sy, r.tx, r.ty});
      break;
    }
    case __cf_Skew: {
      agg::trans_affine_skewing k(args[0] * kPi / 180.0, args[1] * kPi / 180.0);
      premultiplyState(*m, {k.sx, k.shy, k.shx, k.sy, k.tx, k.ty});
      break;
    }
    case __cf_Flip: {
      agg::trans_affine_reflection f(args[0] * kPi / 180.0);
      premultiplyState(*m, {f.sx, f.shy, f.shx, f.sy, f.tx, f.ty});
      break;
    }
    case __cf_Transform: {
      agg::trans_affine t;
      if (count <= 2) {
        t = agg::trans_affine_translation(args[0], count > 1 ? args[1] : 0.0);
      } else if (count == 4) {
        double dx = args[2] - args[0], dy = args[3] - args[1];
        t.scale(std::sqrt(dx * dx + dy * dy));
        t.rotate(std::atan2(dy, dx));
        t.translate(args[0], args[1]);
      } else if (count == 6) {
        t.rect_to_parl(0.0, 0.0, 1.0, 1.0, args);
      }
      premultiplyState(*m, {t.sx, t.shy, t.shx, t.sy, t.tx, t.ty});
      break;
    }
    case __cf_Time:
      m->tbegin = args[0] * m->tsc + m->tbegin;
      m->tend = args[1] * m->tsc + m->tend;
      break;
    case __cf_TimeScale: m->tsc = args[0] * m->tsc; break;
    case __cf_Blend: m->blend = int(args[0]); break;
    case __cf_Hue:
    case __cf_Sat:
    case __cf_Bright:
    case __cf_Alpha: {
      int k = kind - __cf_Hue;
      if (count != 2) {
        for (int i = 0; i < count && k < 4; ++i, ++k)
          m->colour[k] = k == 0 ? adjustHue(m->colour[k], args[i]) : adjustValue(m->colour[k], clampUnit(args[i]));
      } else {
        m->colour[k] = k == 0 ? adjustHue(m->colour[k], clampUnit(args[0]), true, args[1])
                              : adjustValue(m->colour[k], clampUnit(args[0]), true, clampUnit(args[1]));
      }
      break;
    }
    case __cf_HueTarg:
    case __cf_SatTarg:
    case __cf_BrightTarg:
    case __cf_AlphaTarg: {
      int k = kind - __cf_HueTarg;
      m->colour[k] = k == 0 ? adjustHue(m->colour[k], clampUnit(args[0]), true, m->target[k])
                            : adjustValue(m->colour[k], clampUnit(args[0]), true, m->target[k]);
      break;
    }
    case __cf_TargHue: m->target[0] += args[0]; break;
    case __cf_TargSat:
    case __cf_TargBright:
    case __cf_TargAlpha: {
      int k = kind - __cf_TargHue;
      m->target[k] = adjustValue(m->target[k], clampUnit(args[0]));
      break;
    }
    default: fail(c, "unknown adjustment term");
  }
}

int __cf_seen_transform(const __cf_State* transforms, int count, const __cf_State* m) {
  auto same = [](double a, double b) { return std::fabs(a - b) <= 1e-14; };
  for (int i = 0; i < count; ++i) {
    const __cf_State& t = transforms[i];
    if (same(t.sx, m->sx) && same(t.shy, m->shy) && same(t.shx, m->shx) && same(t.sy, m->sy) && same(t.tx, m->tx) &&
        same(t.ty, m->ty))
      return 1;
  }
  return 0;
}

void __cf_transform_by(__cf_State* shape, const __cf_State* m) { premultiplyState(*shape, affineOf(*m)); }

void __cf_fold(__cf_State* m, int kind, int count, const double* v) {
  // Geometry folds as it applies; colour terms are merged: hue values add, the others are set.
  double args[6] = {0, 0, 0, 0, 0, 0};
  for (int i = 0; i < count && i < 6; ++i) args[i] = v[i];
  switch (kind) {
    case __cf_Hue:
    case __cf_Sat:
    case __cf_Bright:
    case __cf_Alpha: {
      int k = kind - __cf_Hue;
      if (count != 2) {
        for (int i = 0; i < count && k < 4; ++i, ++k) m->colour[k] = k == 0 ? m->colour[k] + args[i] : clampUnit(args[i]);
      } else {
        m->colour[k] = clampUnit(args[0]);
        m->target[k] = k == 0 ? args[1] : clampUnit(args[1]);
        m->assign |= kTwoValueBits << (2 * k);
      }
      return;
    }
    case __cf_HueTarg:
    case __cf_SatTarg:
    case __cf_BrightTarg:
    case __cf_AlphaTarg: {
      int k = kind - __cf_HueTarg;
      m->colour[k] = clampUnit(args[0]);
      m->assign |= kTargetBits << (2 * k);
      return;
    }
    case __cf_TargSat:
    case __cf_TargBright:
    case __cf_TargAlpha: m->target[kind - __cf_TargHue] = clampUnit(args[0]); return;
    default: __cf_term(nullptr, m, kind, count, v);
  }
}

}  // extern "C"
