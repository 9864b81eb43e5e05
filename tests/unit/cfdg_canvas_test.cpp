// The CFDG canvas (runtime/cfdg/Canvas.h) against Context Free's own cfdg, run here as the oracle:
// small designs whose shapes' pixel transforms follow by hand from Context Free's rules (the
// adjustment matrices, the stroked bounds of the unit shapes, the fit with its 8-pixel border and
// ×2 dilation), drawn by the canvas and by cfdg, their PNGs decoded and compared pixel for pixel.
// Skipped where /usr/bin/cfdg is not installed (setup.sh installs the contextfree package).
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <llvm/Support/FileSystem.h>
#include <llvm/Support/Path.h>
#include <llvm/Support/Program.h>

#include "runtime/cfdg/Canvas.h"
#include "runtime/files/Images.h"

#include <png.h>

using namespace lcjit::runtime;
using namespace lcjit::runtime::cfdg;

namespace {

const char* const kCfdg = "/usr/bin/cfdg";
constexpr double kPi = 3.14159265358979323846;

// ---- The engine's part, by hand ----

// Adjustment terms, in the canonical order cfdg applies them (x, y, r, s): each is put before
// what the earlier ones built ("premultiply"), so a shape is sized, then rotated, then moved.
struct Adjust {
  double x = 0, y = 0, r = 0, sx = 1, sy = 1;
  Affine matrix() const {
    Affine a;
    if (x != 0 || y != 0) a.premultiply(Affine::translation(x, y));
    if (r != 0) {
      const double t = r * kPi / 180;
      a.premultiply(Affine{std::cos(t), std::sin(t), -std::sin(t), std::cos(t), 0, 0});
    }
    if (sx != 1 || sy != 1) a.premultiply(Affine::scaling(sx, sy));
    return a;
  }
};

// Context Free's HSB to RGB (hue in degrees), for the colours of the designs below.
Rgba hsb(double h, double s, double b, double a = 1) {
  double whole;
  double f = std::modf(h / 60, &whole);
  if (whole <= -0.1 || whole >= 5.1 || f < 0) {
    double q = std::fmod(h / 60, 6);
    if (q < 0) q += 6;
    f = std::modf(q, &whole);
  }
  const int hextant = int(whole + 0.5);
  const double p = b * (1 - s), q = b * (1 - s * f), t = b * (1 - s * (1 - f));
  switch (hextant) {
    case 0: return {b, t, p, a};
    case 1: return {q, b, p, a};
    case 2: return {p, b, t, a};
    case 3: return {p, q, b, a};
    case 4: return {t, p, b, a};
    default: return {b, p, q, a};
  }
}

struct Shape {
  Primitive primitive;
  Affine world;
  Rgba colour;
  int blend = kBlendSourceOver;
  // A path instead of a primitive (when not empty): its outline and paint. The designs below keep
  // paths inside the box of a large square, so that they do not change the frame.
  std::vector<PathVertex> path = {};
  PathStyle style = {};
};

// The corners of the unit shape's outline stroked 0.1 wide with miter joins, which is what
// cfdg measures a shape's bounds by: the square grows to ±0.55, the circle (an octagon there) to
// radius 0.5 + 0.05 / cos 22.5° at its vertices, each triangle corner moves 0.1 away from the
// centroid.
std::vector<std::pair<double, double>> outline(Primitive p) {
  std::vector<std::pair<double, double>> v;
  if (p == Primitive::Square) return {{0.55, 0.55}, {-0.55, 0.55}, {-0.55, -0.55}, {0.55, -0.55}};
  if (p == Primitive::Circle) {
    const double r = 0.5 + 0.05 / std::cos(kPi / 8);
    for (int k = 0; k < 8; ++k) v.push_back({r * std::cos(k * kPi / 4), r * std::sin(k * kPi / 4)});
    return v;
  }
  const double h = 0.5 / std::cos(kPi / 6);
  for (auto [x, y] : {std::pair{0.0, h}, {-0.5, -h / 2}, {0.5, -h / 2}}) {
    const double d = std::sqrt(x * x + y * y);
    v.push_back({x + 0.1 * x / d, y + 0.1 * y / d});
  }
  return v;
}

// The fit of an untiled design W×H with the default border (-b 2): each shape's box dilated ×2
// about its centre, the union scaled into the image less 8 pixels each side, the fitted block
// (the other side's length rounded, of the image's parity) centred at an integer offset. Returns
// the frame: world coordinates into AGG pixels (y up); `block`: where the fitted block lies.
Affine fit(const std::vector<Shape>& shapes, int W, int H, PixelRect* block = nullptr) {
  double x1 = std::numeric_limits<double>::infinity(), y1 = x1, x2 = -x1, y2 = -x1;
  for (const Shape& s : shapes) {
    if (s.primitive == Primitive::Fill || !s.path.empty()) continue;
    double bx1 = std::numeric_limits<double>::infinity(), by1 = bx1, bx2 = -bx1, by2 = -bx1;
    for (auto [x, y] : outline(s.primitive)) {
      s.world.apply(x, y);
      bx1 = std::min(bx1, x), bx2 = std::max(bx2, x), by1 = std::min(by1, y), by2 = std::max(by2, y);
    }
    const double cx = (bx1 + bx2) / 2, cy = (by1 + by2) / 2, hw = (bx2 - bx1) / 2 * 2, hh = (by2 - by1) / 2 * 2;
    x1 = std::min(x1, cx - hw), x2 = std::max(x2, cx + hw), y1 = std::min(y1, cy - hh), y2 = std::max(y2, cy + hh);
  }
  const double border = 8, vw = x2 - x1, vh = y2 - y1, tw = W - 2 * border, th = H - 2 * border;
  double scale;
  int newW = W, newH = H;
  if (vw / tw > vh / th) {
    scale = tw / vw;
    newH = int(std::floor(scale * vh + 2 * border + 0.5));
    newH += (newH ^ H) & 1;
  } else {
    scale = th / vh;
    newW = int(std::floor(scale * vw + 2 * border + 0.5));
    newW += (newW ^ W) & 1;
  }
  Affine frame = Affine::scaling(scale, scale);
  frame.multiply(Affine::translation(-(scale * (x1 + x2) / 2 - newW / 2.0), -(scale * (y1 + y2) / 2 - newH / 2.0)));
  frame.multiply(Affine::translation((W - newW) / 2, (H - newH) / 2));
  if (block) *block = {(W - newW) / 2, (H - newH) / 2, newW, newH};
  return frame;
}

void drawAll(Canvas& canvas, const std::vector<Shape>& shapes, const Affine& frame) {
  for (const Shape& s : shapes) {
    Affine m = s.world;
    m.multiply(frame);
    if (s.path.empty()) canvas.draw({s.primitive, m, s.colour, s.blend});
    else canvas.drawPath(s.path, s.style, m, s.colour, s.blend);
  }
}

// ---- Running both ----

// A PNG's samples as stored (16-bit ones big-endian), with its colour type and depth.
struct RawPng {
  png_uint_32 width = 0, height = 0;
  int colourType = -1, depth = 0;
  std::vector<uint8_t> bytes;
};

// libpng reports errors by longjmp: nothing with a destructor lives in this function.
bool readRawPng(const char* path, RawPng* out) {
  FILE* f = std::fopen(path, "rb");
  if (!f) return false;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    std::fclose(f);
    return false;
  }
  png_init_io(png, f);
  png_read_png(png, info, PNG_TRANSFORM_IDENTITY, nullptr);
  out->width = png_get_image_width(png, info);
  out->height = png_get_image_height(png, info);
  out->colourType = png_get_color_type(png, info);
  out->depth = png_get_bit_depth(png, info);
  const size_t rowBytes = png_get_rowbytes(png, info);
  png_bytepp rows = png_get_rows(png, info);
  out->bytes.resize(rowBytes * out->height);
  for (png_uint_32 y = 0; y < out->height; ++y) std::memcpy(&out->bytes[y * rowBytes], rows[y], rowBytes);
  png_destroy_read_struct(&png, &info, nullptr);
  std::fclose(f);
  return true;
}

struct Case {
  std::string design;  // the .cfdg text; its start shape's variation is fixed (-v A)
  int width, height;
  PixelFormat format;
  Rgba background;
  std::vector<Shape> shapes;
};

class CfdgCanvas : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!llvm::sys::fs::can_execute(kCfdg)) GTEST_SKIP() << kCfdg << " (Context Free) is not installed";
    llvm::SmallString<128> d;
    ASSERT_FALSE(llvm::sys::fs::createUniqueDirectory("lcjit-cfdg-canvas", d));
    dir_ = std::string(d);
  }
  void TearDown() override {
    if (!dir_.empty()) llvm::sys::fs::remove_directories(dir_);
  }

  // Runs cfdg on `design` at W×H (variation A) with extra arguments; false with a test failure
  // when it fails.
  bool runCfdg(const std::string& design, int W, int H, std::vector<std::string> extra, const std::string& out) {
    std::vector<llvm::StringRef> args = {kCfdg, "-q", "-s"};
    const std::string size = std::to_string(W) + "x" + std::to_string(H);
    args.push_back(size);
    args.insert(args.end(), {"-v", "A"});
    for (const std::string& e : extra) args.push_back(e);
    args.push_back(design);
    args.push_back(out);
    std::string error;
    const int rc = llvm::sys::ExecuteAndWait(kCfdg, args, std::nullopt, {}, 120, 0, &error);
    EXPECT_EQ(rc, 0) << "cfdg failed on " << design << ": " << error;
    return rc == 0;
  }

  // Draws `c` with the canvas and with cfdg; expects the same decoded pixels and PNG channels.
  // `crop`: only the fitted block (cfdg -c).
  void expectSameAsCfdg(const Case& c, const std::string& name, bool crop = false) {
    const std::string design = dir_ + "/" + name + ".cfdg", theirs = dir_ + "/" + name + ".cfdg.png",
                      ours = dir_ + "/" + name + ".png";
    std::ofstream(design) << c.design;
    ASSERT_TRUE(runCfdg(design, c.width, c.height, crop ? std::vector<std::string>{"-c"} : std::vector<std::string>{},
                        theirs));
    Canvas canvas(c.width, c.height, c.format, c.background);
    PixelRect block;
    drawAll(canvas, c.shapes, fit(c.shapes, c.width, c.height, &block));
    ASSERT_FALSE(bool(writePng(canvas, ours, crop ? std::optional(block) : std::nullopt)));
    RawPng a, b;
    ASSERT_TRUE(readRawPng(ours.c_str(), &a)) << ours;
    ASSERT_TRUE(readRawPng(theirs.c_str(), &b)) << theirs;
    ASSERT_EQ(a.width, b.width);
    ASSERT_EQ(a.height, b.height);
    EXPECT_EQ(a.colourType, b.colourType) << name << ": PNG colour type";
    ASSERT_EQ(a.depth, b.depth) << name << ": PNG bit depth";
    ASSERT_EQ(a.bytes.size(), b.bytes.size());
    const size_t sample = a.depth / 8, pixel = a.bytes.size() / (size_t(a.width) * a.height);
    size_t differ = 0, first = a.bytes.size();
    int worst = 0;
    for (size_t i = 0; i < a.bytes.size(); i += sample) {
      const int va = sample == 2 ? a.bytes[i] << 8 | a.bytes[i + 1] : a.bytes[i];
      const int vb = sample == 2 ? b.bytes[i] << 8 | b.bytes[i + 1] : b.bytes[i];
      if (va != vb) {
        ++differ;
        first = std::min(first, i);
        worst = std::max(worst, std::abs(va - vb));
      }
    }
    EXPECT_EQ(differ, 0u) << name << ": " << differ << " samples differ from cfdg's (largest by " << worst
                          << "), the first at pixel " << (first / pixel) % a.width << "," << (first / pixel) / a.width;
  }

  std::string dir_;
};

const Rgba kWhite{1, 1, 1, 1};
const Rgba kBlack{0, 0, 0, 1};

TEST_F(CfdgCanvas, LoneSquare) {
  // Bounds ±1.1, scale 484/2.2 = 220: a 222-pixel square (grown 0.8) at the centre, grey PNG.
  const Case c{"startshape A\nshape A { SQUARE [] }\n", 500, 500, PixelFormat::Gray8, kWhite,
               {{Primitive::Square, {}, kBlack}}};
  expectSameAsCfdg(c, "square");
  // Not square: the fitted block is centred at an integer offset, its height of the image's parity.
  Case wide = c;
  wide.width = 301, wide.height = 157;
  expectSameAsCfdg(wide, "square_wide");
}

TEST_F(CfdgCanvas, CroppedToTheFittedBlock) {
  // -c: the 157-pixel block of a 301×157 image; a 200×104 block (the frame's height rounded to
  // the image's parity) with a triangle to tell top from bottom.
  expectSameAsCfdg({"startshape A\nshape A { SQUARE [] }\n", 301, 157, PixelFormat::Gray8, kWhite,
                    {{Primitive::Square, {}, kBlack}}},
                   "crop_square", true);
  expectSameAsCfdg({"startshape A\nshape A { SQUARE [b 0.5] TRIANGLE [x 3 s 0.5] }\n", 200, 200, PixelFormat::Gray8,
                    kWhite, {{Primitive::Square, {}, hsb(0, 0, 0.5)},
                             {Primitive::Triangle, Adjust{3, 0, 0, 0.5, 0.5}.matrix(), kBlack}}},
                   "crop_wide", true);
}

TEST_F(CfdgCanvas, CropCountsRowsFromTheBottom) {
  // cfdg's crops are centred; an off-centre one: AGG's row 0 is the picture's bottom row.
  Canvas canvas(4, 4, PixelFormat::Gray8, kWhite);
  canvas.draw({Primitive::Square, Affine{2, 0, 0, 2, 1, 1}, kBlack});  // AGG pixels [0,2]², grown
  for (auto [y, expected] : {std::pair{0, 0}, {3, 255}}) {
    ASSERT_FALSE(bool(writePng(canvas, dir_ + "/corner.png", PixelRect{0, y, 1, 1})));
    RawPng png;
    ASSERT_TRUE(readRawPng((dir_ + "/corner.png").c_str(), &png));
    ASSERT_EQ(png.width, 1u);
    ASSERT_EQ(png.height, 1u);
    EXPECT_EQ(png.bytes[0], expected) << "AGG row " << y;
  }
}

TEST_F(CfdgCanvas, ColouredShapes) {
  // RGB (the design uses sat); h 30 sat 0.8 b 0.6 is #995C1F.
  const Case c{"startshape A\nshape A {\n SQUARE [h 30 sat 0.8 b 0.6]\n SQUARE [x 0.3 y -0.2 r 45 s 0.4 b 0.9 h 200 sat 1]\n"
               " SQUARE [r 90 s 0.5 0.1 b 0.3]\n}\n",
               333, 280, PixelFormat::Rgb8, kWhite,
               {{Primitive::Square, {}, hsb(30, 0.8, 0.6)},
                {Primitive::Square, Adjust{0.3, -0.2, 45, 0.4, 0.4}.matrix(), hsb(200, 1, 0.9)},
                {Primitive::Square, Adjust{0, 0, 90, 0.5, 0.1}.matrix(), hsb(0, 0, 0.3)}}};
  expectSameAsCfdg(c, "coloured");
}

TEST_F(CfdgCanvas, Circles) {
  // A large square sets the frame (scale 484/4.4 = 110); circles of 110, 33, 4.4 and 1.1 pixels
  // (vertex counts 64, 24, 16 and 8; the last two below 5 pixels, grown as a 5-pixel one).
  const Case c{"startshape A\nshape A {\n SQUARE [s 2 b 0.8]\n CIRCLE []\n CIRCLE [x 0.7 y 0.6 s 0.3 b 0.5]\n"
               " CIRCLE [x -0.7 y 0.6 s 0.04 b 0.2]\n CIRCLE [x -0.7 y -0.6 s 0.01]\n CIRCLE [x 0.5 y -0.5 s 0.6 0.2 r 30 b 1]\n}\n",
               500, 500, PixelFormat::Gray8, kWhite,
               {{Primitive::Square, Adjust{0, 0, 0, 2, 2}.matrix(), hsb(0, 0, 0.8)},
                {Primitive::Circle, {}, kBlack},
                {Primitive::Circle, Adjust{0.7, 0.6, 0, 0.3, 0.3}.matrix(), hsb(0, 0, 0.5)},
                {Primitive::Circle, Adjust{-0.7, 0.6, 0, 0.04, 0.04}.matrix(), hsb(0, 0, 0.2)},
                {Primitive::Circle, Adjust{-0.7, -0.6, 0, 0.01, 0.01}.matrix(), kBlack},
                {Primitive::Circle, Adjust{0.5, -0.5, 30, 0.6, 0.2}.matrix(), kWhite}}};
  expectSameAsCfdg(c, "circles");
}

TEST_F(CfdgCanvas, LoneCircleAndTriangle) {
  // Framed by their own stroked bounds (radius 0.5 + 0.05/cos 22.5°; corners pushed out 0.1).
  expectSameAsCfdg({"startshape A\nshape A { CIRCLE [] }\n", 400, 300, PixelFormat::Gray8, kWhite,
                    {{Primitive::Circle, {}, kBlack}}},
                   "circle");
  expectSameAsCfdg({"startshape A\nshape A { TRIANGLE [] }\n", 300, 400, PixelFormat::Gray8, kWhite,
                    {{Primitive::Triangle, {}, kBlack}}},
                   "triangle");
}

TEST_F(CfdgCanvas, Triangles) {
  const Case c{"startshape A\nshape A {\n SQUARE [s 2 b 0.9]\n TRIANGLE [r 45 b 0.3]\n TRIANGLE [x 0.6 y 0.6 r -90 s 0.5 0.2]\n"
               " TRIANGLE [x -0.6 y -0.6 s 0.03 b 0.5]\n}\n",
               400, 400, PixelFormat::Gray8, kWhite,
               {{Primitive::Square, Adjust{0, 0, 0, 2, 2}.matrix(), hsb(0, 0, 0.9)},
                {Primitive::Triangle, Adjust{0, 0, 45}.matrix(), hsb(0, 0, 0.3)},
                {Primitive::Triangle, Adjust{0.6, 0.6, -90, 0.5, 0.2}.matrix(), kBlack},
                {Primitive::Triangle, Adjust{-0.6, -0.6, 0, 0.03, 0.03}.matrix(), hsb(0, 0, 0.5)}}};
  expectSameAsCfdg(c, "triangles");
}

TEST_F(CfdgCanvas, TranslucentShapesOnABackground) {
  // Shapes with alpha blended on a grey background (gray: translucency without an alpha channel),
  // and a FILL over everything.
  const Case c{"startshape A\nCF::Background = [b -0.4]\nshape A {\n SQUARE [b 0.2]\n CIRCLE [x 0.3 a -0.6 b 0.9]\n"
               " FILL [b 0.5 a -0.7]\n TRIANGLE [y -0.2 a -0.3]\n}\n",
               250, 250, PixelFormat::Gray8, hsb(0, 0, 0.6),
               {{Primitive::Square, {}, hsb(0, 0, 0.2)},
                {Primitive::Circle, Adjust{0.3}.matrix(), hsb(0, 0, 0.9, 0.4)},
                {Primitive::Fill, {}, hsb(0, 0, 0.5, 1 - 0.7)},
                {Primitive::Triangle, Adjust{0, -0.2}.matrix(), hsb(0, 0, 0, 1 - 0.3)}}};
  expectSameAsCfdg(c, "translucent");
}

TEST_F(CfdgCanvas, AlphaChannel) {
  // CF::Alpha: an RGBA PNG, translucent background, rows un-premultiplied.
  const Case c{"startshape A\nCF::Alpha = 1\nCF::Background = [a -0.5 b -0.1 sat 0.7 h 120]\nshape A {\n"
               " SQUARE [h 10 sat 0.9 b 0.8 a -0.3]\n CIRCLE [x 0.3 a -0.6 b 0.9 sat 0.5 h 250]\n}\n",
               200, 150, PixelFormat::Rgba8, hsb(120, 0.7, 0.9, 0.5),
               {{Primitive::Square, {}, hsb(10, 0.9, 0.8, 0.7)},
                {Primitive::Circle, Adjust{0.3}.matrix(), hsb(250, 0.5, 0.9, 0.4)}}};
  expectSameAsCfdg(c, "alpha");
}

TEST_F(CfdgCanvas, BlendModes) {
  // Any blend mode makes the canvas RGBA with AGG's compositing operators; shapes without one
  // are drawn src-over. Multiply 13, Screen 14, Difference 22.
  const Case c{"startshape A\nshape A {\n SQUARE [h 30 sat 0.8 b 0.6]\n CIRCLE [x 0.3 b 0.9 sat 1 h 200 blend CF::Multiply]\n"
               " CIRCLE [x -0.3 b 0.7 sat 0.5 h 100 a -0.4 blend CF::Screen]\n TRIANGLE [y 0.2 b 1 sat 1 h 300 blend CF::Difference]\n"
               " SQUARE [s 0.3 y -0.3 b 0.5]\n}\n",
               300, 300, PixelFormat::Rgba8Blend, kWhite,
               {{Primitive::Square, {}, hsb(30, 0.8, 0.6)},
                {Primitive::Circle, Adjust{0.3}.matrix(), hsb(200, 1, 0.9), 13},
                {Primitive::Circle, Adjust{-0.3}.matrix(), hsb(100, 0.5, 0.7, 0.6), 14},
                {Primitive::Triangle, Adjust{0, 0.2}.matrix(), hsb(300, 1, 1), 22},
                {Primitive::Square, Adjust{0, -0.3, 0, 0.3, 0.3}.matrix(), hsb(0, 0, 0.5)}}};
  expectSameAsCfdg(c, "blend");
}

TEST_F(CfdgCanvas, EveryBlendMode) {
  // Each of cfdg's blend modes (AGG's comp_op numbers) once, a translucent circle over two squares;
  // then FILLs.
  const std::vector<std::pair<const char*, int>> modes = {
      {"Clear", 0},       {"Normal", 3},     {"Xor", 11},        {"Plus", 12},       {"Multiply", 13},
      {"Screen", 14},     {"Overlay", 15},   {"Darken", 16},     {"Lighten", 17},    {"ColorDodge", 18},
      {"ColorBurn", 19},  {"HardLight", 20}, {"SoftLight", 21},  {"Difference", 22}, {"Exclusion", 23}};
  std::string design = "startshape A\nshape A {\n SQUARE [s 8 2 y 0.5 h 30 sat 0.8 b 0.6]\n SQUARE [s 8 2 y -1 h 200 sat 0.5 b 0.9 a -0.4]\n";
  std::vector<Shape> shapes = {{Primitive::Square, Adjust{0, 0.5, 0, 8, 2}.matrix(), hsb(30, 0.8, 0.6)},
                               {Primitive::Square, Adjust{0, -1, 0, 8, 2}.matrix(), hsb(200, 0.5, 0.9, 0.6)}};
  for (size_t i = 0; i < modes.size(); ++i) {
    const double x = -3.5 + 0.5 * double(i), hue = 24.0 * double(i);
    char line[160];
    std::snprintf(line, sizeof line, " CIRCLE [x %g y %g s 1.2 h %g sat 0.9 b 0.8 a -0.3 blend CF::%s]\n", x,
                  i % 2 ? -0.3 : 0.0, hue, modes[i].first);
    design += line;
    shapes.push_back({Primitive::Circle, Adjust{x, i % 2 ? -0.3 : 0.0, 0, 1.2, 1.2}.matrix(), hsb(hue, 0.9, 0.8, 0.7),
                      modes[i].second});
  }
  // A FILL's own blend mode is ignored: it blends with the last shape's (here Exclusion).
  design += " FILL [h 120 sat 0.3 b 0.5 a -0.8 blend CF::Overlay]\n}\n";
  shapes.push_back({Primitive::Fill, {}, hsb(120, 0.3, 0.5, 1 - 0.8), 15});
  expectSameAsCfdg({design, 400, 160, PixelFormat::Rgba8Blend, kWhite, shapes}, "every_blend");
  // Before any shape, src-over.
  expectSameAsCfdg({"startshape A\nCF::Background = [h 200 sat 0.7 b -0.2]\nshape A {\n"
                    " FILL [h 120 sat 0.3 b 0.5 a -0.5 blend CF::Multiply]\n SQUARE [h 30 sat 0.8 b 0.6 blend CF::Screen]\n"
                    " FILL [h 300 sat 0.3 b 0.5 a -0.5]\n}\n",
                    100, 100, PixelFormat::Rgba8Blend, hsb(200, 0.7, 0.8),
                    {{Primitive::Fill, {}, hsb(120, 0.3, 0.5, 0.5), 13},
                     {Primitive::Square, {}, hsb(30, 0.8, 0.6), 14},
                     {Primitive::Fill, {}, hsb(300, 0.3, 0.5, 0.5)}}},
                   "fill_blend");
}

TEST_F(CfdgCanvas, SixteenBits) {
  // CF::ColorDepth 16: colours rounded to 16 bits, 16-bit PNG samples; grey, RGB, RGBA, blending.
  const std::string shapes = "shape A {\n SQUARE [b 0.3]\n CIRCLE [x 0.3 a -0.6 b 0.9]\n TRIANGLE [y -0.2 a -0.3 b 0.55]\n}\n";
  const std::vector<Shape> drawn = {{Primitive::Square, {}, hsb(0, 0, 0.3)},
                                    {Primitive::Circle, Adjust{0.3}.matrix(), hsb(0, 0, 0.9, 0.4)},
                                    {Primitive::Triangle, Adjust{0, -0.2}.matrix(), hsb(0, 0, 0.55, 1 - 0.3)}};
  expectSameAsCfdg({"startshape A\nCF::ColorDepth = 16\nCF::Background = [b -0.35]\n" + shapes, 210, 190,
                    PixelFormat::Gray16, hsb(0, 0, 0.65), drawn},
                   "gray16");
  expectSameAsCfdg({"startshape A\nCF::ColorDepth = 16\nCF::Color = 1\nCF::Background = [b -0.35]\n" + shapes, 210, 190,
                    PixelFormat::Rgb16, hsb(0, 0, 0.65), drawn},
                   "rgb16");
  const Case alpha{"startshape A\nCF::ColorDepth = 16\nCF::Alpha = 1\nCF::Background = [a -0.5 b -0.1 sat 0.7 h 120]\n"
                   "shape A {\n SQUARE [h 10 sat 0.9 b 0.8 a -0.3]\n CIRCLE [x 0.3 a -0.6 b 0.9 sat 0.5 h 250]\n}\n",
                   200, 150, PixelFormat::Rgba16, hsb(120, 0.7, 0.9, 0.5),
                   {{Primitive::Square, {}, hsb(10, 0.9, 0.8, 0.7)},
                    {Primitive::Circle, Adjust{0.3}.matrix(), hsb(250, 0.5, 0.9, 0.4)}}};
  expectSameAsCfdg(alpha, "rgba16");
  const Case blend{"startshape A\nCF::ColorDepth = 16\nshape A {\n SQUARE [h 30 sat 0.8 b 0.6]\n"
                   " CIRCLE [x 0.3 b 0.9 sat 1 h 200 a -0.2 blend CF::Multiply]\n SQUARE [s 0.3 y -0.3 b 0.5]\n}\n",
                   160, 160, PixelFormat::Rgba16Blend, kWhite,
                   {{Primitive::Square, {}, hsb(30, 0.8, 0.6)},
                    {Primitive::Circle, Adjust{0.3}.matrix(), hsb(200, 1, 0.9, 0.8), 13},
                    {Primitive::Square, Adjust{0, -0.3, 0, 0.3, 0.3}.matrix(), hsb(0, 0, 0.5)}}};
  expectSameAsCfdg(blend, "blend16");
}

// ---- Paths ----

// A path's vertices from the operations cfdg turns its path commands into (AGG's path_storage),
// sub-paths aligned as cfdg aligns them.
std::vector<PathVertex> buildPath(void (*ops)(PathBuilder&)) {
  PathBuilder b;
  ops(b);
  b.alignAllPaths();
  return b.vertices();
}

// The shape's adjustment, then the path command's own (STROKE(…)[adj]) before it.
Affine commandThenShape(const Adjust& command, const Adjust& shape) {
  Affine m = command.matrix();
  m.multiply(shape.matrix());
  return m;
}

TEST_F(CfdgCanvas, PathFills) {
  // Polygons, non-zero and even-odd, arcs (AGG's Bézier arcs) and quadratic and cubic curves,
  // flattened at the path's scale; a large square sets the frame (scale 284/6.6).
  const std::string design =
      "startshape A\nshape A {\n SQUARE [s 3 b 0.9]\n P1 [b 0.3]\n P2 [r 30 x -0.8 y -0.6 b 0.5]\n"
      " P2NZ [x 0.8 y 0.9 s 0.6 b 0.7]\n P3 [x 0.2 y -1.2 s 0.8 b 0.1]\n P4 [x -1 y 0.6 s 0.7]\n}\n"
      "path P1 { MOVETO(0, 0) LINETO(1, 0.2) LINETO(0.3, 1) CLOSEPOLY() FILL[] }\n"
      "path P2 {\n MOVETO(-0.5, -0.5) LINETO(0.3, -0.5) LINETO(0.3, 0.3) LINETO(-0.5, 0.3) CLOSEPOLY()\n"
      " MOVETO(-0.2, -0.2) LINETO(0.6, -0.2) LINETO(0.6, 0.6) LINETO(-0.2, 0.6) CLOSEPOLY()\n FILL(CF::EvenOdd)[]\n}\n"
      "path P2NZ {\n MOVETO(-0.5, -0.5) LINETO(0.3, -0.5) LINETO(0.3, 0.3) LINETO(-0.5, 0.3) CLOSEPOLY()\n"
      " MOVETO(-0.2, -0.2) LINETO(0.6, -0.2) LINETO(0.6, 0.6) LINETO(-0.2, 0.6) CLOSEPOLY()\n FILL[]\n}\n"
      "path P3 { MOVETO(0.5, 0) ARCTO(-0.5, 0, 0.5) ARCTO(0.5, 0, 0.5) CLOSEPOLY() FILL[] }\n"
      "path P4 { MOVETO(-0.5, 0) CURVETO(0.5, 0, -0.2, 0.8, 0.4, -0.9) CURVETO(0, -0.5, 0.3, 0.4) CLOSEPOLY() FILL[] }\n";
  auto twoSquares = [](PathBuilder& b) {
    b.moveTo(-0.5, -0.5), b.lineTo(0.3, -0.5), b.lineTo(0.3, 0.3), b.lineTo(-0.5, 0.3), b.closePolygon();
    b.moveTo(-0.2, -0.2), b.lineTo(0.6, -0.2), b.lineTo(0.6, 0.6), b.lineTo(-0.2, 0.6), b.closePolygon();
  };
  PathStyle evenOdd;
  evenOdd.evenOdd = true;
  const Case c{design, 300, 300, PixelFormat::Gray8, kWhite,
               {{Primitive::Square, Adjust{0, 0, 0, 3, 3}.matrix(), hsb(0, 0, 0.9)},
                {Primitive::Square, {}, hsb(0, 0, 0.3),  kBlendSourceOver,
                 buildPath([](PathBuilder& b) { b.moveTo(0, 0), b.lineTo(1, 0.2), b.lineTo(0.3, 1), b.closePolygon(); })},
                {Primitive::Square, Adjust{-0.8, -0.6, 30}.matrix(), hsb(0, 0, 0.5), kBlendSourceOver,
                 buildPath(twoSquares), evenOdd},
                {Primitive::Square, Adjust{0.8, 0.9, 0, 0.6, 0.6}.matrix(), hsb(0, 0, 0.7), kBlendSourceOver,
                 buildPath(twoSquares)},
                {Primitive::Square, Adjust{0.2, -1.2, 0, 0.8, 0.8}.matrix(), hsb(0, 0, 0.1), kBlendSourceOver,
                 buildPath([](PathBuilder& b) {
                   b.moveTo(0.5, 0), b.arcTo(0.5, 0.5, 0, false, true, -0.5, 0);
                   b.arcTo(0.5, 0.5, 0, false, true, 0.5, 0), b.closePolygon();
                 })},
                {Primitive::Square, Adjust{-1, 0.6, 0, 0.7, 0.7}.matrix(), kBlack, kBlendSourceOver,
                 buildPath([](PathBuilder& b) {
                   b.moveTo(-0.5, 0), b.curve4(-0.2, 0.8, 0.4, -0.9, 0.5, 0), b.curve3(0.3, 0.4, 0, -0.5);
                   b.closePolygon();
                 })}}};
  expectSameAsCfdg(c, "path_fills");
}

TEST_F(CfdgCanvas, PathStrokes) {
  // Open and closed strokes: miter, round and bevel joins; butt, square and round caps; a width
  // stretched by the command's own adjustment, and an iso width (in pixels, the same every way);
  // thin strokes (no angle tolerance) and wide ones; arcs and curves.
  const std::string design =
      "startshape A\nshape A {\n SQUARE [s 3 b 0.9]\n S1 [b 0.3]\n S2 [x -1 y -0.8 r 20]\n S3 [x 0.9 y -0.9 s 0.8 b 0.5]\n"
      " S4 [x -0.9 y 0.9 s 0.5 b 0.2]\n S5 [x 0.7 y 0.8 s 0.7]\n}\n"
      "path S1 { MOVETO(0, 0) LINETO(1, 0.2) LINETO(0.3, 1) STROKE(0.08)[] }\n"
      "path S2 { MOVETO(-0.5, -0.3) LINETO(0.5, -0.3) LINETO(0, 0.2) STROKE(0.12, CF::RoundJoin + CF::SquareCap)[]\n"
      " MOVETO(-0.5, 0.1) LINETO(0.5, 0.1) LINETO(0, 0.6) STROKE(0.1, CF::BevelJoin + CF::RoundCap)[y 0.2] }\n"
      "path S3 { MOVETO(-0.4, -0.4) LINETO(0.4, -0.4) LINETO(0.4, 0.4) CLOSEPOLY() STROKE(0.05)[s 1 2]\n"
      " MOVETO(-0.4, -0.4) LINETO(0.2, 0) LINETO(-0.4, 0.4) CLOSEPOLY() STROKE(0.02, CF::IsoWidth)[s 1 3] }\n"
      "path S4 { MOVETO(0.5, 0) ARCTO(-0.5, 0, 0.5) ARCTO(0.5, 0, 0.5) CLOSEPOLY() STROKE(0.2)[]\n"
      " MOVETO(0.3, 0) ARCTO(-0.3, 0, 0.3, 0.15, 30, CF::ArcLarge) STROKE(0.01)[] }\n"
      "path S5 { MOVETO(-0.5, 0) CURVETO(0.5, 0, -0.2, 0.8, 0.4, -0.9) CURVETO(0, -0.5, 0.3, 0.4) STROKE(0.15)[]\n"
      " MOVETO(-0.5, -0.6) CURVETO(0.5, -0.6, 0, 0.2) STROKE(0.005)[] }\n";
  auto stroke = [](double width, uint8_t join = 0, uint8_t cap = 0, bool iso = false) {
    PathStyle style;
    style.stroke = true, style.width = width, style.join = join, style.cap = cap, style.isoWidth = iso;
    return style;
  };
  const Adjust s2{-1, -0.8, 20}, s3{0.9, -0.9, 0, 0.8, 0.8}, s4{-0.9, 0.9, 0, 0.5, 0.5}, s5{0.7, 0.8, 0, 0.7, 0.7};
  const Case c{
      design, 300, 300, PixelFormat::Gray8, kWhite,
      {{Primitive::Square, Adjust{0, 0, 0, 3, 3}.matrix(), hsb(0, 0, 0.9)},
       {Primitive::Square, {}, hsb(0, 0, 0.3), kBlendSourceOver,
        buildPath([](PathBuilder& b) { b.moveTo(0, 0), b.lineTo(1, 0.2), b.lineTo(0.3, 1); }), stroke(0.08)},
       {Primitive::Square, s2.matrix(), kBlack, kBlendSourceOver,
        buildPath([](PathBuilder& b) { b.moveTo(-0.5, -0.3), b.lineTo(0.5, -0.3), b.lineTo(0, 0.2); }),
        stroke(0.12, 2, 1)},
       {Primitive::Square, commandThenShape(Adjust{0, 0.2}, s2), kBlack, kBlendSourceOver,
        buildPath([](PathBuilder& b) { b.moveTo(-0.5, 0.1), b.lineTo(0.5, 0.1), b.lineTo(0, 0.6); }),
        stroke(0.1, 3, 2)},
       {Primitive::Square, commandThenShape(Adjust{0, 0, 0, 1, 2}, s3), hsb(0, 0, 0.5), kBlendSourceOver,
        buildPath([](PathBuilder& b) { b.moveTo(-0.4, -0.4), b.lineTo(0.4, -0.4), b.lineTo(0.4, 0.4), b.closePolygon(); }),
        stroke(0.05)},
       {Primitive::Square, commandThenShape(Adjust{0, 0, 0, 1, 3}, s3), hsb(0, 0, 0.5), kBlendSourceOver,
        buildPath([](PathBuilder& b) { b.moveTo(-0.4, -0.4), b.lineTo(0.2, 0), b.lineTo(-0.4, 0.4), b.closePolygon(); }),
        stroke(0.02, 0, 0, true)},
       {Primitive::Square, s4.matrix(), hsb(0, 0, 0.2), kBlendSourceOver, buildPath([](PathBuilder& b) {
          b.moveTo(0.5, 0), b.arcTo(0.5, 0.5, 0, false, true, -0.5, 0);
          b.arcTo(0.5, 0.5, 0, false, true, 0.5, 0), b.closePolygon();
        }),
        stroke(0.2)},
       {Primitive::Square, s4.matrix(), hsb(0, 0, 0.2), kBlendSourceOver, buildPath([](PathBuilder& b) {
          b.moveTo(0.3, 0), b.arcTo(0.3, 0.15, 30 * 0.0174532925199, true, true, -0.3, 0);  // cfdg's degree
        }),
        stroke(0.01)},
       {Primitive::Square, s5.matrix(), kBlack, kBlendSourceOver, buildPath([](PathBuilder& b) {
          b.moveTo(-0.5, 0), b.curve4(-0.2, 0.8, 0.4, -0.9, 0.5, 0), b.curve3(0.3, 0.4, 0, -0.5);
        }),
        stroke(0.15)},
       {Primitive::Square, s5.matrix(), kBlack, kBlendSourceOver,
        buildPath([](PathBuilder& b) { b.moveTo(-0.5, -0.6), b.curve3(0, 0.2, 0.5, -0.6); }), stroke(0.005)}}};
  expectSameAsCfdg(c, "path_strokes");
}

// ---- Whole designs, through cfdg's SVG ----

// What cfdg's SVG output (-V) lists: every drawn primitive and path, with its colour (8-bit) and
// its transform to SVG pixels (y down, 8 significant digits). A path's joins and caps are not
// there (the SVG names "miter" whatever they are): paths are read as mitred and butt-capped.
struct SvgItem {
  bool isPath = false;
  CanvasShape shape;  // a path's colour and transform too
  std::vector<PathVertex> path;
  PathStyle style;
};

std::vector<PathVertex> svgPathData(const std::string& d) {
  std::vector<PathVertex> v;
  std::istringstream in(d);
  std::string token;
  char command = 0;
  int done = 0;  // points of the current command read
  while (in >> token) {
    if (std::isalpha(static_cast<unsigned char>(token[0]))) {
      command = token[0], done = 0;
      if (command == 'Z') v.push_back({0, 0, kEndPoly | kClose});
      continue;
    }
    double x, y;
    if (std::sscanf(token.c_str(), "%lf,%lf", &x, &y) != 2) continue;
    const unsigned cmd = command == 'M' ? (done == 0 ? kMoveTo : kLineTo) : command == 'L' ? kLineTo
                         : command == 'Q' ? kCurve3 : kCurve4;
    v.push_back({x, y, cmd});
    ++done;
  }
  return v;
}

std::vector<SvgItem> svgItems(const std::string& svg, int H) {
  auto attribute = [](const std::string& e, const std::string& name) -> std::string {
    const size_t at = e.find(" " + name + "=\"");
    if (at == std::string::npos) return "";
    const size_t from = at + name.size() + 3;
    return e.substr(from, e.find('"', from) - from);
  };
  auto colour = [&](const std::string& e, const std::string& colourName, const std::string& opacityName) {
    const unsigned rgb = unsigned(std::stoul(attribute(e, colourName).substr(1), nullptr, 16));
    const std::string opacity = attribute(e, opacityName);
    return Rgba{(rgb >> 16) / 255.0, ((rgb >> 8) & 255) / 255.0, (rgb & 255) / 255.0,
                opacity.empty() ? 1.0 : std::stod(opacity)};
  };
  // SVG's y runs down the picture, AGG's up: y → H - y.
  auto transform = [&](const std::string& e) {
    double m[6] = {1, 0, 0, 1, 0, 0};
    std::sscanf(attribute(e, "transform").c_str(), "matrix(%lf %lf %lf %lf %lf %lf)", m, m + 1, m + 2, m + 3, m + 4,
                m + 5);
    return Affine{m[0], -m[1], m[2], -m[3], m[4], H - m[5]};
  };
  std::vector<SvgItem> items;
  std::map<std::string, std::vector<PathVertex>> paths;  // by id, for <use>
  SvgItem group;  // the <g> a path is drawn in
  bool inGroup = false;
  for (size_t at = svg.find("</defs>"); (at = svg.find('<', at + 1)) != std::string::npos;) {
    const std::string e = svg.substr(at, svg.find('>', at) - at);
    if (e.rfind("<g", 0) == 0) {
      inGroup = true;
      group = SvgItem{};
      group.isPath = true;
      group.shape.toPixels = transform(e);
      group.style.stroke = attribute(e, "fill") == "none";
      if (group.style.stroke) {
        group.shape.colour = colour(e, "stroke", "stroke-opacity");
        group.style.width = std::stod(attribute(e, "stroke-width"));
        group.style.miterLimit = std::stod(attribute(e, "stroke-miterlimit"));
      } else {
        group.shape.colour = colour(e, "fill", "fill-opacity");
        group.style.evenOdd = attribute(e, "fill-rule") == "evenodd";
      }
      continue;
    }
    if (e.rfind("</g", 0) == 0) {
      inGroup = false;
      continue;
    }
    if (inGroup) {
      if (e.rfind("<path", 0) == 0) paths[attribute(e, "id")] = svgPathData(attribute(e, "d"));
      else if (e.rfind("<use", 0) != 0) continue;
      const std::string id = e.rfind("<path", 0) == 0 ? attribute(e, "id") : attribute(e, "xlink:href").substr(1);
      group.path = paths[id];
      items.push_back(group);
      continue;
    }
    SvgItem item;
    if (e.rfind("<rect", 0) == 0) item.shape.primitive = Primitive::Square;
    else if (e.rfind("<circle", 0) == 0) item.shape.primitive = Primitive::Circle;
    else if (e.rfind("<use xlink:href=\"#TRIANGLE\"", 0) == 0) item.shape.primitive = Primitive::Triangle;
    else continue;
    item.shape.colour = colour(e, "fill", "fill-opacity");
    item.shape.toPixels = transform(e);
    items.push_back(item);
  }
  return items;
}

// Shipped example designs (those not tiled, sized or with other joins and caps than mitred and
// butt) drawn from their SVG. The SVG's matrices are rounded to 8 digits, so
// some edge pixels differ; most must not. (Exact matrices come from the engine.) cfdg's SVG turns
// y over about the image height before it adds the fitted block's offset, so where the block is
// lower than the image its shapes sit 2·offset pixels lower than in the PNG: the picture is drawn
// on a canvas three images high and compared at the even shift that matches best.
TEST_F(CfdgCanvas, ShippedExamplesThroughSvg) {
  const std::string examples = "/usr/share/doc/contextfree/examples/";
  if (!llvm::sys::fs::exists(examples)) GTEST_SKIP() << examples << " is not there";
  const int W = 500, H = 500;
  // Squares, circles and triangles; grey and RGB; translucency; fitted blocks lower than the image;
  // filled paths with curves (ciliasun, i_polygons); stroked ones (the rest, default joins and caps).
  for (const char* name : {"welcome", "demo1", "lesson2", "xmas", "sierpinski", "octopi", "rose", "underground",
                           "triples", "i_pix", "alphabet", "tests/arraytest1", "ciliasun", "i_polygons",
                           "tests/polytest4", "tests/looptest3", "tests/bigpathtest", "tests/alloctest1", "tests/wiggle"}) {
    const std::string design = examples + name + ".cfdg", file = dir_ + "/" + llvm::sys::path::filename(name).str(),
                      png = file + ".png", svgFile = file + ".svg";
    if (!runCfdg(design, W, H, {}, png) || !runCfdg(design, W, H, {"-V"}, svgFile)) continue;
    std::ifstream in(svgFile);
    const std::string svg((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::vector<SvgItem> items = svgItems(svg, H);
    auto theirs = loadImage(png);
    ASSERT_TRUE(bool(theirs)) << llvm::toString(theirs.takeError());
    // The background as cfdg's corner pixel shows it (the SVG does not say).
    const uint8_t* corner = theirs->pixel(0, 0);
    const PixelFormat format = theirs->fileChannels == 1 ? PixelFormat::Gray8
                               : theirs->fileChannels == 3 ? PixelFormat::Rgb8 : PixelFormat::Rgba8;
    Canvas canvas(W, 3 * H, format, {corner[0] / 255.0, corner[1] / 255.0, corner[2] / 255.0, corner[3] / 255.0});
    for (SvgItem item : items) {
      item.shape.toPixels.ty += H;
      if (item.isPath) canvas.drawPath(item.path, item.style, item.shape.toPixels, item.shape.colour);
      else canvas.draw(item.shape);
    }
    const std::string oursFile = file + ".ours.png";
    ASSERT_FALSE(bool(writePng(canvas, oursFile)));
    auto ours = loadImage(oursFile);
    ASSERT_TRUE(bool(ours)) << llvm::toString(ours.takeError());
    // cfdg's row y (from the top) is the tall picture's row y + H + shift.
    auto compare = [&](int shift, int* worst) {
      size_t same = 0;
      for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
          int d = 0;
          for (int c = 0; c < 4; ++c)
            d = std::max(d, std::abs(int(ours->pixel(x, y + H + shift)[c]) - int(theirs->pixel(x, y)[c])));
          same += d == 0;
          if (worst) *worst = std::max(*worst, d);
        }
      return same;
    };
    int shift = 0;
    size_t best = 0;
    for (int s = 0; s <= H; s += 2)
      if (size_t same = compare(s, nullptr); same > best) best = same, shift = s;
    int worst = 0;
    const double fraction = double(compare(shift, &worst)) / (W * H);
    std::printf("%-16s %7zu shapes, shift %3d: %8.4f%% of pixels equal, largest difference %d\n", name,
                items.size(), shift, 100 * fraction, worst);
    EXPECT_GE(fraction, 0.999) << name;
    EXPECT_LE(worst, 2) << name;
  }
}

}  // namespace
