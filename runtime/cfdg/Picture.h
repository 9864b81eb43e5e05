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

// What a design's shapes are painted on: AGG's canvas (drawExpansion), or a vector page
// (VectorPage.h). It takes what Canvas takes: each primitive, and each path command's outline
// with its paint, with its complete transform into the picture's pixels (y up).
class ShapePainter {
 public:
  virtual ~ShapePainter() = default;
  virtual void draw(const CanvasShape& shape) = 0;
  virtual void drawPath(const std::vector<PathVertex>& outline, const PathStyle& style, const Affine& toPixels,
                        const Rgba& colour, int blend) = 0;
};
// Paints every drawn shape of `expansion` in Context Free's drawing order, each copy of a tiled
// picture, each command of a path (the background is the painter's to lay first).
void paintShapes(const __cf_Design& design, const Expansion& expansion, const Framing& framing,
                 const ExpandOptions& options, ShapePainter& painter);
// A colour in HSBA (Context Free's) as the device colour painters take.
Rgba deviceColour(const double hsba[4]);

}  // namespace lcjit::runtime::cfdg
