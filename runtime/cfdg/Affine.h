// A 2-D affine transform laid out as Context Free (and the AGG library it draws with) lay theirs
// out: x' = sx·x + shx·y + tx, y' = shy·x + sy·y + ty. A design's pictures depend on the last bits
// of these numbers (a shape's area decides when it is expanded and whether it is drawn), so the
// products are written out in the order Context Free computes them, and model code is compiled
// without fused multiply-add.
#pragma once
#include <cmath>

namespace lcjit::runtime::cfdg {

struct Affine {
  double sx = 1, shy = 0, shx = 0, sy = 1, tx = 0, ty = 0;

  // This transform, then `m`.
  Affine& multiply(const Affine& m) {
    double t0 = sx * m.sx + shy * m.shx;
    double t2 = shx * m.sx + sy * m.shx;
    double t4 = tx * m.sx + ty * m.shx + m.tx;
    shy = sx * m.shy + shy * m.sy;
    sy = shx * m.shy + sy * m.sy;
    ty = tx * m.shy + ty * m.sy + m.ty;
    sx = t0;
    shx = t2;
    tx = t4;
    return *this;
  }
  // `m`, then this transform.
  Affine& premultiply(const Affine& m) {
    Affine t = m;
    t.multiply(*this);
    return *this = t;
  }
  double determinant() const { return sx * sy - shy * shx; }
  void apply(double& x, double& y) const {
    double x0 = x;
    x = x0 * sx + y * shx + tx;
    y = x0 * shy + y * sy + ty;
  }

  static Affine translation(double x, double y) { return {1, 0, 0, 1, x, y}; }
  static Affine scaling(double x, double y) { return {x, 0, 0, y, 0, 0}; }
};

}  // namespace lcjit::runtime::cfdg
