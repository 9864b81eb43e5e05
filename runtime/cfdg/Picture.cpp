// A design's expansion drawn as Context Free draws it (Picture.h).
#include "runtime/cfdg/Picture.h"

#include <algorithm>
#include <thread>

#include "runtime/cfdg/Paths.h"

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
  // A shape's transform to pixels, multiplied in cfdg's order: its state's, the fit, the fitted
  // block's place in the picture.
  const Affine offset = Affine::translation(f.offsetX, f.offsetY);
  auto toPixels = [&](const Affine& state) {
    Affine m = state;
    m.multiply(f.fit.toBlock);
    m.multiply(offset);
    return m;
  };
  auto primitive = [&](const FinishedShape& s, CanvasShape& c) {
    c.primitive = Primitive(s.shape);
    c.toPixels = toPixels(s.transform);
    c.colour = {s.rgba[0], s.rgba[1], s.rgba[2], s.rgba[3]};
    // A blend flag carries AGG's compositing operator above bit 21.
    c.blend = (s.blend & (1 << 20)) ? (s.blend >> 21) & 31 : kBlendSourceOver;
  };
  if (e.paths.empty()) {
    // Primitives only: drawn in bands of rows on every core (Canvas::drawEach).
    auto shapeAt = [&](size_t i, CanvasShape& c) {
      const FinishedShape& s = e.shapes[i];
      if (!drawn(s, f, o))
        return false;
      primitive(s, c);
      return true;
    };
    canvas.drawEach(e.shapes.size(), shapeAt, std::max(1u, std::thread::hardware_concurrency()));
    return canvas;
  }
  PathEngine paths(design);
  const PathPainter paint = [&](const std::vector<PathVertex>& outline, const PathCommandInfo& info,
                                const __cf_State& state) {
    PathStyle style;
    style.stroke = (info.flags & kFill) == 0;
    style.evenOdd = !style.stroke && (info.flags & kEvenOdd);
    style.width = info.width;
    style.isoWidth = (info.flags & kIsoWidth) != 0;
    style.join = uint8_t(info.flags & kJoinMask);
    style.cap = uint8_t((info.flags >> kCapShift) & 7);
    style.miterLimit = info.miterLimit;
    const int blend = (info.flags & kBlendPresent) ? (info.flags >> 21) & 31 : kBlendSourceOver;
    canvas.drawPath(outline, style, toPixels({state.sx, state.shy, state.shx, state.sy, state.tx, state.ty}),
                    deviceColour(state.colour), blend);
  };
  for (const FinishedShape& s : e.shapes) {
    if (!drawn(s, f, o))
      continue;
    if (s.shape == kPathShape) {
      paths.paint(e.paths[size_t(s.path)], e.statics, paint);
      continue;
    }
    CanvasShape c;
    primitive(s, c);
    canvas.draw(c);
  }
  return canvas;
}

}  // namespace lcjit::runtime::cfdg
