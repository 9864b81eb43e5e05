// Context Free's symmetry lists: CF::Symmetry (every finished shape drawn once per transform, the
// transform applied after the shape's own) and the lists of transform statements. A list holds
// transforms (adjustments that only move, turn, scale, skew or flip) and symmetry flags, each
// followed by its numbers: the cyclic and dihedral groups about a centre, and the frieze and
// wallpaper groups of a tiled design, made from its lattice. The transforms are made with AGG's
// affine operations in the order Context Free makes them, so that every copy is where its copy is
// to the last bit, and each is kept once (AGG's equality, to 1e-14).
#pragma once
#include <string>
#include <vector>

#include "runtime/cfdg/Affine.h"
#include "runtime/include/lcjit/cfdg.h"

namespace lcjit::runtime::cfdg {

// A setting Context Free rejects, in its words, at the place in the design ("file:line:col").
struct SettingError {
  std::string at, message;
};

// The transforms of `items` in order. `tiled`: the design has a CF::Tile lattice in both
// directions; `tile` is CF::Tile's transform without its translation (the identity when there is
// none), which the frieze and wallpaper groups are made from. Throws SettingError.
std::vector<Affine> symmetryTransforms(const __cf_SymmetryItem* items, int count, bool tiled, const Affine& tile);

}  // namespace lcjit::runtime::cfdg
