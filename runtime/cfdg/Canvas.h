// The canvas a CFDG design's finished shapes are drawn on, and the PNG it becomes. Context Free's
// cfdg draws with the AGG library (Anti-Grain Geometry 2.6.1 on Debian); so does this canvas
// (AggCanvas.cpp), through the same rasteriser, pixel formats and blenders, so that a picture
// matches cfdg's pixel for pixel. The engine hands over plain data: which primitive, its complete
// transform into pixels, its colour and blend mode; the canvas knows nothing of rules or HSB.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <llvm/Support/Error.h>

#include "runtime/cfdg/Affine.h"

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
  int blend = kBlendSourceOver;
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

  int width() const { return width_; }
  int height() const { return height_; }
  PixelFormat format() const { return format_; }
  // The pixels as drawn: rows top first (the picture's top row is AGG's y = height - 1),
  // channels R, G, B, A (or grey), premultiplied, 16-bit values in native byte order.
  const std::vector<uint8_t>& pixels() const { return pixels_; }
  size_t rowBytes() const { return size_t(width_) * channelCount(format_) * bytesPerChannel(format_); }

  struct Surface;  // the AGG pixel format drawing into pixels_ (AggCanvas.cpp)

 private:
  int width_, height_;
  PixelFormat format_;
  std::vector<uint8_t> pixels_;
  std::unique_ptr<Surface> surface_;
};

// Writes the canvas as cfdg writes its PNG: grey (colour type 0), RGB (2) or RGBA (6) at 8 or 16
// bits, RGBA rows un-premultiplied as AGG does it, one tEXt chunk "Software" = "Context Free"
// (cfdg's). Errors: "PATH: error: cannot write file: WHY".
llvm::Error writePng(const Canvas& canvas, const std::string& path);

}  // namespace lcjit::runtime::cfdg
