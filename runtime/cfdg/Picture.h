// A design's expansion drawn as Context Free draws it: the pixel format it chooses (grey, RGB,
// RGBA, with compositing operators), the background, each drawn shape's colour and transform to
// pixels, on the AGG canvas (Canvas.h).
#pragma once
#include "runtime/cfdg/Canvas.h"
#include "runtime/cfdg/Expander.h"

namespace lcjit::runtime::cfdg {

// The format cfdg draws a design in: its terms and settings (CF::Color, CF::Alpha, CF::ColorDepth,
// the background's alpha, blend modes).
PixelFormat pixelFormat(const __cf_Design& design, const PictureSettings& picture);

Canvas drawExpansion(const __cf_Design& design, const Expansion& expansion, const Framing& framing,
                     const ExpandOptions& options);

}  // namespace lcjit::runtime::cfdg
