// A design's expansion drawn as Context Free draws it (Picture.h).
#include "runtime/cfdg/Picture.h"

#include <algorithm>
#include <memory>
#include <thread>

#include "runtime/cfdg/Paths.h"
#include "runtime/cfdg/Tiling.h"

namespace lcjit::runtime::cfdg {

Rgba deviceColour(const double hsba[4]) {
  double rgba[4];
  rgbOf(hsba, rgba);
  return {rgba[0], rgba[1], rgba[2], rgba[3]};
}

namespace {

// A shape's transform to pixels, multiplied in cfdg's order: its state's, the fit, (on a tiled
// picture, the copy's offset,) the fitted block's place in the picture (Tiling.h).
Affine blockOffset(const Framing& f) { return Affine::translation(f.offsetX, f.offsetY); }

void primitiveOf(const Expansion& e, const FinishedShape& s, CanvasShape& c) {
  c.primitive = Primitive(s.shape);
  const std::array<double, 4>& rgba = e.colours[s.colour];
  c.colour = {rgba[0], rgba[1], rgba[2], rgba[3]};
  // A blend flag carries AGG's compositing operator above bit 21.
  c.blend = (s.blend & (1 << 20)) ? (s.blend >> 21) & 31 : kBlendSourceOver;
}

// The AGG canvas as a painter.
class CanvasPainter final : public ShapePainter {
 public:
  explicit CanvasPainter(Canvas& canvas) : canvas_(canvas) {}
  void draw(const CanvasShape& shape) override { canvas_.draw(shape); }
  void drawPath(const std::vector<PathVertex>& outline, const PathStyle& style, const Affine& toPixels,
                const Rgba& colour, int blend) override {
    canvas_.drawPath(outline, style, toPixels, colour, blend);
  }

 private:
  Canvas& canvas_;
};

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

namespace {
// An animation's frame of a frieze: cfdg makes the canvas at the picture's size before it knows the
// frieze's (a fitted block narrower or lower than the picture), and when the frame is drawn it
// copies the picture onto itself one block further along the frieze, in place, row by row from its
// bottom, pixel by pixel from the left: everything past the first block repeats the picture's
// first block's width (or height) of pixels, margins and all.
void repeatFrieze(Canvas& canvas, const Framing& f, const PictureSettings& p) {
  std::vector<uint8_t>& pixels = canvas.pixels();
  const size_t row = canvas.rowBytes(), pixel = row / size_t(canvas.width());
  if (p.frieze == 1 && f.fit.width < canvas.width()) {
    const size_t shift = size_t(f.fit.width) * pixel;
    for (int y = 0; y < canvas.height(); ++y)
      for (size_t x = shift; x < row; ++x) pixels[size_t(y) * row + x] = pixels[size_t(y) * row + x - shift];
  }
  if (p.frieze == 2 && f.fit.height < canvas.height()) {
    // cfdg's rows count from the bottom; the canvas's from the top.
    for (int y = f.fit.height; y < canvas.height(); ++y) {
      uint8_t* to = pixels.data() + size_t(canvas.height() - 1 - y) * row;
      std::copy_n(pixels.data() + size_t(canvas.height() - 1 - (y - f.fit.height)) * row, row, to);
    }
  }
}
}  // namespace

Canvas drawExpansion(const __cf_Design& design, const Expansion& e, const Framing& f, const ExpandOptions& o) {
  Canvas canvas(f.width, f.height, pixelFormat(design, e.picture), deviceColour(e.background));
  if (e.paths.empty() && f.tiling == 0) {
    // Primitives only, each drawn once: drawn in bands of rows on every core (Canvas::drawEach).
    const Affine offset = blockOffset(f);
    auto shapeAt = [&](size_t i, CanvasShape& c) {
      const FinishedShape& s = e.shapes[i];
      if (!drawn(s, f, o))
        return false;
      primitiveOf(e, s, c);
      forEachCopy(e, f, s, offset, [&](const Affine& toPixels) { c.toPixels = toPixels; });
      return true;
    };
    canvas.drawEach(e.shapes.size(), shapeAt, std::max(1u, std::thread::hardware_concurrency()));
    if (o.animation) repeatFrieze(canvas, f, e.picture);
    return canvas;
  }
  CanvasPainter painter(canvas);
  paintShapes(design, e, f, o, painter);
  if (o.animation) repeatFrieze(canvas, f, e.picture);
  return canvas;
}

void paintShapes(const __cf_Design& design, const Expansion& e, const Framing& f, const ExpandOptions& o,
                 ShapePainter& painter) {
  const Affine offset = blockOffset(f);
  std::unique_ptr<PathEngine> paths;
  std::vector<std::pair<double, double>> copies;  // of the path being painted, on a tiled picture
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
    forEachCopy(Affine{state.sx, state.shy, state.shx, state.sy, state.tx, state.ty}, copies, f, offset,
                [&](const Affine& toPixels) { painter.drawPath(outline, style, toPixels, deviceColour(state.colour), blend); });
  };
  for (const FinishedShape& s : e.shapes) {
    if (!drawn(s, f, o))
      continue;
    if (s.shape == kPathShape) {
      if (!paths) paths = std::make_unique<PathEngine>(design);
      copies = copyOffsets(e, f, s);
      paths->paint(e.paths[size_t(s.path)], e, paint);
      continue;
    }
    CanvasShape c;
    primitiveOf(e, s, c);
    forEachCopy(e, f, s, offset, [&](const Affine& toPixels) {
      c.toPixels = toPixels;
      painter.draw(c);
    });
  }
}

}  // namespace lcjit::runtime::cfdg
