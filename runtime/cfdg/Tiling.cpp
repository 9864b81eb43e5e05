// The copies of a tiled or frieze design's shapes (Tiling.h), found as Context Free's tiled canvas
// finds them: in pixels, with AGG's affine arithmetic.
#include "runtime/cfdg/Tiling.h"

#include <agg_basics.h>
#include <agg_trans_affine.h>

#include <cmath>

namespace lcjit::runtime::cfdg {

namespace {
agg::trans_affine aggOf(const Affine& a) { return {a.sx, a.shy, a.shx, a.sy, a.tx, a.ty}; }
Affine affineOf(const agg::trans_affine& t) { return {t.sx, t.shy, t.shx, t.sy, t.tx, t.ty}; }
}  // namespace

void frameLattice(Framing& f, const PictureSettings& p) {
  f.tiling = p.tiled ? 1 : 2;
  agg::trans_affine lattice = aggOf(p.tile);
  lattice *= agg::trans_affine_scaling(f.fit.scale);
  agg::trans_affine inverse;
  if (p.frieze) {
    // One side of a frieze's lattice is zero: each axis is inverted alone.
    inverse.sx = lattice.sx == 0.0 ? 0.0 : 1 / lattice.sx;
    inverse.sy = lattice.sy == 0.0 ? 0.0 : 1 / lattice.sy;
  } else {
    inverse = ~lattice;
  }
  f.lattice = affineOf(lattice);
  f.latticeInverse = affineOf(inverse);
}

std::vector<std::pair<double, double>> tileOffsets(const Framing& f, const Bounds& box) {
  const agg::trans_affine lattice = aggOf(f.lattice), inverse = aggOf(f.latticeInverse);
  const agg::trans_affine toBlock = aggOf(f.fit.toBlock);
  // The box in pixels, and the lattice point nearest its centre.
  double x1 = box.minX, y1 = box.minY, x2 = box.maxX, y2 = box.maxY;
  toBlock.transform(&x1, &y1);
  toBlock.transform(&x2, &y2);
  double cx = (x1 + x2) * 0.5, cy = (y1 + y2) * 0.5;
  inverse.transform(&cx, &cy);
  cx = std::floor(cx + 0.5);
  cy = std::floor(cy + 0.5);

  std::vector<std::pair<double, double>> offsets;
  double dx = -cx, dy = -cy;
  lattice.transform(&dx, &dy);
  offsets.emplace_back(dx, dy);  // the copy nearest the centre, always
  // The picture, a few pixels larger: a copy whose box touches it is drawn.
  const agg::rect_d picture(-5, -5, static_cast<double>(f.fit.width + 9), static_cast<double>(f.fit.height + 9));
  auto copy = [&](double i, double j) {
    lattice.transform(&i, &j);
    const agg::rect_d shape(x1 + i, y1 + j, x2 + i, y2 + j);
    if (!shape.overlaps(picture)) return false;
    offsets.emplace_back(i, j);
    return true;
  };
  const bool frieze = f.tiling == 2;
  if (frieze) cx = cy = cx + cy;  // the other axis's coordinate is zero
  for (int ring = 1;; ++ring) {
    bool hit = false;
    if (frieze) {
      hit = copy(ring - cx, ring - cy);
      hit = copy(-ring - cx, -ring - cy) || hit;
    } else {
      for (int pos = -ring; pos < ring; ++pos) {
        hit = copy(pos - cx, -ring - cy) || hit;
        hit = copy(ring - cx, pos - cy) || hit;
        hit = copy(-pos - cx, ring - cy) || hit;
        hit = copy(-ring - cx, -pos - cy) || hit;
      }
    }
    if (!hit) break;
  }
  return offsets;
}

}  // namespace lcjit::runtime::cfdg
