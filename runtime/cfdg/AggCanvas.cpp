// The CFDG canvas (Canvas.h) drawn with AGG 2.6.1, as Context Free 3.4's cfdg draws: the same
// scanline rasteriser (integer clipper, 1/256-pixel subpixels, identity gamma, non-zero fill), the
// same premultiplied pixel formats and blenders, and the same geometry handed to them: the unit
// SQUARE and TRIANGLE as polygons, the CIRCLE as cfdg's own n-gon, each first grown by a fraction
// of a pixel (below); paths flattened and stroked by AGG's converters with cfdg's settings. What
// AGG does inside comes from its headers and libagg.a, the very code cfdg runs (Debian's libagg2
// is built from the same source).
#include "runtime/cfdg/Canvas.h"

#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <memory>
#include <thread>
#include <type_traits>

#include <agg_basics.h>
#include <agg_color_gray.h>
#include <agg_color_rgba.h>
#include <agg_conv_curve.h>
#include <agg_conv_stroke.h>
#include <agg_conv_transform.h>
#include <agg_path_storage.h>
#include <agg_pixfmt_gray.h>
#include <agg_pixfmt_rgb.h>
#include <agg_pixfmt_rgba.h>
#include <agg_rasterizer_scanline_aa.h>
#include <agg_renderer_base.h>
#include <agg_renderer_scanline.h>
#include <agg_rendering_buffer.h>
#include <agg_scanline_p.h>
#include <agg_trans_affine.h>
#include <png.h>

#include "support/ReplacingFile.h"

namespace lcjit::runtime::cfdg {

int channelCount(PixelFormat f) {
  switch (f) {
    case PixelFormat::Gray8: case PixelFormat::Gray16: return 1;
    case PixelFormat::Rgb8: case PixelFormat::Rgb16: return 3;
    default: return 4;
  }
}

int bytesPerChannel(PixelFormat f) { return f >= PixelFormat::Gray16 ? 2 : 1; }

namespace {

// Context Free's value of π (its shape.h), used for the circle's vertex angles.
constexpr double kPi = 3.14159265358979323846;

// ---- The unit primitives as AGG vertex sources ----

// A closed polygon through fixed points: move_to, line_to…, end_poly(close).
class Polygon {
 public:
  Polygon(const double* xy, unsigned count) : xy_(xy), count_(count) {}
  void rewind(unsigned) { i_ = 0; }
  unsigned vertex(double* x, double* y) {
    if (i_ < count_) {
      *x = xy_[2 * i_];
      *y = xy_[2 * i_ + 1];
      return i_++ == 0 ? agg::path_cmd_move_to : agg::path_cmd_line_to;
    }
    if (i_++ == count_) return unsigned(agg::path_cmd_end_poly) | unsigned(agg::path_flags_close);
    return agg::path_cmd_stop;
  }

 private:
  const double* xy_;
  unsigned count_, i_ = 0;
};

const double kSquare[] = {0.5, 0.5, -0.5, 0.5, -0.5, -0.5, 0.5, -0.5};

// The equilateral triangle of side 1 centred on its centroid, a vertex up: circumradius
// 0.5 / cos 30°.
struct TrianglePoints {
  double xy[6];
  TrianglePoints() {
    const double h = 0.5 / std::cos(30.0 * kPi / 180.0);
    const double p[] = {0, h, -0.5, -h / 2, 0.5, -h / 2};
    std::copy(p, p + 6, xy);
  }
};
const TrianglePoints kTriangle;

// cfdg's circle: a counter-clockwise n-gon of radius 0.5 whose vertices sit at the odd multiples
// of π/n, starting just past π. Its cosines and sines come from one octant: the first n/8 angles
// are computed and the rest of the quarter mirrored from them (so the table is symmetric to the
// last bit), then each quadrant walks the quarter forwards or backwards with its signs.
struct CircleTable {
  unsigned n = 0, quarter = 0;
  std::vector<double> c, s;
  explicit CircleTable(unsigned count) : n(count), quarter(count / 4), c(quarter), s(quarter) {
    for (unsigned i = 0; i < n / 8; ++i) {
      const double theta = ((i + 0.5) / n) * 2 * kPi;
      c[i] = std::cos(theta);
      s[i] = std::sin(theta);
      s[quarter - 1 - i] = std::cos(theta);
      c[quarter - 1 - i] = std::sin(theta);
    }
  }
};

// The tables of the circles a surface draws, by vertex count: a design draws millions of small
// circles with a few counts, and working out the table each time cost more than drawing one.
class CircleTables {
 public:
  const CircleTable& of(unsigned n) {
    const size_t k = n / 8;
    if (k >= kKept) {
      large_ = std::make_unique<CircleTable>(n);
      return *large_;
    }
    if (k >= kept_.size()) kept_.resize(k + 1);
    if (!kept_[k]) kept_[k] = std::make_unique<CircleTable>(n);
    return *kept_[k];
  }

 private:
  static constexpr size_t kKept = 512;  // up to 4,096 vertices: circles up to 16,000 pixels across
  std::vector<std::unique_ptr<CircleTable>> kept_;
  std::unique_ptr<CircleTable> large_;
};

// A circle of its table's count as an AGG vertex source.
class Circle {
 public:
  explicit Circle(const CircleTable& t) : t_(t) {}
  void rewind(unsigned) { k_ = 0; }
  unsigned vertex(double* x, double* y) {
    if (k_ < t_.n) {
      static const double signX[] = {-1, 1, 1, -1}, signY[] = {-1, -1, 1, 1};
      const unsigned q = k_ / t_.quarter;
      unsigned j = k_ % t_.quarter;
      if (q & 1) j = t_.quarter - 1 - j;
      *x = t_.c[j] * signX[q] * 0.5;
      *y = t_.s[j] * signY[q] * 0.5;
      return k_++ == 0 ? agg::path_cmd_move_to : agg::path_cmd_line_to;
    }
    if (k_++ == t_.n) return unsigned(agg::path_cmd_end_poly) | unsigned(agg::path_flags_close) | unsigned(agg::path_flags_ccw);
    return agg::path_cmd_stop;
  }

 private:
  const CircleTable& t_;
  unsigned k_ = 0;
};

// ---- Colours ----

// A shape's colour in the format's colour type, premultiplied. cfdg keeps device colours as AGG
// rgba8 rounded from the doubles (uround(v·255)) and widened to 16 bits; an 8-bit canvas narrows
// them back (the same bytes), a grey one takes AGG's integer luminance of those bytes, a 16-bit
// one rounds the doubles to 16 bits.
template <class C> C shapeColour(const Rgba& c) {
  const agg::rgba d(c.r, c.g, c.b, c.a);
  C out;
  if constexpr (std::is_same_v<C, agg::rgba8> || std::is_same_v<C, agg::gray8>) out = C(agg::rgba8(d));
  else out = C(agg::rgba16(d));
  out.premultiply();
  return out;
}

// The background is premultiplied in doubles, then converted straight to the format's colour type
// (a grey one by AGG's floating-point luminance).
template <class C> C backgroundColour(const Rgba& c) {
  agg::rgba d(c.r, c.g, c.b, c.a);
  d.premultiply();
  return C(d);
}

template <class PixFmt> constexpr bool kHasCompOp = requires(PixFmt& p) { p.comp_op(0u); };

}  // namespace

// ---- Drawing ----

struct Canvas::Surface {
  virtual ~Surface() = default;
  // Another surface over the same pixels that only changes rows y0…y1 (AGG's y, from the bottom):
  // each thread of a banded draw has one. The same shapes give the same pixels in its rows, as the
  // rasteriser does not see the band, only the renderer clips to it.
  virtual std::unique_ptr<Surface> band(int y0, int y1) = 0;
  virtual void draw(const CanvasShape& shape) = 0;
  virtual void drawPath(const std::vector<PathVertex>& path, const PathStyle& style, const Affine& toPixels,
                        const Rgba& colour, int blend) = 0;
};

namespace {

// A PathVertex list as an AGG vertex source.
class PathSource {
 public:
  explicit PathSource(const std::vector<PathVertex>& v) : v_(v) {}
  void rewind(unsigned) { i_ = 0; }
  unsigned vertex(double* x, double* y) {
    if (i_ >= v_.size()) return agg::path_cmd_stop;
    const PathVertex& p = v_[i_++];
    *x = p.x;
    *y = p.y;
    return p.command;
  }

 private:
  const std::vector<PathVertex>& v_;
  size_t i_ = 0;
};

}  // namespace

namespace {

template <class PixFmt> class AggSurface final : public Canvas::Surface {
  using Colour = typename PixFmt::color_type;

 public:
  // The rows are attached bottom up (negative stride), as cfdg attaches its buffer: AGG's y axis
  // then points up the picture.
  AggSurface(uint8_t* pixels, int width, int height, size_t rowBytes, const Rgba& background)
      : buffer_(pixels, width, height, -int(rowBytes)), pixfmt_(buffer_), base_(pixfmt_), solid_(base_),
        pixels_(pixels), rowBytes_(rowBytes) {
    base_.clear(backgroundColour<Colour>(background));
  }
  // A band of an existing surface: nothing cleared.
  AggSurface(uint8_t* pixels, int width, int height, size_t rowBytes, int y0, int y1)
      : buffer_(pixels, width, height, -int(rowBytes)), pixfmt_(buffer_), base_(pixfmt_), solid_(base_),
        pixels_(pixels), rowBytes_(rowBytes), bandY0_(y0), bandY1_(y1), banded_(true) {
    base_.clip_box(0, y0, width - 1, y1);
  }

  std::unique_ptr<Canvas::Surface> band(int y0, int y1) override {
    return std::make_unique<AggSurface>(pixels_, int(buffer_.width()), int(buffer_.height()), rowBytes_, y0, y1);
  }

  void drawPath(const std::vector<PathVertex>& path, const PathStyle& style, const Affine& a, const Rgba& colour,
                int blend) override {
    setBlend(blend);
    solid_.color(shapeColour<Colour>(colour));
    agg::trans_affine tr(a.sx, a.shy, a.shx, a.sy, a.tx, a.ty);
    // Curves are flattened finely enough for the transform's mean scale.
    const double scale = std::sqrt(std::fabs(tr.determinant()));
    PathSource source(path);
    agg::conv_curve<PathSource> curves(source);
    curves.approximation_scale(scale);
    rasterizer_.reset();
    rasterizer_.filling_rule(style.evenOdd ? agg::fill_even_odd : agg::fill_non_zero);
    if (!style.stroke) {
      // cfdg paints every path through one set of converters: a fill flattens its curves with the
      // angle tolerance the last stroke painted set.
      curves.angle_tolerance(angleTolerance_);
      agg::conv_transform<agg::conv_curve<PathSource>> transformed(curves, tr);
      rasterizer_.add_path(transformed);
    } else if (!style.isoWidth) {
      // Stroked in the path's units, then transformed (a non-uniform transform stretches the width).
      curves.angle_tolerance(angleTolerance_ = style.width * scale > 1 ? 0.2 : 0);
      agg::conv_stroke<agg::conv_curve<PathSource>> stroke(curves);
      configure(stroke, style, style.width, scale);
      agg::conv_transform<agg::conv_stroke<agg::conv_curve<PathSource>>> transformed(stroke, tr);
      rasterizer_.add_path(transformed);
    } else {
      // Transformed, then stroked in pixels: the same width in every direction.
      curves.angle_tolerance(angleTolerance_ = style.width * scale > 1 ? 0.2 : 0);
      agg::conv_transform<agg::conv_curve<PathSource>> transformed(curves, tr);
      agg::conv_stroke<agg::conv_transform<agg::conv_curve<PathSource>>> stroke(transformed);
      configure(stroke, style, style.width * scale, 1);
      rasterizer_.add_path(stroke);
    }
    agg::render_scanlines(rasterizer_, scanline_, solid_);
    rasterizer_.filling_rule(agg::fill_non_zero);
  }

  void draw(const CanvasShape& shape) override {
    const Colour colour = shapeColour<Colour>(shape.colour);
    // cfdg sets no blend mode for a FILL: it blends with the mode of the shape drawn before it
    // (src-over before any), whatever its own.
    if (shape.primitive == Primitive::Fill) {
      if (!banded_) {
        base_.fill(colour);
      } else {  // the same blend of every pixel, in this band's rows
        for (int y = bandY0_; y <= bandY1_; ++y) pixfmt_.blend_hline(0, y, buffer_.width(), colour, agg::cover_full);
      }
      return;
    }
    setBlend(shape.blend);
    const Affine& a = shape.toPixels;
    agg::trans_affine tr(a.sx, a.shy, a.shx, a.sy, a.tx, a.ty);
    // How long the unit axes are in pixels; each is lengthened by `grow` pixels (less than one)
    // so that thin shapes and the seams between touching shapes look as in cfdg. Below 5 pixels
    // the growth is that of a 5-pixel shape, in proportion.
    const double sizeX = std::sqrt(tr.sx * tr.sx + tr.shy * tr.shy);
    const double sizeY = std::sqrt(tr.shx * tr.shx + tr.sy * tr.sy);
    const double grow = shape.primitive == Primitive::Circle ? 0.3 : shape.primitive == Primitive::Square ? 0.8 : 0.9;
    const double factorX = sizeX >= 5 ? (sizeX + grow) / sizeX : (5 + grow) / 5;
    const double factorY = sizeY >= 5 ? (sizeY + grow) / sizeY : (5 + grow) / 5;
    tr.premultiply(agg::trans_affine_scaling(factorX, factorY));
    solid_.color(colour);
    switch (shape.primitive) {
      case Primitive::Square: render(Polygon(kSquare, 4), tr); break;
      case Primitive::Triangle: render(Polygon(kTriangle.xy, 3), tr); break;
      case Primitive::Circle: {
        // Vertices: a quarter of the (ungrown) pixel diameter plus 8, rounded up to a multiple of 8.
        unsigned n = unsigned(int((sizeX + sizeY) / 4)) + 8;
        n = (n + 7) & ~7u;
        render(Circle(circles_.of(n)), tr);
        break;
      }
      case Primitive::Fill: break;
    }
  }

 private:
  void setBlend(int blend) {
    if constexpr (kHasCompOp<PixFmt>)
      pixfmt_.comp_op(blend == kBlendSourceOver ? unsigned(agg::comp_op_src_over) : unsigned(blend));
  }

  template <class Stroke> static void configure(Stroke& stroke, const PathStyle& style, double width, double scale) {
    stroke.width(width);
    stroke.line_join(agg::line_join_e(style.join));
    stroke.line_cap(agg::line_cap_e(style.cap));
    stroke.miter_limit(style.miterLimit);
    stroke.inner_join(agg::inner_round);
    stroke.approximation_scale(scale);
  }

  template <class Source> void render(Source source, agg::trans_affine& tr) {
    agg::conv_transform<Source> transformed(source, tr);
    rasterizer_.reset();
    rasterizer_.add_path(transformed);
    agg::render_scanlines(rasterizer_, scanline_, solid_);
  }

  agg::rendering_buffer buffer_;
  PixFmt pixfmt_;
  agg::renderer_base<PixFmt> base_;
  agg::renderer_scanline_aa_solid<agg::renderer_base<PixFmt>> solid_;
  agg::rasterizer_scanline_aa<> rasterizer_;
  agg::scanline_p8 scanline_;
  uint8_t* pixels_;
  size_t rowBytes_;
  int bandY0_ = 0, bandY1_ = 0;
  bool banded_ = false;
  double angleTolerance_ = 0;  // the curve flattener's, as the last stroke left it
  CircleTables circles_;
};

using PixfmtRgba32Blend =
    agg::pixfmt_custom_blend_rgba<agg::comp_op_adaptor_rgba_pre<agg::rgba8, agg::order_rgba>, agg::rendering_buffer>;
using PixfmtRgba64Blend =
    agg::pixfmt_custom_blend_rgba<agg::comp_op_adaptor_rgba_pre<agg::rgba16, agg::order_rgba>, agg::rendering_buffer>;

}  // namespace

Canvas::Canvas(int width, int height, PixelFormat format, Rgba background)
    : width_(std::max(width, 1)), height_(std::max(height, 1)), format_(format) {
  pixels_.assign(rowBytes() * size_t(height_), 0);
  if (channelCount(format) < 4) background.a = 1;
  uint8_t* p = pixels_.data();
  const size_t rb = rowBytes();
  switch (format) {
    case PixelFormat::Gray8: surface_ = std::make_unique<AggSurface<agg::pixfmt_gray8_pre>>(p, width_, height_, rb, background); break;
    case PixelFormat::Rgb8: surface_ = std::make_unique<AggSurface<agg::pixfmt_rgb24_pre>>(p, width_, height_, rb, background); break;
    case PixelFormat::Rgba8: surface_ = std::make_unique<AggSurface<agg::pixfmt_rgba32_pre>>(p, width_, height_, rb, background); break;
    case PixelFormat::Rgba8Blend: surface_ = std::make_unique<AggSurface<PixfmtRgba32Blend>>(p, width_, height_, rb, background); break;
    case PixelFormat::Gray16: surface_ = std::make_unique<AggSurface<agg::pixfmt_gray16_pre>>(p, width_, height_, rb, background); break;
    case PixelFormat::Rgb16: surface_ = std::make_unique<AggSurface<agg::pixfmt_rgb48_pre>>(p, width_, height_, rb, background); break;
    case PixelFormat::Rgba16: surface_ = std::make_unique<AggSurface<agg::pixfmt_rgba64_pre>>(p, width_, height_, rb, background); break;
    case PixelFormat::Rgba16Blend: surface_ = std::make_unique<AggSurface<PixfmtRgba64Blend>>(p, width_, height_, rb, background); break;
  }
}

Canvas::~Canvas() = default;
Canvas::Canvas(Canvas&&) noexcept = default;
Canvas& Canvas::operator=(Canvas&&) noexcept = default;

void Canvas::draw(const CanvasShape& shape) { surface_->draw(shape); }

namespace {
// The rows (AGG's y) a shape can touch: its unit box, a little larger than any primitive, through
// the transform, and two pixels for antialiasing and the growth `draw` gives small shapes. Clamped
// to the picture, and all of it when the numbers are not (NaN).
void rowsOf(const CanvasShape& shape, int height, int& low, int& high) {
  low = 0, high = height - 1;
  if (shape.primitive == Primitive::Fill) return;
  const Affine& a = shape.toPixels;
  const double reach = 0.6 * (std::fabs(a.shy) + std::fabs(a.sy)) + 2.0;
  const double from = std::floor(a.ty - reach), to = std::ceil(a.ty + reach);
  if (from > 0) low = from < height ? int(from) : height;
  if (to < height - 1) high = to >= 0 ? int(to) : -1;
}
}  // namespace

void Canvas::drawEach(size_t count, const std::function<bool(size_t, CanvasShape&)>& shapeAt, unsigned threads) {
  if (threads <= 1 || count < 4096 || height_ < 64) {
    CanvasShape shape;
    for (size_t i = 0; i < count; ++i)
      if (shapeAt(i, shape)) surface_->draw(shape);
    return;
  }
  // A band of rows per thread, each drawing, in order, the shapes that reach its rows: a pixel
  // sees the same shapes in the same order as in one pass. The bands are cut where they have as
  // much work as each other (a triangle's base has more shapes than its tip), so that every core
  // is busy to the end: the work of each row is estimated from a sample of the shapes (every
  // shape would cost another pass over millions of them), a shape costing about as much as eight
  // rows of one, plus its rows, spread over them.
  std::vector<double> rowWork(size_t(height_) + 1);  // by differences: row y's is the sum up to y
  const size_t stride = std::max<size_t>(1, count / 65536);
  CanvasShape sample;
  for (size_t i = 0; i < count; i += stride) {
    int low = 0, high = -1;
    if (shapeAt(i, sample)) rowsOf(sample, height_, low, high);
    if (low > high) continue;
    const double each = (8.0 + (high - low + 1)) / (high - low + 1);
    rowWork[size_t(low)] += each;
    rowWork[size_t(high) + 1] -= each;
  }
  double all = 0, running = 0;
  for (int y = 0; y < height_; ++y) all += (running += rowWork[size_t(y)]);
  std::vector<int> bandEnd;  // each band's last row: where the work so far passes its share
  double sum = 0;
  running = 0;
  for (int y = 0; y < height_ && bandEnd.size() + 1 < threads; ++y) {
    sum += (running += rowWork[size_t(y)]);
    if (sum >= all * double(bandEnd.size() + 1) / threads) bandEnd.push_back(y);
  }
  bandEnd.push_back(height_ - 1);
  std::vector<std::thread> workers;
  for (size_t b = 0; b < bandEnd.size(); ++b) {
    const int y0 = b == 0 ? 0 : bandEnd[b - 1] + 1, y1 = bandEnd[b];
    if (y0 > y1) continue;
    workers.emplace_back([this, y0, y1, count, &shapeAt] {
      std::unique_ptr<Surface> band = surface_->band(y0, y1);
      CanvasShape shape;
      for (size_t i = 0; i < count; ++i) {
        if (!shapeAt(i, shape)) continue;
        int low, high;
        rowsOf(shape, height_, low, high);
        if (high < y0 || low > y1) continue;
        band->draw(shape);
      }
    });
  }
  for (auto& w : workers) w.join();
}

void Canvas::drawPath(const std::vector<PathVertex>& path, const PathStyle& style, const Affine& toPixels,
                      const Rgba& colour, int blend) {
  surface_->drawPath(path, style, toPixels, colour, blend);
}

// ---- Paths ----

struct PathBuilder::Storage {
  agg::path_storage path;
};

PathBuilder::PathBuilder() : storage_(std::make_unique<Storage>()) {}
PathBuilder::~PathBuilder() = default;
void PathBuilder::moveTo(double x, double y) { storage_->path.move_to(x, y); }
void PathBuilder::lineTo(double x, double y) { storage_->path.line_to(x, y); }
void PathBuilder::arcTo(double rx, double ry, double angle, bool largeArc, bool sweep, double x, double y) {
  storage_->path.arc_to(rx, ry, angle, largeArc, sweep, x, y);
}
void PathBuilder::curve3(double cx, double cy, double x, double y) { storage_->path.curve3(cx, cy, x, y); }
void PathBuilder::curve3(double x, double y) { storage_->path.curve3(x, y); }
void PathBuilder::curve4(double c1x, double c1y, double c2x, double c2y, double x, double y) {
  storage_->path.curve4(c1x, c1y, c2x, c2y, x, y);
}
void PathBuilder::curve4(double c2x, double c2y, double x, double y) { storage_->path.curve4(c2x, c2y, x, y); }
void PathBuilder::closePolygon() { storage_->path.close_polygon(); }
void PathBuilder::alignAllPaths() { storage_->path.align_all_paths(); }
size_t PathBuilder::size() const { return storage_->path.total_vertices(); }
std::vector<PathVertex> PathBuilder::vertices() const {
  std::vector<PathVertex> out(storage_->path.total_vertices());
  for (unsigned i = 0; i < out.size(); ++i) out[i].command = storage_->path.vertex(i, &out[i].x, &out[i].y);
  return out;
}

// ---- PNG ----

namespace {

// libpng reports errors by longjmp, which must not skip a C++ destructor: the function that calls
// setjmp owns nothing; its caller owns the rows and the output.
struct PngWrite {
  std::string* out = nullptr;
  const uint8_t* const* rows = nullptr;
  png_uint_32 width = 0, height = 0;
  int depth = 8, colourType = PNG_COLOR_TYPE_GRAY;
  char error[256] = "";
};

void pngError(png_structp png, png_const_charp msg) {
  auto* w = static_cast<PngWrite*>(png_get_error_ptr(png));
  std::snprintf(w->error, sizeof w->error, "%s", msg);
  png_longjmp(png, 1);
}
void pngWarning(png_structp, png_const_charp) {}
void pngSink(png_structp png, png_bytep data, size_t n) {
  static_cast<PngWrite*>(png_get_io_ptr(png))->out->append(reinterpret_cast<const char*>(data), n);
}
void pngFlush(png_structp) {}

bool encodePng(PngWrite* w) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, w, pngError, pngWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, nullptr);
    std::snprintf(w->error, sizeof w->error, "out of memory");
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_set_write_fn(png, w, pngSink, pngFlush);
  png_set_IHDR(png, info, w->width, w->height, w->depth, w->colourType, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_text text{};
  text.compression = PNG_TEXT_COMPRESSION_NONE;
  text.key = const_cast<char*>("Software");
  text.text = const_cast<char*>("Context Free");
  png_set_text(png, info, &text, 1);
  png_write_info(png, info);
  png_write_image(png, const_cast<png_bytepp>(w->rows));
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  return true;
}

// The rows as the file stores them: top first, RGBA un-premultiplied (AGG's integer demultiply),
// 16-bit values big-endian.
// RGBA pixels, premultiplied, made straight with AGG's integer demultiply (rgba8 or rgba16).
template <class Colour, class Value> void demultiplyAll(Value* p, size_t pixels) {
  for (size_t i = 0; i < pixels; ++i, p += 4) {
    Colour c(p[0], p[1], p[2], p[3]);
    c.demultiply();
    p[0] = c.r, p[1] = c.g, p[2] = c.b;
  }
}

std::vector<uint8_t> fileRows(const Canvas& canvas) {
  std::vector<uint8_t> bytes = canvas.pixels();
  const size_t pixels = size_t(canvas.width()) * canvas.height();
  const bool alpha = channelCount(canvas.format()) == 4;
  if (bytesPerChannel(canvas.format()) == 1) {
    if (alpha) demultiplyAll<agg::rgba8>(bytes.data(), pixels);
    return bytes;
  }
  auto* values = reinterpret_cast<uint16_t*>(bytes.data());
  if (alpha) demultiplyAll<agg::rgba16>(values, pixels);
  for (size_t i = 0, n = bytes.size() / 2; i < n; ++i) {
    const uint16_t v = values[i];
    bytes[2 * i] = uint8_t(v >> 8);
    bytes[2 * i + 1] = uint8_t(v & 0xff);
  }
  return bytes;
}

}  // namespace

runtime::Image imageOf(const Canvas& canvas) {
  const std::vector<uint8_t> bytes = fileRows(canvas);
  const int channels = channelCount(canvas.format()), depth = bytesPerChannel(canvas.format());
  runtime::Image image;
  image.width = canvas.width(), image.height = canvas.height();
  image.rgba.resize(size_t(image.width) * size_t(image.height) * 4);
  for (size_t i = 0, n = size_t(image.width) * size_t(image.height); i < n; ++i) {
    const uint8_t* p = bytes.data() + i * size_t(channels * depth);  // a 16-bit value's high byte first
    uint8_t* q = image.rgba.data() + i * 4;
    for (int k = 0; k < 3; ++k) q[k] = p[(channels == 1 ? 0 : k) * depth];
    q[3] = channels == 4 ? p[3 * depth] : 255;
  }
  return image;
}

llvm::Error writePng(const Canvas& canvas, const std::string& path, std::optional<PixelRect> crop) {
  PixelRect r{0, 0, canvas.width(), canvas.height()};
  if (crop) {
    const int x1 = std::max(crop->x, 0), y1 = std::max(crop->y, 0);
    const int x2 = std::min(crop->x + crop->width, canvas.width()), y2 = std::min(crop->y + crop->height, canvas.height());
    if (x2 <= x1 || y2 <= y1) return llvm::createStringError(path + ": error: cannot write file: empty picture");
    r = {x1, y1, x2 - x1, y2 - y1};
  }
  const std::vector<uint8_t> bytes = fileRows(canvas);
  const size_t pixelBytes = canvas.rowBytes() / size_t(canvas.width());
  // The file's top row is AGG's row y + height - 1; the canvas stores rows top first.
  std::vector<const uint8_t*> rows(size_t(r.height));
  for (size_t i = 0; i < rows.size(); ++i)
    rows[i] = bytes.data() + (size_t(canvas.height()) - size_t(r.y + r.height) + i) * canvas.rowBytes() + size_t(r.x) * pixelBytes;
  std::string out;
  PngWrite w;
  w.out = &out;
  w.rows = rows.data();
  w.width = png_uint_32(r.width);
  w.height = png_uint_32(r.height);
  w.depth = 8 * bytesPerChannel(canvas.format());
  const int channels = channelCount(canvas.format());
  w.colourType = channels == 1 ? PNG_COLOR_TYPE_GRAY : channels == 3 ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_RGB_ALPHA;
  if (!encodePng(&w)) return llvm::createStringError(path + ": error: cannot write file: " + w.error);
  return support::writeWholeFile(path, out);
}

}  // namespace lcjit::runtime::cfdg
