// Tiled and frieze designs (CF::Tile): the picture is one tile of a lattice (or one stretch of a
// frieze) and each shape is drawn again at every point of the lattice where a copy touches the
// picture, as Context Free's tiled canvas draws it: the copy nearest the picture's centre first,
// then rings of lattice points around it until a ring has no copy on the picture.
#pragma once
#include <utility>
#include <vector>

#include "runtime/cfdg/Expander.h"

namespace lcjit::runtime::cfdg {

// The lattice in pixels (the tile's transform, then the picture's scale) and its inverse, for
// the final framing.
void frameLattice(Framing& framing, const PictureSettings& picture);

// The offsets (pixels) of the copies of a shape whose box (world units) is `box`.
std::vector<std::pair<double, double>> tileOffsets(const Framing& framing, const Bounds& box);

// The offsets of finished shape `s`'s copies on a tiled or frieze picture; none (empty) on
// another picture, where the shape is drawn once, as it is.
inline std::vector<std::pair<double, double>> copyOffsets(const Expansion& e, const Framing& f, const FinishedShape& s) {
  if (f.tiling == 0 || s.shape == 3 || s.order == 0 || s.order > e.boxes.size()) return {};
  return tileOffsets(f, e.boxes[size_t(s.order - 1)]);
}

// Calls draw(matrix) for each copy of `state` (a transform of finished shape `s`, or of one of its
// path's commands) drawn on the picture: `state`, then the fit into the fitted block, then the
// copy's offset, then `after` (the block's place in the picture, or SVG's flip). Multiplied in
// that order, as Context Free multiplies them.
template <class Draw>
void forEachCopy(const Affine& state, const std::vector<std::pair<double, double>>& offsets, const Framing& f,
                 const Affine& after, Draw&& draw) {
  Affine m = state;
  m.multiply(f.fit.toBlock);
  if (offsets.empty()) {
    m.multiply(after);
    draw(m);
    return;
  }
  for (const auto& [dx, dy] : offsets) {
    Affine copy = m;
    copy.tx += dx;
    copy.ty += dy;
    copy.multiply(after);
    draw(copy);
  }
}
template <class Draw>
void forEachCopy(const Expansion& e, const Framing& f, const FinishedShape& s, const Affine& after, Draw&& draw) {
  forEachCopy(s.transform, copyOffsets(e, f, s), f, after, draw);
}

}  // namespace lcjit::runtime::cfdg
