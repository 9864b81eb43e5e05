// A design's expansion drawn as Context Free draws it (Picture.h).
#include "runtime/cfdg/Picture.h"

#include "runtime/cfdg/Tiling.h"

namespace lcjit::runtime::cfdg {

namespace {
Rgba deviceColour(const double hsba[4]) {
  double rgba[4];
  rgbOf(hsba, rgba);
  return {rgba[0], rgba[1], rgba[2], rgba[3]};
}
}  // namespace

PixelFormat pixelFormat(const __cf_Design& design, const PictureSettings& p) {
  // Colour when a sat term is used, unless CF::Color says; alpha when CF::Alpha says, unless there
  // is a background (then: when it has an alpha term); RGBA with compositing with any blend mode.
  const bool colour = p.colour >= 0 ? p.colour != 0 : design.usesColour != 0;
  const bool alpha = design.background ? design.backgroundAlpha != 0 : p.alpha > 0;
  PixelFormat format = design.usesBlend ? PixelFormat::Rgba8Blend
                       : alpha          ? PixelFormat::Rgba8
                       : colour         ? PixelFormat::Rgb8
                                        : PixelFormat::Gray8;
  if (p.depth16) format = PixelFormat(int(format) + int(PixelFormat::Gray16));
  return format;
}

Canvas drawExpansion(const __cf_Design& design, const Expansion& e, const Framing& f, const ExpandOptions& o) {
  Canvas canvas(f.width, f.height, pixelFormat(design, e.picture), deviceColour(e.background));
  const Affine offset = Affine::translation(f.offsetX, f.offsetY);
  for (const FinishedShape& s : e.shapes) {
    if (!drawn(s, f, o))
      continue;
    CanvasShape c;
    c.primitive = Primitive(s.shape);
    c.colour = {s.rgba[0], s.rgba[1], s.rgba[2], s.rgba[3]};
    // A blend flag carries AGG's compositing operator above bit 21.
    c.blend = (s.blend & (1 << 20)) ? (s.blend >> 21) & 31 : kBlendSourceOver;
    forEachCopy(e, f, s, offset, [&](const Affine& toPixels) {
      c.toPixels = toPixels;
      canvas.draw(c);
    });
  }
  return canvas;
}

}  // namespace lcjit::runtime::cfdg
