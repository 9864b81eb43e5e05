// The canvas a CFDG design's finished shapes are drawn on, and the PNG it becomes. Context Free's
// cfdg draws with the AGG library (Anti-Grain Geometry 2.6.1 on Debian); so does this canvas
// (AggCanvas.cpp), through the same rasteriser, pixel formats and blenders, so that a picture
// matches cfdg's pixel for pixel. The engine hands over plain data: which primitive (or a path's
// outline and paint), its complete transform into pixels, its colour and blend mode; the canvas
// knows nothing of rules or HSB.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <llvm/Support/Error.h>

#include "runtime/cfdg/Affine.h"
#include "runtime/cfdg/PathVertex.h"
#include "runtime/files/Images.h"

namespace lcjit::runtime::cfdg {

enum class Primitive : uint8_t { Circle = 0, Square = 1, Triangle = 2, Fill = 3 };

// How the picture is stored, as cfdg chooses it: grey unless the design uses saturation (or
// CF::Color), RGBA when it asks for alpha, RGBA with AGG's compositing operators ("Blend") as
// soon as any shape has a blend mode; 16 bits per channel with CF::ColorDepth 16. Pixels are
// premultiplied by alpha while drawing, as cfdg's are.
enum class PixelFormat : uint8_t { Gray8, Rgb8, Rgba8, Rgba8Blend, Gray16, Rgb16, Rgba16, Rgba16Blend };

int channelCount(PixelFormat);
int bytesPerChannel(PixelFormat);

// A device colour: the shape's HSB colour converted to RGB, each channel in [0, 1], alpha not
// multiplied in. The canvas rounds it to the pixel format as cfdg does.
struct Rgba {
  double r = 0, g = 0, b = 0, a = 1;
};

// The blend mode of a shape drawn with src-over (cfdg's default, and every shape's when the
// design uses no blend mode). Other values are AGG comp_op_e numbers (CF::Multiply = 13, …).
constexpr int kBlendSourceOver = -1;

struct CanvasShape {
  Primitive primitive = Primitive::Square;
  // The unit shape (centred on 0, size 1) into AGG pixel space: the shape's world transform,
  // then the fit (scale and centring), then the offset of the fitted block in the image. Pixel
  // y grows UP (row 0 of the picture file is y = height - 1). Unused for Fill.
  Affine toPixels;
  Rgba colour;
  // Ignored for Fill, which cfdg blends with the mode of the shape drawn before it.
  int blend = kBlendSourceOver;
};

// Builds a PathVertex list with AGG's own path_storage, so that arcs become the Bézier curves AGG
// makes of them (bezier_arc_svg) and the other operations behave as in cfdg's paths (a drawing
// operation with no current point starts the path there, an arc to the current point is dropped).
class PathBuilder {
 public:
  PathBuilder();
  ~PathBuilder();
  PathBuilder(const PathBuilder&) = delete;
  PathBuilder& operator=(const PathBuilder&) = delete;

  void moveTo(double x, double y);
  void lineTo(double x, double y);
  // An elliptical arc from the current point to (x, y), as SVG's: radii, the ellipse's x-axis
  // angle in radians, which of the four arcs.
  void arcTo(double rx, double ry, double angle, bool largeArc, bool sweep, double x, double y);
  void curve3(double cx, double cy, double x, double y);
  void curve3(double x, double y);  // control point: the previous one reflected
  void curve4(double c1x, double c1y, double c2x, double c2y, double x, double y);
  void curve4(double c2x, double c2y, double x, double y);  // first control point reflected
  void closePolygon();
  // Makes each sub-path's last point exactly its first when they are within 1e-8 (AGG's
  // align_all_paths; cfdg aligns a path's sub-paths before painting them).
  void alignAllPaths();
  size_t size() const;
  std::vector<PathVertex> vertices() const;

 private:
  struct Storage;
  std::unique_ptr<Storage> storage_;
};

// How a path is painted (a path's STROKE or FILL command).
struct PathStyle {
  bool stroke = false;   // else filled
  bool evenOdd = false;  // fill rule (CF::EvenOdd), else non-zero
  // Strokes: the width in path units (CF::IsoWidth: the path is transformed first and the width,
  // scaled by the transform's mean scale, is in pixels, the same in every direction); AGG's
  // line_join_e (miter 0, round 2, bevel 3) and line_cap_e (butt 0, square 1, round 2).
  double width = 0.1;
  bool isoWidth = false;
  uint8_t join = 0, cap = 0;
  double miterLimit = 4;
};

class Canvas {
 public:
  // A width×height picture cleared to `background` (for formats without alpha its alpha is
  // taken as 1, as cfdg forces it).
  Canvas(int width, int height, PixelFormat format, Rgba background);
  ~Canvas();
  Canvas(Canvas&&) noexcept;
  Canvas& operator=(Canvas&&) noexcept;

  void draw(const CanvasShape& shape);
  // `count` shapes, in order: shapeAt(i, shape) fills in shape i, or says it is not drawn (it is
  // called from several threads at once). With `threads` > 1 the picture is drawn in bands of
  // rows at once, the same pixels as one pass.
  void drawEach(size_t count, const std::function<bool(size_t, CanvasShape&)>& shapeAt, unsigned threads);
  // A path's FILL or STROKE: its outline, curves flattened as cfdg flattens them at this scale,
  // through `toPixels` (as CanvasShape's). As cfdg's one set of converters, a fill flattens curves
  // with the angle tolerance the last stroke painted left: paths are painted in the picture's order.
  void drawPath(const std::vector<PathVertex>& path, const PathStyle& style, const Affine& toPixels, const Rgba& colour,
                int blend = kBlendSourceOver);

  int width() const { return width_; }
  int height() const { return height_; }
  PixelFormat format() const { return format_; }
  // The pixels as drawn: rows top first (the picture's top row is AGG's y = height - 1),
  // channels R, G, B, A (or grey), premultiplied, 16-bit values in native byte order.
  const std::vector<uint8_t>& pixels() const { return pixels_; }
  std::vector<uint8_t>& pixels() { return pixels_; }
  size_t rowBytes() const { return size_t(width_) * channelCount(format_) * bytesPerChannel(format_); }

  struct Surface;  // the AGG pixel format drawing into pixels_ (AggCanvas.cpp)

 private:
  int width_, height_;
  PixelFormat format_;
  std::vector<uint8_t> pixels_;
  std::unique_ptr<Surface> surface_;
};

// A rectangle of the canvas in AGG pixels: x from the left, y from the BOTTOM row.
struct PixelRect {
  int x = 0, y = 0, width = 0, height = 0;
};

// Writes the canvas as cfdg writes its PNG: grey (colour type 0), RGB (2) or RGBA (6) at 8 or 16
// bits, RGBA rows un-premultiplied as AGG does it, one tEXt chunk "Software" = "Context Free"
// (cfdg's). With `crop` (cfdg -c: the fitted block) only that part, clipped to the canvas.
// Errors: "PATH: error: cannot write file: WHY".
llvm::Error writePng(const Canvas& canvas, const std::string& path, std::optional<PixelRect> crop = std::nullopt);
// The picture as lcjit's RGBA image (a video's frame): 8 bits a channel, not premultiplied.
runtime::Image imageOf(const Canvas& canvas);

}  // namespace lcjit::runtime::cfdg
