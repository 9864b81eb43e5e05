// A design's picture as a vector page, PDF or PostScript: Context Free's framing (the picture's
// size, one pixel a point, the fitted block where the PNG has it), its background, and each shape
// in drawing order as a path in its colour (a SQUARE, a CIRCLE of four Bézier arcs, a TRIANGLE, a
// path command's outline filled or stroked as its STROKE or FILL says), through the same
// transforms as the PNG's pixels (Picture.h's paintShapes). PDF pages carry each shape's alpha;
// PostScript has none. Blend modes are not carried.
#pragma once
#include <string>

#include "runtime/cfdg/Expander.h"

namespace lcjit::runtime::cfdg {

enum class PageFormat { Pdf, PostScript };

std::string vectorPage(const __cf_Design& design, const Expansion& expansion, const Framing& framing,
                       const ExpandOptions& options, PageFormat format);

}  // namespace lcjit::runtime::cfdg
