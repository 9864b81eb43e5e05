// A design's expansion drawn as Context Free draws it (Picture.h).
#include "runtime/cfdg/Picture.h"

#include <algorithm>
#include <thread>

namespace lcjit::runtime::cfdg {

namespace {
Rgba deviceColour(const double hsba[4]) {
  double rgba[4];
  rgbOf(hsba, rgba);
  return {rgba[0], rgba[1], rgba[2], rgba[3]};
}
}  // namespace

Canvas drawExpansion(const __cf_Design& design, const Expansion& e, const Framing& f, const ExpandOptions& o) {
  PixelFormat format = design.usesBlend          ? PixelFormat::Rgba8Blend
                       : design.backgroundAlpha ? PixelFormat::Rgba8
                       : design.usesColour      ? PixelFormat::Rgb8
                                                : PixelFormat::Gray8;
  Canvas canvas(f.width, f.height, format, deviceColour(e.background));
  auto shapeAt = [&](size_t i, CanvasShape& c) {
    const FinishedShape& s = e.shapes[i];
    if (!drawn(s, f, o))
      return false;
    c.primitive = Primitive(s.shape);
    c.toPixels = s.transform;
    c.toPixels.multiply(f.toPixels);
    c.colour = {s.rgba[0], s.rgba[1], s.rgba[2], s.rgba[3]};
    // A blend flag carries AGG's compositing operator above bit 21.
    c.blend = (s.blend & (1 << 20)) ? (s.blend >> 21) & 31 : kBlendSourceOver;
    return true;
  };
  canvas.drawEach(e.shapes.size(), shapeAt, std::max(1u, std::thread::hardware_concurrency()));
  return canvas;
}

}  // namespace lcjit::runtime::cfdg
