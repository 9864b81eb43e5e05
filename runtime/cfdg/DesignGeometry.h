// A design's drawn shapes as runtime::Geometry, for the exporters (OBJ, PLY, STL, glTF, PDF,
// PostScript, POV-Ray) and the renderer: each shape flat triangles in its device colour, unlit,
// on the z = 0 plane, in drawing order (what the 2D formats keep for coplanar shapes). Alpha and
// blend modes are not carried (Geometry's colours are opaque); the PNG keeps them.
#pragma once
#include "runtime/cfdg/Expander.h"
#include "runtime/turtle/Geometry.h"

namespace lcjit::runtime::cfdg {

// `circleSides`: the polygon a CIRCLE becomes.
Geometry geometryOf(const Expansion& expansion, const Framing& framing, const ExpandOptions& options,
                    int circleSides = 48);

}  // namespace lcjit::runtime::cfdg
