// Framing (runtime/turtle/Camera.cpp), the renderer and headless rendering (viewer/): synthetic
// geometry rendered offscreen through EGL, pixels checked at known places.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>

#include "runtime/turtle/Camera.h"
#include "viewer/Headless.h"

#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#include <stb_image.h>

using namespace lcjit;
using namespace lcjit::runtime;
using namespace lcjit::viewer;

namespace {

// ---------------------------------------------------------------------------------------------
// Framing

Bounds box(V3f a, V3f b) {
  Bounds r;
  r.add(a);
  r.add(b);
  return r;
}

TEST(Framing, DefaultScaleFillsNinetyPercent) {
  ViewSettings v;
  CameraMatrices c = frameView(v, box({-1, -1, 0}, {1, 1, 0}), std::nullopt, 800, 800);
  glm::vec3 p = projectToWindow(c, {1, 1, 0});
  EXPECT_NEAR(p.x, 760, 0.01);
  EXPECT_NEAR(p.y, 40, 0.01);
  glm::vec3 o = projectToWindow(c, {0, 0, 0});
  EXPECT_NEAR(o.x, 400, 0.01);
  EXPECT_NEAR(o.y, 400, 0.01);
  EXPECT_FALSE(c.perspective);
  EXPECT_NEAR(c.viewDirection.z, -1, 1e-6);  // looking along -Z, Y up
  EXPECT_NEAR(c.up.y, 1, 1e-6);
}

TEST(Framing, WideWindowKeepsHeight) {
  ViewSettings v;
  CameraMatrices c = frameView(v, box({-1, -1, 0}, {1, 1, 0}), std::nullopt, 1600, 800);
  glm::vec3 p = projectToWindow(c, {1, 1, 0});
  EXPECT_NEAR(p.x, 1160, 0.01);
  EXPECT_NEAR(p.y, 40, 0.01);
}

TEST(Framing, TallVolumeFitsHeight) {
  ViewSettings v;
  CameraMatrices c = frameView(v, box({-1, -2, 0}, {1, 2, 0}), std::nullopt, 800, 800);
  glm::vec3 p = projectToWindow(c, {1, 2, 0});
  EXPECT_NEAR(p.x, 580, 0.01);
  EXPECT_NEAR(p.y, 40, 0.01);
}

TEST(Framing, ScaleAndBox) {
  ViewSettings v;
  v.scale = 0.5f;
  CameraMatrices c = frameView(v, box({-1, -1, 0}, {1, 1, 0}), std::nullopt, 800, 800);
  EXPECT_NEAR(projectToWindow(c, {1, 1, 0}).x, 600, 0.01);
  ViewSettings b;
  b.boxes.push_back({0, {-2, -2, -2}, {2, 2, 2}});
  c = frameView(b, box({-1, -1, 0}, {1, 1, 0}), std::nullopt, 800, 800);
  EXPECT_NEAR(projectToWindow(c, {1, 1, 0}).x, 580, 0.01);
  // A box for another view id does not apply.
  c = frameView(b, box({-1, -1, 0}, {1, 1, 0}), std::nullopt, 800, 800, 1);
  EXPECT_NEAR(projectToWindow(c, {1, 1, 0}).x, 760, 0.01);
}

TEST(Framing, ViewDirection) {
  ViewSettings v;
  ViewDefinition d;
  d.dir = V3f(1, 0, 0);
  d.up = V3f(0, 1, 0);
  v.views.push_back(d);
  CameraMatrices c = frameView(v, box({-1, -1, -1}, {1, 1, 1}), std::nullopt, 800, 800);
  EXPECT_NEAR(c.viewDirection.x, 1, 1e-6);
  EXPECT_GT(projectToWindow(c, {0, 0, 1}).x, 400);  // +Z is to the right when looking along +X
  EXPECT_LT(projectToWindow(c, {0, 1, 0}).y, 400);  // up is up
}

TEST(Framing, Perspective) {
  ViewSettings v;
  v.projection = Projection::Perspective;
  CameraMatrices c = frameView(v, box({-1, -1, 0}, {1, 1, 0}), std::nullopt, 800, 800);
  EXPECT_TRUE(c.perspective);
  glm::vec3 o = projectToWindow(c, {0, 0, 0});
  EXPECT_NEAR(o.x, 400, 0.01);
  // zShift = 1·(1/0.9)/tan(22.5°) + 0.525·2√2; fov' = 2·atan(tan(22.5°)/0.9)
  float hd = 0.525f * 2 * std::sqrt(2.0f);
  float z = (1 / 0.9f) / std::tan(glm::radians(22.5f)) + hd;
  EXPECT_NEAR(c.zShift, z, 1e-4);
  float half = z * std::tan(glm::radians(22.5f)) / 0.9f;
  EXPECT_NEAR(projectToWindow(c, {1, 1, 0}).x, 400 + 400 / half, 0.05);
}

TEST(Framing, CameraModuleAndClipping) {
  ViewSettings v;
  CameraPose pose;
  pose.position = V3f(0, 0, 10);
  pose.heading = V3f(0, 0, -1);
  pose.up = V3f(0, 1, 0);
  CameraMatrices c = frameView(v, box({-1, -1, 0}, {1, 1, 0}), pose, 800, 800);
  EXPECT_NEAR(c.eye.z, 10, 1e-4);
  EXPECT_NEAR(c.eye.x, 0, 1e-4);
  v.frontDistance = -3;
  v.backDistance = 5;
  c = frameView(v, box({-1, -1, 0}, {1, 1, 0}), std::nullopt, 800, 800);
  EXPECT_NEAR(c.halfDepth, 4, 1e-5);
}

TEST(Framing, EmptyAndStationaryLights) {
  ViewSettings v;
  CameraMatrices c = frameView(v, Bounds{}, std::nullopt, 100, 100);
  EXPECT_NEAR(projectToWindow(c, {0, 0, 0}).x, 50, 1e-3);
  c = frameView(v, box({1, 1, 1}, {3, 3, 3}), std::nullopt, 100, 100);
  glm::vec4 t = c.stationaryLights * glm::vec4(2, 2, 2, 1);  // the centre, seen from the initial eye
  EXPECT_NEAR(t.x, 0, 1e-5);
  EXPECT_NEAR(t.z, -c.zShift, 1e-4);
}

// ---------------------------------------------------------------------------------------------
// Rendering

HeadlessRenderer& context() {
  static std::unique_ptr<HeadlessRenderer> r = [] {
    auto e = HeadlessRenderer::create();
    if (!e) {
      ADD_FAILURE() << llvm::toString(e.takeError());
      return std::unique_ptr<HeadlessRenderer>();
    }
    return std::move(*e);
  }();
  if (!r) throw std::runtime_error("no headless context");
  return *r;
}

constexpr std::array<uint8_t, 3> kBg{0, 0, 128}, kRed{255, 0, 0}, kGreen{0, 255, 0};

RenderPalette colors() {
  RenderPalette p;
  p.color[0] = {0, 0, 128 / 255.0f, 1};
  p.color[1] = {1, 0, 0, 1};
  p.color[2] = {0, 1, 0, 1};
  p.color[3] = {1, 1, 1, 1};
  return p;
}

Image render(const Geometry& g, const ViewSettings& v, const RenderPalette& p, int w = 200, int h = 200,
             const std::vector<Image>& textures = {}) {
  HeadlessOptions o;
  o.width = w;
  o.height = h;
  auto img = context().render(g, v, p, textures, o);
  if (!img) {
    ADD_FAILURE() << llvm::toString(img.takeError());
    Image blank;
    blank.width = w;
    blank.height = h;
    blank.rgba.assign(size_t(w) * h * 4, 0);
    return blank;
  }
  // LCJIT_RENDER_TEST_DUMP=dir keeps every picture (dir/Suite.Test.N.png) for looking at.
  if (const char* dir = std::getenv("LCJIT_RENDER_TEST_DUMP")) {
    static int n = 0;
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string path = std::string(dir) + "/" + info->test_suite_name() + "." + info->name() + "." + std::to_string(n++) + ".png";
    llvm::consumeError(writeImage(*img, path));
  }
  return std::move(*img);
}

std::array<uint8_t, 3> rgb(const Image& im, int x, int y) {
  auto p = im.pixel(x, y);
  return {p[0], p[1], p[2]};
}

void tri(Geometry& g, V3f a, V3f b, V3f c, int color, V3f n = {0, 0, 1}) {
  uint32_t i = g.addVertex({a, n, {0, 0}, color});
  uint32_t j = g.addVertex({b, n, {0, 0}, color});
  uint32_t k = g.addVertex({c, n, {0, 0}, color});
  g.addTriangle(i, j, k);
}

Geometry centredTriangle(int color = 1) {
  Geometry g;
  tri(g, {-1, -1, 0}, {1, -1, 0}, {0, 1, 0}, color);
  return g;
}

TEST(Render, TriangleCentreAndBackground) {
  Image im = render(centredTriangle(), ViewSettings{}, colors());
  EXPECT_EQ(rgb(im, 100, 110), kRed);
  EXPECT_EQ(rgb(im, 2, 2), kBg);
  EXPECT_EQ(rgb(im, 197, 197), kBg);
  EXPECT_EQ(im.pixel(100, 110)[3], 255);
  // lpfg's default colormap: black background, white drawing.
  Image d = render(centredTriangle(), ViewSettings{}, RenderPalette{});
  EXPECT_EQ(rgb(d, 100, 110), (std::array<uint8_t, 3>{255, 255, 255}));
  EXPECT_EQ(rgb(d, 2, 2), (std::array<uint8_t, 3>{0, 0, 0}));
}

// A multi-view picture (lpfg's window: lines): every view framed in its rectangle, the window
// border's colour (and width) between views that meet, as lpfg's window lays them out.
TEST(Render, ViewsInTheirRectanglesWithBorders) {
  ViewSettings v;
  v.windowBorderSize = 10;
  v.windowBorderColor = {0, 1, 0};
  std::vector<ViewPane> panes(2);
  panes[0].geometry = centredTriangle(1);
  panes[0].rect = {0, 0, 1, 0.5f};  // the top half
  panes[1].geometry = centredTriangle(3);
  panes[1].rect = {0, 0.5f, 1, 0.5f};
  panes[1].viewId = 1;
  HeadlessOptions o;
  o.width = 200;
  o.height = 200;
  auto im = context().renderPanes(panes, v, colors(), {}, o);
  ASSERT_TRUE(bool(im)) << llvm::toString(im.takeError());
  EXPECT_EQ(im->width, 200);
  EXPECT_EQ(im->height, 200);
  // Each view is 200 x 95 (half the 200 rows less half the border), its triangle in its middle.
  EXPECT_EQ(rgb(*im, 100, 50), kRed);
  EXPECT_EQ(rgb(*im, 100, 152), (std::array<uint8_t, 3>{255, 255, 255}));
  EXPECT_EQ(rgb(*im, 2, 2), kBg);
  EXPECT_EQ(rgb(*im, 2, 197), kBg);
  // The border: rows 95..104.
  EXPECT_EQ(rgb(*im, 100, 96), kGreen);
  EXPECT_EQ(rgb(*im, 2, 103), kGreen);
  EXPECT_EQ(rgb(*im, 2, 93), kBg);
  EXPECT_EQ(rgb(*im, 2, 106), kBg);
  std::array<int, 4> r = paneRects({panes[0].rect, panes[1].rect}, 200, 200, 10)[1];
  EXPECT_EQ(r, (std::array<int, 4>{0, 105, 200, 95}));
}

// lpfg lays views out in a Qt grid of 100 x 100 cells, the border as its spacing, not in exact
// fractions. Expected rectangles: Qt 5.15's QGridLayout given lpfg's layout (mainwindow.cpp),
// and lpfg's pictures (FibonacciFlorets: the separator is column 160, not 159 as half a border
// off 0.4 x 400 would put it).
TEST(Render, ViewsAreLaidOutAsLpfgsGridLayout) {
  using R = ViewPane::Rect;
  using A = std::array<int, 4>;
  auto split = paneRects({R{0, 0, 0.4f, 1}, R{0.4f, 0, 0.6f, 1}}, 400, 400, 1);
  EXPECT_EQ(split, (std::vector<A>{{0, 0, 160, 400}, {161, 0, 239, 400}}));
  // Multiview (vlab): one view above two, a 15-pixel border.
  auto three = paneRects({R{0, 0, 1, 0.5f}, R{0, 0.5f, 0.5f, 0.5f}, R{0.5f, 0.5f, 0.5f, 0.5f}}, 400, 400, 15);
  EXPECT_EQ(three, (std::vector<A>{{0, 0, 400, 192}, {0, 207, 192, 193}, {207, 207, 193, 193}}));
  // In float, 100 x 0.59 is 58.99..., 58 cells, and the second view's 41 cells end at cell 98:
  // 99 cells share 635 pixels, and the first view is 372 wide, not 0.59 x 640 = 377.
  auto truncated = paneRects({R{0, 0, 0.59f, 1}, R{0.59f, 0, 0.41f, 1}}, 640, 300, 5);
  EXPECT_EQ(truncated, (std::vector<A>{{0, 0, 372, 300}, {377, 0, 263, 300}}));
  // Cells no view covers take no room: a lone half-width view fills the picture.
  auto lone = paneRects({R{0, 0, 0.5f, 1}}, 300, 200, 3);
  EXPECT_EQ(lone, (std::vector<A>{{0, 0, 300, 200}}));
}

// Ten windows of 0.2 x 0.5, the fifth column at `0.8 0 0.2 0.5`, a 1-pixel border, 400 wide:
// lpfg's borders fall at columns 79, 159, 239 and 320. The last column's width is 0.2 (20 cells),
// not 1 - 0.8 in float (0.19999999, 19 cells, which moves the borders to 80, 161, 242, 323).
TEST(Render, AWindowEndingAtTheRightEdgeKeepsItsWidth) {
  std::vector<ViewPane::Rect> rects;
  for (float top : {0.f, 0.5f})
    for (float left : {0.f, 0.2f, 0.4f, 0.6f, 0.8f}) rects.push_back(ViewPane::Rect::inside(left, top, 0.2f, 0.5f));
  EXPECT_EQ(rects[4].width, 0.2f);
  auto laid = paneRects(rects, 400, 400, 1);
  ASSERT_EQ(laid.size(), 10u);
  const int borders[4] = {79, 159, 239, 320};
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(laid[size_t(i)][0] + laid[size_t(i)][2], borders[i]) << "view " << i << " ends before the border";
    EXPECT_EQ(laid[size_t(i) + 1][0], borders[i] + 1) << "view " << i + 1 << " starts after it";
  }
  EXPECT_EQ(laid[4][0] + laid[4][2], 400);
  // A window reaching past the edge is still cut at it.
  ViewPane::Rect past = ViewPane::Rect::inside(0.7f, 0.6f, 0.5f, 0.5f);
  EXPECT_FLOAT_EQ(past.left + past.width, 1);
  EXPECT_FLOAT_EQ(past.top + past.height, 1);
}

TEST(Render, NonSquareImage) {
  Image im = render(centredTriangle(), ViewSettings{}, colors(), 300, 150);
  EXPECT_EQ(im.width, 300);
  EXPECT_EQ(im.height, 150);
  EXPECT_EQ(rgb(im, 150, 80), kRed);
  EXPECT_EQ(rgb(im, 20, 75), kBg);  // the triangle fits the height: the sides are background
}

int countColumn(const Image& im, int x, std::array<uint8_t, 3> c) {
  int n = 0;
  for (int y = 0; y < im.height; ++y) n += rgb(im, x, y) == c;
  return n;
}
int countRow(const Image& im, int y, std::array<uint8_t, 3> c) {
  int n = 0;
  for (int x = 0; x < im.width; ++x) n += rgb(im, x, y) == c;
  return n;
}

TEST(Render, SegmentWidthInPixels) {
  for (auto [width, expected] : {std::pair{5.0f, 5}, {1.0f, 1}, {2.6f, 3}, {0.3f, 1}}) {
    Geometry g;
    g.addSegment({{-1, 0, 0}, {1, 0, 0}, width, 1});
    g.addSegment({{0, -1, 0}, {0, -1, 0}, 1, 1});  // a point: frames y, draws nothing
    Image im = render(g, ViewSettings{}, colors());
    EXPECT_EQ(countColumn(im, 100, kRed), expected) << "width " << width;
    EXPECT_EQ(countColumn(im, 60, kRed), expected) << "width " << width;
    EXPECT_EQ(countColumn(im, 5, kRed), 0);  // beyond the segment's end (90% of the width)
  }
  // A vertical (y-major) segment spans its width horizontally.
  Geometry g;
  g.addSegment({{0, -1, 0}, {0, 1, 0}, 4, 2});
  Image im = render(g, ViewSettings{}, colors());
  EXPECT_EQ(countRow(im, 100, kGreen), 4);
}

// Many segments of one width go through GL_LINES (glLineWidth): same pixels as the quads.
TEST(Render, LineRunsWidthInPixels) {
  for (auto [width, expected] : {std::pair{5.0f, 5}, {1.0f, 1}, {3.4f, 3}}) {
    Geometry g;
    for (int i = 0; i < 40; ++i) g.addSegment({{-1 + i * 0.05f, 0, 0}, {-1 + (i + 1) * 0.05f, 0, 0}, width, 1});
    g.addSegment({{0, -1, 0}, {0, -1, 0}, width, 1});
    Image im = render(g, ViewSettings{}, colors());
    EXPECT_EQ(countColumn(im, 100, kRed), expected) << "width " << width;
    EXPECT_EQ(countColumn(im, 37, kRed), expected) << "width " << width;
  }
}

// Fragmented widths (every segment another width) are drawn grouped by width; painter's order
// must survive: the last segment over the centre decides its colour.
TEST(Render, FragmentedWidthsKeepPainterOrder) {
  for (int vertical : {1, 2}) {
    int horizontal = 3 - vertical;
    Geometry g;
    for (int i = 0; i < 4000; ++i) {  // odd: vertical; the last one (3999) is vertical
      float w = float(1 + i % 3);
      if (i % 2) g.addSegment({{0, -1, 0}, {0, 1, 0}, w, vertical});
      else g.addSegment({{-1, 0, 0}, {1, 0, 0}, w, horizontal});
    }
    Image im = render(g, ViewSettings{}, colors(), 201, 201);  // the centre is pixel (100,100)
    auto col = [&](int c) { return c == 1 ? kRed : kGreen; };
    EXPECT_EQ(rgb(im, 100, 100), col(vertical));
    EXPECT_EQ(rgb(im, 100, 40), col(vertical));
    EXPECT_EQ(rgb(im, 40, 100), col(horizontal));
    EXPECT_EQ(context().renderer().stats().drawCalls, 3u);  // one per width
  }
}

RenderPalette materials() {
  RenderPalette p;
  p.materials = true;
  for (auto& m : p.material) m = Material{};
  p.material[0].emission[0] = 0, p.material[0].emission[1] = 0, p.material[0].emission[2] = 0.5f;
  Material& m = p.material[1];
  m.ambient[0] = 0.1f, m.ambient[1] = 0, m.ambient[2] = 0;
  m.diffuse[0] = 0.5f, m.diffuse[1] = 0, m.diffuse[2] = 0;
  p.color = colors().color;
  return p;
}

TEST(Render, MaterialsAreLit) {
  // Default light V: 0 0 1 with ambient 1: 0.2·0.1 + 1·0.1 + 1·0.5 = 0.62 facing the light.
  ViewSettings v;
  v.renderMode = RenderMode::Shaded;
  Image facing = render(centredTriangle(), v, materials());
  EXPECT_NEAR(facing.pixel(100, 110)[0], 158, 2);
  EXPECT_NEAR(facing.pixel(2, 2)[2], 128, 1);  // background = emission of material 0
  Geometry away;
  tri(away, {-1, -1, 0}, {1, -1, 0}, {0, 1, 0}, 1, {0, 0, -1});
  Image dark = render(away, v, materials());
  EXPECT_NEAR(dark.pixel(100, 110)[0], 31, 2);  // ambient only: 0.12
  // Two-sided lighting: a back-facing polygon is lit with the reversed normal.
  Geometry back;
  tri(back, {-1, -1, 0}, {0, 1, 0}, {1, -1, 0}, 1, {0, 0, -1});
  Image b = render(back, v, materials());
  EXPECT_NEAR(b.pixel(100, 110)[0], 158, 2);
  // Filled mode is lit too (flat).
  v.renderMode = RenderMode::Filled;
  EXPECT_NEAR(render(centredTriangle(), v, materials()).pixel(100, 110)[0], 158, 2);
}

TEST(Render, ColormapIsNeverLit) {
  Geometry away;
  tri(away, {-1, -1, 0}, {1, -1, 0}, {0, 1, 0}, 1, {0, 0, -1});
  for (RenderMode m : {RenderMode::Filled, RenderMode::Shaded}) {
    ViewSettings v;
    v.renderMode = m;
    EXPECT_EQ(rgb(render(away, v, colors()), 100, 110), kRed);
  }
}

TEST(Render, FlatVersusSmoothShading) {
  Geometry g;
  uint32_t a = g.addVertex({{-1, -1, 0}, {0, 0, 1}, {0, 0}, 1});
  uint32_t b = g.addVertex({{1, -1, 0}, {0, 0, 1}, {0, 0}, 1});
  uint32_t c = g.addVertex({{0, 1, 0}, {0, 0, -1}, {0, 0}, 1});
  g.addTriangle(a, b, c);
  ViewSettings v;
  v.renderMode = RenderMode::Filled;
  Image flat = render(g, v, materials());
  EXPECT_EQ(rgb(flat, 100, 150), rgb(flat, 100, 40));   // one colour per face
  EXPECT_NEAR(flat.pixel(100, 100)[0], 31, 2);          // the last vertex's
  v.renderMode = RenderMode::Shaded;
  Image smooth = render(g, v, materials());
  EXPECT_GT(smooth.pixel(100, 170)[0], smooth.pixel(100, 40)[0] + 40);  // Gouraud
}

TEST(Render, Texture) {
  Image t;
  t.width = 2;
  t.height = 2;
  t.rgba = {255, 0, 0, 255, 0, 255, 0, 255,      // top row: red, green
            0, 0, 255, 255, 255, 255, 255, 0};   // bottom row: blue, transparent
  Geometry g;
  g.useTexture(0);
  auto v = [&](float x, float y) { return g.addVertex({{x, y, 0}, {0, 0, 1}, {(x + 1) / 2, (y + 1) / 2}, 3}); };
  uint32_t a = v(-1, -1), b = v(1, -1), c = v(1, 1), d = v(-1, 1);
  g.addTriangle(a, b, c);
  g.addTriangle(a, c, d);
  Image im = render(g, ViewSettings{}, colors(), 200, 200, {t});
  EXPECT_EQ(rgb(im, 50, 50), kRed);
  EXPECT_EQ(rgb(im, 150, 50), kGreen);
  EXPECT_EQ(rgb(im, 50, 150), (std::array<uint8_t, 3>{0, 0, 255}));
  EXPECT_EQ(rgb(im, 150, 150), kBg);  // alpha 0: discarded (alpha test > 0.1)
}

TEST(Render, Wireframe) {
  ViewSettings v;
  v.renderMode = RenderMode::Wireframe;
  Image im = render(centredTriangle(), v, colors());
  EXPECT_EQ(rgb(im, 100, 110), kBg);
  int n = countColumn(im, 100, kRed);
  EXPECT_GE(n, 2);  // the bottom edge and the apex
  EXPECT_LE(n, 4);
}

TEST(Render, DepthOrderWithZBufferAndPainterOrderWithout) {
  Geometry g;
  tri(g, {-1, -1, 0.5f}, {1, -1, 0.5f}, {0, 1, 0.5f}, 1);     // near, drawn first
  tri(g, {-1, -1, -0.5f}, {1, -1, -0.5f}, {0, 1, -0.5f}, 2);  // far, drawn last
  ViewSettings v;
  EXPECT_EQ(rgb(render(g, v, colors()), 100, 110), kGreen);  // z buffer off (lpfg default)
  v.zBuffer = true;
  EXPECT_EQ(rgb(render(g, v, colors()), 100, 110), kRed);
}

TEST(Render, PainterOrderAcrossKinds) {
  Geometry g;
  tri(g, {-1, -1, 0}, {1, -1, 0}, {0, 1, 0}, 2);
  g.addSegment({{-1, 0, 0}, {1, 0, 0}, 9, 1});
  Image im = render(g, ViewSettings{}, colors());
  EXPECT_EQ(rgb(im, 100, 100), kRed);  // the segment came last
  Geometry h;
  h.addSegment({{-1, 0, 0}, {1, 0, 0}, 9, 1});
  tri(h, {-1, -1, 0}, {1, -1, 0}, {0, 1, 0}, 2);
  EXPECT_EQ(rgb(render(h, ViewSettings{}, colors()), 100, 100), kGreen);
}

TEST(Render, IncompleteOrderDrawsLinesFirst) {
  Geometry g;
  tri(g, {-1, -1, 0}, {1, -1, 0}, {0, 1, 0}, 2);
  g.segments.push_back({{-1, 0, 0}, {1, 0, 0}, 9, 1});  // not recorded in g.order
  EXPECT_EQ(rgb(render(g, ViewSettings{}, colors()), 100, 100), kGreen);
}

TEST(Render, Discs) {
  Geometry g;
  g.addDisc({{0, 0, 0}, 0, 1, 1});
  Image im = render(g, ViewSettings{}, colors());
  EXPECT_EQ(rgb(im, 100, 100), kRed);
  EXPECT_EQ(rgb(im, 100, 30), kRed);  // radius 90 px
  EXPECT_EQ(rgb(im, 5, 5), kBg);
  Geometry r;
  r.addDisc({{0, 0, 0}, 0.5f, 1, 1});
  Image ring = render(r, ViewSettings{}, colors());
  EXPECT_EQ(rgb(ring, 100, 100), kBg);
  EXPECT_EQ(rgb(ring, 100 + 67, 100), kRed);  // 0.75 of the radius
}

TEST(Render, Label) {
  Geometry g;
  g.addSegment({{-1, -1, 0}, {-1, -1, 0}, 1, 1});
  g.addSegment({{1, 1, 0}, {1, 1, 0}, 1, 1});
  g.labels.push_back({{0, 0, 0}, "HH", 2});
  Image im = render(g, ViewSettings{}, colors());
  int text = 0, outside = 0;
  for (int y = 0; y < 200; ++y)
    for (int x = 0; x < 200; ++x) {
      bool lit = im.pixel(x, y)[1] > 100;
      if (x >= 100 && x < 130 && y >= 85 && y <= 102) text += lit;
      else outside += lit;
    }
  EXPECT_GT(text, 30);
  EXPECT_EQ(outside, 0);
}

// Labels in any script (the bug: "é ü" drawn as "??"): each character of "é ü ß Ω 木" has ink
// where the shaping puts it, and none of them is the '?' glyph or the empty-box .notdef glyph.
TEST(Render, LabelNonAscii) {
  ViewSettings v;
  v.winFontSize = 15;  // 20 px
  auto picture = [&](const std::string& text) {
    Geometry g;
    g.addSegment({{-1, -1, 0}, {-1, -1, 0}, 1, 1});
    g.addSegment({{1, 1, 0}, {1, 1, 0}, 1, 1});
    g.labels.push_back({{-0.9f, 0, 0}, text, 2});
    return render(g, v, colors());
  };
  Geometry frame;
  frame.addSegment({{-1, -1, 0}, {-1, -1, 0}, 1, 1});
  frame.addSegment({{1, 1, 0}, {1, 1, 0}, 1, 1});
  frame.labels.push_back({{-0.9f, 0, 0}, "x", 2});
  CameraMatrices cam = frameView(v, frame.framingBounds(), std::nullopt, 200, 200);
  glm::vec3 at = projectToWindow(cam, {-0.9f, 0, 0});
  const float x0 = std::round(at.x), baseline = std::round(at.y) + 2;
  const int em = runtime::text::pixelSizeForPoints(v.winFontSize);

  // Ink (colour 2, green) in a box of columns [x, x + width) from an em above the baseline to a
  // third of one below, as a bit mask.
  auto mask = [&](const Image& im, int x, int width) {
    std::vector<bool> m;
    for (int y = int(baseline) - em; y < int(baseline) + em / 3; ++y)
      for (int c = x; c < x + width; ++c) m.push_back(c >= 0 && c < 200 && y >= 0 && y < 200 && im.pixel(c, y)[1] > 100);
    return m;
  };
  auto differ = [](const std::vector<bool>& a, const std::vector<bool>& b) {
    size_t n = 0;
    for (size_t i = 0; i < a.size(); ++i) n += a[i] != b[i];
    return n;
  };
  const std::string label = "\xc3\xa9 \xc3\xbc \xc3\x9f \xce\xa9 \xe6\x9c\xa8";
  runtime::text::ShapedText shaped = runtime::text::Fonts::shared().shape(label, labelFont(v), (float)em);
  ASSERT_EQ(shaped.glyphs.size(), 9u);
  Image im = picture(label), question = picture("?"), notdef = picture("\xf4\x8f\xbf\xbd");  // U+10FFFD: no face has it
  for (size_t i = 0; i < shaped.glyphs.size(); i += 2) {  // the characters, not the spaces between
    float next = i + 1 < shaped.glyphs.size() ? shaped.glyphs[i + 1].x : shaped.advance;
    int x = int(std::floor(x0 + shaped.glyphs[i].x)), width = int(std::ceil(next - shaped.glyphs[i].x));
    std::vector<bool> m = mask(im, x, width);
    size_t ink = std::count(m.begin(), m.end(), true);
    EXPECT_GE(ink, 12u) << "character " << i / 2;
    EXPECT_GT(differ(m, mask(question, int(x0), width)), ink / 4) << "character " << i / 2 << " is a '?'";
    EXPECT_GT(differ(m, mask(notdef, int(x0), width)), ink / 4) << "character " << i / 2 << " is .notdef";
  }
  // Nothing beyond the shaped advance.
  std::vector<bool> after = mask(im, int(std::ceil(x0 + shaped.advance)) + 2, 30);
  EXPECT_EQ(std::count(after.begin(), after.end(), true), 0);
}

TEST(Render, Shadows) {
  Geometry g;
  auto quad = [&](float x0, float y0, float x1, float y1, float z, int color) {
    tri(g, {x0, y0, z}, {x1, y0, z}, {x1, y1, z}, color);
    tri(g, {x0, y0, z}, {x1, y1, z}, {x0, y1, z}, color);
  };
  quad(-1, -1, 1, 1, 0, 2);              // ground
  quad(-0.3f, -0.3f, 0.3f, 0.3f, 0.5f, 1);  // occluder above it
  ViewSettings v;
  v.renderMode = RenderMode::Shadows;
  Light l;
  l.position = V3f(1, 0, 1);  // from the right and the viewer
  l.ambient = {0, 0, 0};
  v.lights.push_back(l);
  RenderPalette p = materials();
  Material& ground = p.material[2];
  ground.ambient[0] = 0, ground.ambient[1] = 0.1f, ground.ambient[2] = 0;
  ground.diffuse[0] = 0, ground.diffuse[1] = 0.8f, ground.diffuse[2] = 0;
  Image im = render(g, v, p);
  // The shadow falls 0.5 to the left: world x ∈ [-0.8, -0.2]; pixels at x = -0.65 and +0.65.
  int shadowX = int(100 - 0.65f * 90), litX = int(100 + 0.65f * 90);
  EXPECT_LT(im.pixel(shadowX, 100)[1] + 40, im.pixel(litX, 100)[1]);
  EXPECT_NEAR(im.pixel(litX, 100)[1], 255 * (0.02 + 0.8 * std::sqrt(0.5)), 3);
  // Colour 2 above and below the occluder's shadow is lit.
  EXPECT_NEAR(im.pixel(shadowX, 20)[1], im.pixel(litX, 100)[1], 2);
}

TEST(Render, BackfaceCulling) {
  Geometry g;
  tri(g, {-1, -1, 0}, {0, 1, 0}, {1, -1, 0}, 1);  // clockwise: back-facing
  ViewSettings v;
  EXPECT_EQ(rgb(render(g, v, colors()), 100, 110), kRed);
  v.backfaceCulling = true;
  EXPECT_EQ(rgb(render(g, v, colors()), 100, 110), kBg);
}

TEST(Render, Transparency) {
  RenderPalette p = materials();
  p.material[1].emission[0] = 1;
  p.material[1].transparency = 0.5f;
  Image im = render(centredTriangle(), ViewSettings{}, p);
  auto c = im.pixel(100, 110);
  EXPECT_NEAR(c[0], 128, 2);  // half red over the blue background
  EXPECT_NEAR(c[2], 64, 2);
}

TEST(Render, ProjectToWindowMatchesPixels) {
  Geometry g;
  g.addSegment({{-1, -1, 0}, {1, 1, 0}, 1, 1});
  g.addDisc({{0.5f, -0.25f, 0}, 0, 0.05f, 2});
  ViewSettings v;
  Image im = render(g, v, colors(), 240, 160);
  CameraMatrices c = frameView(v, g.bounds(), std::nullopt, 240, 160);
  glm::vec3 p = projectToWindow(c, {0.5f, -0.25f, 0});
  EXPECT_EQ(rgb(im, int(p.x), int(p.y)), kGreen);
}

TEST(Headless, WritesImageFiles) {
  Image im = render(centredTriangle(), ViewSettings{}, colors(), 64, 48);
  auto dir = std::filesystem::temp_directory_path() / "lcjit_render_test";
  std::filesystem::create_directories(dir);
  for (const char* name : {"a.png", "a.jpg", "a.BMP", "a.jpeg"}) {
    std::string path = (dir / name).string();
    ASSERT_FALSE(writeImage(im, path)) << path;
    int w = 0, h = 0, n = 0;
    unsigned char* data = stbi_load(path.c_str(), &w, &h, &n, 3);
    ASSERT_NE(data, nullptr) << path;
    EXPECT_EQ(w, 64);
    EXPECT_EQ(h, 48);
    const unsigned char* px = data + (24 * 64 + 32) * 3;  // centre: red
    EXPECT_NEAR(px[0], 255, 8);
    EXPECT_NEAR(px[2], 0, 8);
    const unsigned char* corner = data;
    EXPECT_NEAR(corner[2], 128, 8);
    stbi_image_free(data);
  }
  llvm::Error e = writeImage(im, (dir / "a.tiff").string());
  EXPECT_TRUE(bool(e));
  llvm::consumeError(std::move(e));
  std::string out = (dir / "direct.png").string();
  EXPECT_FALSE(renderToFile(centredTriangle(), ViewSettings{}, colors(), {}, out));
  EXPECT_TRUE(std::filesystem::exists(out));
  std::filesystem::remove_all(dir);
}

// The performance target: one million pixel segments to a PNG at 800×800 in about a second
// (measured with a context already made; shaders compiled on first use are included once).
TEST(Headless, MillionSegments) {
  for (bool varied : {false, true}) {
    Geometry g;
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> step(-0.01f, 0.01f);
    V3f p(0, 0, 0);
    g.segments.reserve(1000000);
    for (int i = 0; i < 1000000; ++i) {
      V3f q(p.x + step(rng), p.y + step(rng), p.z + step(rng));
      if (std::fabs(q.x) > 1 || std::fabs(q.y) > 1) q = V3f(0, 0, 0);
      g.segments.push_back({p, q, varied ? float(1 + i % 3) : 1.0f, 1 + i % 3});
      p = q;
    }
    auto dir = std::filesystem::temp_directory_path() / "lcjit_render_perf";
    std::filesystem::create_directories(dir);
    HeadlessOptions o;
    auto t0 = std::chrono::steady_clock::now();
    auto im = context().render(g, ViewSettings{}, colors(), {}, o);
    ASSERT_TRUE(bool(im)) << llvm::toString(im.takeError());
    auto t1 = std::chrono::steady_clock::now();
    ASSERT_FALSE(writeImage(*im, (dir / "million.png").string()));
    auto t2 = std::chrono::steady_clock::now();
    auto again = context().renderFrame(ViewSettings{}, frameView(ViewSettings{}, g.bounds(), std::nullopt, 800, 800));
    auto t3 = std::chrono::steady_clock::now();
    ASSERT_TRUE(bool(again));
    auto sec = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
    std::printf("1M segments (%s widths) 800x800: upload+draw+read %.3f s + PNG %.3f s = %.3f s; redraw+read %.3f s (%s)\n",
                varied ? "varied" : "equal", sec(t0, t1), sec(t1, t2), sec(t0, t2), sec(t2, t3),
                context().glRenderer().c_str());
    EXPECT_LT(sec(t0, t2), 10.0);
    EXPECT_LE(context().renderer().stats().drawCalls, 3u);
    int nonBg = 0;
    for (int y = 0; y < 800; y += 4)
      for (int x = 0; x < 800; x += 4) nonBg += rgb(*im, x, y) != kBg;
    EXPECT_GT(nonBg, 100);
    std::filesystem::remove_all(dir);
  }
}

}  // namespace
