// The 2D picture: SVG, PostScript/EPS and PDF. Everything is projected with the renderer's framing
// (frameView / projectToWindow) and drawn back to front (painter's algorithm, by mean depth), in
// flat palette colours like lpfg's PostScript output. Labels are shaped as the renderer shapes
// them (runtime/text): SVG keeps them as text, PostScript and PDF draw the glyphs' outlines. A
// multi-view model's page holds every view in its rectangle, as the picture lays them out
// (ViewLayout.h), each view clipped to it.
#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

#include "runtime/export/ExportCommon.h"
#include "runtime/export/ExportFormats.h"
#include "runtime/text/LabelText.h"

namespace lcjit::runtime::exporting {
namespace {

// Rounded to 1/100 pixel and printed shortest ("12.5", "3").
struct Num {
  double v;
};
Num num(float f) { return {std::round(double(f) * 100) / 100}; }
Num num3(float f) { return {std::round(double(f) * 1000) / 1000}; }

}  // namespace
}  // namespace lcjit::runtime::exporting

template <> struct fmt::formatter<lcjit::runtime::exporting::Num> : fmt::formatter<double> {
  auto format(lcjit::runtime::exporting::Num n, format_context& ctx) const {
    double v = n.v == 0 ? 0 : n.v;  // no "-0"
    return fmt::format_to(ctx.out(), "{}", v);
  }
};

namespace lcjit::runtime::exporting {
namespace {

struct Item {
  uint32_t depth;  // window depth quantised, so that coplanar things keep their drawing order
  uint32_t index;
  enum Kind : uint8_t { Triangle, Line, Disc, Ring, Text } kind;
};

// One view's drawing, in its own window coordinates (x right, y down, pixels).
struct Picture {
  const Geometry* g = nullptr;
  int x = 0, y = 0;  // its top left corner on the page
  int width = 0, height = 0;
  std::vector<glm::vec3> win;  // projected mesh vertices
  std::vector<Item> items;     // back to front
  std::vector<Rgba> triangleColor;
  struct Circle {
    float x, y, r, w;
  };
  std::vector<Circle> circles;  // per disc
  std::vector<glm::vec3> segmentEnds, labelAt;
};

uint32_t quantise(float depth) { return (uint32_t)std::lround(std::clamp(depth, 0.0f, 1.0f) * float(1 << 20)); }

bool inDepth(const glm::vec3& p) { return p.z >= 0 && p.z <= 1 && std::isfinite(p.x) && std::isfinite(p.y); }

Picture draw(const Context& cx, const Geometry& g, const CameraMatrices& cam) {
  Picture pic;
  pic.g = &g;
  pic.width = cam.width;
  pic.height = cam.height;
  const float W = (float)cam.width, H = (float)cam.height;

  pic.win.resize(g.vertices.size());
  for (size_t i = 0; i < g.vertices.size(); ++i) pic.win[i] = projectToWindow(cam, g.vertices[i].position);

  // Optional shading: 0.2 ambient + each light's diffuse brightness × |n·l| (two-sided).
  std::vector<std::pair<V3f, float>> lights;
  if (cx.in.shade) {
    const Bounds b = g.bounds();
    const V3f centre = b.empty() ? V3f(0, 0, 0) : b.center();
    for (const Light& l : cx.view.lights.empty() ? std::vector<Light>{Light()} : cx.view.lights)
      lights.push_back({lightDirection(cx, l, centre), (l.diffuse.r + l.diffuse.g + l.diffuse.b) / 3});
  }
  const int gradient = cx.view.gradientMagnitude != 0 ? cx.view.gradientDirection : 0;

  const size_t nt = g.triangleCount();
  pic.items.reserve(nt + g.segments.size() + g.discs.size() + g.labels.size());
  pic.triangleColor.resize(nt);
  for (size_t t = 0; t < nt; ++t) {
    uint32_t ia = g.indices[3 * t], ib = g.indices[3 * t + 1], ic = g.indices[3 * t + 2];
    const glm::vec3 &a = pic.win[ia], &b = pic.win[ib], &c = pic.win[ic];
    if (!inDepth(a) || !inDepth(b) || !inDepth(c)) continue;
    if ((a.x < 0 && b.x < 0 && c.x < 0) || (a.x > W && b.x > W && c.x > W) || (a.y < 0 && b.y < 0 && c.y < 0) ||
        (a.y > H && b.y > H && c.y > H))
      continue;
    float area = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
    if (area == 0) continue;
    if (cx.view.backfaceCulling && area > 0) continue;  // window y points down: front faces turn clockwise
    const MeshVertex &va = g.vertices[ia], &vb = g.vertices[ib], &vc = g.vertices[ic];
    Rgba col = cx.color(va.color);
    float k = 1;
    if (gradient == 1) k += cx.view.gradientMagnitude * (va.uv.x + vb.uv.x + vc.uv.x) / 3;
    else if (gradient == 2) k += cx.view.gradientMagnitude * (va.uv.y + vb.uv.y + vc.uv.y) / 3;
    if (!lights.empty()) {
      V3f n = va.normal + vb.normal + vc.normal;
      if (!(n * n >= 1e-12f)) n = (vb.position - va.position) % (vc.position - va.position);  // also NaN
      n = unit(n);
      float s = 0.2f;
      for (auto& [d, bright] : lights) s += bright * std::fabs(n * d);
      k *= std::min(s, 1.0f);
    }
    if (k != 1)
      for (int i = 0; i < 3; ++i) col[i] = std::clamp(col[i] * k, 0.0f, 1.0f);
    pic.triangleColor[t] = col;
    pic.items.push_back({quantise((a.z + b.z + c.z) / 3), (uint32_t)t, Item::Triangle});
  }

  pic.segmentEnds.resize(2 * g.segments.size());
  for (size_t i = 0; i < g.segments.size(); ++i) {
    glm::vec3 a = projectToWindow(cam, g.segments[i].from), b = projectToWindow(cam, g.segments[i].to);
    pic.segmentEnds[2 * i] = a;
    pic.segmentEnds[2 * i + 1] = b;
    if (!inDepth(a) || !inDepth(b)) continue;
    pic.items.push_back({quantise((a.z + b.z) / 2), (uint32_t)i, Item::Line});
  }

  const CameraFrame frame = cameraFrame(cam);
  pic.circles.resize(g.discs.size());
  for (size_t i = 0; i < g.discs.size(); ++i) {
    const Disc& d = g.discs[i];
    glm::vec3 c = projectToWindow(cam, d.center);
    if (!inDepth(c)) continue;
    auto radius = [&](float r) {
      glm::vec3 e = projectToWindow(cam, d.center + frame.right * r);
      return std::hypot(e.x - c.x, e.y - c.y);
    };
    float ro = radius(d.outer);
    if (d.inner > 0) {
      float ri = radius(d.inner);
      pic.circles[i] = {c.x, c.y, (ro + ri) / 2, ro - ri};
      pic.items.push_back({quantise(c.z), (uint32_t)i, Item::Ring});
    } else {
      pic.circles[i] = {c.x, c.y, ro, 0};
      pic.items.push_back({quantise(c.z), (uint32_t)i, Item::Disc});
    }
  }

  pic.labelAt.resize(g.labels.size());
  for (size_t i = 0; i < g.labels.size(); ++i) {
    pic.labelAt[i] = projectToWindow(cam, g.labels[i].position);
    if (inDepth(pic.labelAt[i])) pic.items.push_back({quantise(pic.labelAt[i].z), (uint32_t)i, Item::Text});
  }

  // Far (depth 1) first; drawing order (triangles, segments, discs, labels) among equals.
  std::stable_sort(pic.items.begin(), pic.items.end(), [](const Item& a, const Item& b) { return a.depth > b.depth; });
  return pic;
}

// What a 2D file shows: the picture of the geometry, or each of a multi-view model's views in its
// rectangle of the page (paneRects, paneCamera: as the renderer lays them out), the window border
// colour between them.
struct Page {
  int width = 0, height = 0;
  std::vector<Picture> pictures;
  bool multiView = false;
  Rgba border{0, 0, 0, 1};
};

Page drawPage(const Context& cx) {
  Page page;
  if (!cx.in.views || cx.in.views->empty()) {
    page.pictures.push_back(draw(cx, cx.geometry, cx.camera()));
    page.width = page.pictures[0].width, page.height = page.pictures[0].height;
    return page;
  }
  const std::vector<ViewPane>& views = *cx.in.views;
  page.multiView = true;
  page.width = std::max(1, cx.in.width), page.height = std::max(1, cx.in.height);
  const Rgb& b = cx.view.windowBorderColor;
  page.border = {b.r, b.g, b.b, 1};
  std::vector<ViewPane::Rect> rects;
  for (const ViewPane& v : views) rects.push_back(v.rect);
  const std::vector<std::array<int, 4>> placed = paneRects(rects, page.width, page.height, cx.view.windowBorderSize);
  for (size_t i = 0; i < views.size(); ++i) {
    Picture pic = draw(cx, views[i].geometry, paneCamera(cx.view, views[i], placed[i], cx.in.adjust));
    pic.x = placed[i][0], pic.y = placed[i][1];
    page.pictures.push_back(std::move(pic));
  }
  return page;
}

struct Hex {
  Rgba c;
};

}  // namespace
}  // namespace lcjit::runtime::exporting

template <> struct fmt::formatter<lcjit::runtime::exporting::Hex> {
  constexpr auto parse(format_parse_context& ctx) { return ctx.begin(); }
  auto format(const lcjit::runtime::exporting::Hex& h, format_context& ctx) const {
    auto b = [](float f) { return (int)std::lround(std::clamp(f, 0.0f, 1.0f) * 255); };
    return fmt::format_to(ctx.out(), "#{:02x}{:02x}{:02x}", b(h.c[0]), b(h.c[1]), b(h.c[2]));
  }
};

namespace lcjit::runtime::exporting {
namespace {

std::string xmlEscape(std::string_view s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default:
        if ((unsigned char)c < 0x20 && c != '\t' && c != '\n') break;  // not allowed in XML 1.0
        out += c;
    }
  }
  return out;
}

// A label's text for a comment line of PostScript or PDF (where it is not drawn as text).
std::string commentText(std::string_view s) {
  std::string out = text::cleanUtf8(s);
  for (char& c : out)
    if ((unsigned char)c < 0x20) c = ' ';
  return out;
}

// Labels as the renderer draws them: the same faces (the view's `winfont:`, fontconfig's
// fallbacks), HarfBuzz's shaping kerned as Qt kerns, the em at 96 dpi, the left end at
// the anchor and the baseline 2 px below it. Outlines in window pixels, y down; each glyph's outline is loaded once.
class LabelGlyphs {
 public:
  explicit LabelGlyphs(const ViewSettings& v)
      : spec_{.family = v.winFont, .weight = v.winFontWeight, .italic = v.winFontItalic},
        em_((float)text::pixelSizeForPoints(v.winFontSize)) {}
  float em() const { return em_; }
  // f(outline, x, y): each glyph of `label` anchored at window point p, its origin at (x, y).
  template <class F> void forEach(const Label& label, const glm::vec3& p, F&& f) {
    text::ShapedText t = text::Fonts::shared().shape(label.text, spec_, em_);
    for (const text::PlacedGlyph& g : t.glyphs) {
      auto key = std::make_pair(g.face, g.glyph);
      auto it = outlines_.find(key);
      if (it == outlines_.end()) it = outlines_.emplace(key, text::Fonts::shared().outline(g.face, g.glyph, em_)).first;
      if (!it->second.empty()) f(it->second, p.x + g.x, p.y + 2 + g.y);
    }
  }

 private:
  text::FontSpec spec_;
  float em_;
  std::map<std::pair<int, uint32_t>, text::GlyphOutline> outlines_;
};

// An outline as path operators ("x y m", "x y l", "x1 y1 x2 y2 x3 y3 c", "h"); `at` maps a
// window point to the output's coordinates as two strings.
template <class Out, class At> void outlinePath(const text::GlyphOutline& o, float x, float y, Out&& out, At&& at) {
  size_t k = 0;
  for (text::GlyphOutline::Op op : o.ops) {
    switch (op) {
      case text::GlyphOutline::Move:
      case text::GlyphOutline::Line:
        out(at(x + o.xy[k], y + o.xy[k + 1]) + (op == text::GlyphOutline::Move ? " m " : " l "));
        k += 2;
        break;
      case text::GlyphOutline::Cubic:
        out(at(x + o.xy[k], y + o.xy[k + 1]) + " " + at(x + o.xy[k + 2], y + o.xy[k + 3]) + " " +
            at(x + o.xy[k + 4], y + o.xy[k + 5]) + " c ");
        k += 6;
        break;
      case text::GlyphOutline::Close: out(std::string("h\n")); break;
    }
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------------

// SVG path data, kept small: coordinates on a grid of 1/kSvgGrid pixel, every move relative to the
// current point (exact differences of grid points, so rounding never accumulates), numbers without
// leading zeros and with only the separators the path grammar needs ("m1.5-2 .5.5").
//
// The grid: the SVG's user unit is one pixel of the picture (-w W H), the size lpfg's picture and
// lcjit's PNG have. A tenth of a pixel moves an edge by at most 0.05 px — under 1/20 of one
// pixel's anti-aliased coverage at that size, and 1/16 000 of an 800-pixel picture when it is
// enlarged — where the former 1/100 px cost a digit more per number for nothing visible.
constexpr double kSvgGrid = 10;

int64_t onGrid(float v) { return std::llround(double(v) * kSvgGrid); }

class PathData {
 public:
  std::string d;
  bool empty() const { return d.empty(); }
  void clear() { d.clear(), last_ = None; }
  void command(char c) { d += c, last_ = None; }
  void number(int64_t q) {  // q / kSvgGrid
    char buf[32];
    char* e = buf;
    const bool negative = q < 0;
    uint64_t a = negative ? uint64_t(-q) : uint64_t(q);
    const uint64_t whole = a / uint64_t(kSvgGrid), tenth = a % uint64_t(kSvgGrid);
    if (negative) *e++ = '-';
    if (whole || !tenth) e = fmt::format_to(e, "{}", whole);
    if (tenth) *e++ = '.', *e++ = char('0' + tenth);
    // A separator unless the sign or a second decimal point ends the previous number.
    if (last_ != None && !negative && !(buf[0] == '.' && last_ == Fraction)) d += ' ';
    d.append(buf, e);
    last_ = tenth ? Fraction : Whole;
  }

 private:
  enum { None, Whole, Fraction } last_ = None;
};

// Number in an attribute, on the same grid.
std::string gridNumber(float v) {
  PathData p;
  p.number(onGrid(v));
  return p.d;
}

llvm::Error writeSvg(const Context& cx) {
  const Page page = drawPage(cx);
  FileWriter w;
  if (auto e = w.open(cx.path)) return e;

  // Colours go in classes, one for fill and one for stroke per colour used (fN, sN).
  std::unordered_map<uint32_t, int> classOf;
  std::vector<Rgba> classColor;
  auto packed = [](const Rgba& c) {
    auto b = [](float f) { return (uint32_t)std::lround(std::clamp(f, 0.0f, 1.0f) * 255); };
    return b(c[0]) << 16 | b(c[1]) << 8 | b(c[2]);
  };
  auto colorClass = [&](const Rgba& c) {
    auto [it, added] = classOf.try_emplace(packed(c), (int)classColor.size());
    if (added) classColor.push_back(c);
    return it->second;
  };
  auto itemColor = [&](const Picture& pic, const Item& it) -> Rgba {
    const Geometry& g = *pic.g;
    switch (it.kind) {
      case Item::Triangle: return pic.triangleColor[it.index];
      case Item::Line: return cx.color(g.segments[it.index].color);
      case Item::Disc:
      case Item::Ring: return cx.color(g.discs[it.index].color);
      case Item::Text: return cx.textColor(g.labels[it.index].color);
    }
    return {};
  };
  for (const Picture& pic : page.pictures)
    for (const Item& it : pic.items) colorClass(itemColor(pic, it));

  w.print("<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"no\"?>\n<!-- written by lcjit; coordinates to 1/{} px -->\n",
          kSvgGrid);
  w.print("<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"{0}\" height=\"{1}\" viewBox=\"0 0 {0} {1}\">\n",
          page.width, page.height);
  // Triangles (.t) get a hairline of their own colour so anti-aliasing leaves no seams between them.
  w.print("<style>\n.t{{stroke-width:.5px;stroke-linejoin:round}}.l{{fill:none;stroke-linecap:butt}}\n");
  w.print("text{{font-family:\"{}\";font-size:{}px;font-kerning:none{}{}}}\n", xmlEscape(cx.view.winFont),
          text::pixelSizeForPoints(cx.view.winFontSize), cx.view.winFontBold() ? ";font-weight:bold" : "",
          cx.view.winFontItalic ? ";font-style:italic" : "");
  for (size_t i = 0; i < classColor.size(); ++i) {
    w.print(".f{0:x}{{fill:{1}}}.s{0:x}{{stroke:{1}}}", i, Hex{classColor[i]});
    w.text(i % 4 == 3 || i + 1 == classColor.size() ? "\n" : "");
  }
  w.text("</style>\n");
  // One view: its background, then the plant. Several: the border colour, then each view as an
  // <svg> of its own (its viewport clips it, its coordinates are the view's), background and plant.
  w.print("<rect id=\"{}\" x=\"0\" y=\"0\" width=\"{}\" height=\"{}\" fill=\"{}\"/>\n",
          page.multiView ? "border" : "background", page.width, page.height,
          Hex{page.multiView ? page.border : cx.color(0)});

  // Consecutive opaque triangles of one colour share a group (<g class="t fN sN">), as do
  // consecutive opaque segments of one colour and width: the style is said once, while each shape
  // stays an element of its own, so that where shapes overlap their anti-aliased edges blend as
  // they did (one path for many would fill their union instead: 0.25 % of a bushy picture's pixels
  // came out different). Two triangles that share an edge, the halves of a quad, are one polygon:
  // they do not overlap. Translucent shapes stay apart from any group, as their overlaps must blend.
  using Point = std::array<int64_t, 2>;
  enum Kind { None, Triangles, Lines } open = None;
  int openClass = -1;
  float openWidth = 0;
  std::vector<Point> pending;  // a triangle that may become a quad with the next one
  PathData d;
  // <path d="m x y dx dy …">: the first point absolute, the others relative (implicit linetos).
  auto writePath = [&](const Point* p, size_t n, bool close) {
    d.clear();
    d.command('m');
    d.number(p[0][0]), d.number(p[0][1]);
    for (size_t k = 1; k < n; ++k) d.number(p[k][0] - p[k - 1][0]), d.number(p[k][1] - p[k - 1][1]);
    if (close) d.command('z');
    w.text("<path d=\"");
    w.text(d.d);
    w.text("\"/>\n");
  };
  auto flushPending = [&]() {
    if (!pending.empty()) writePath(pending.data(), pending.size(), true);
    pending.clear();
  };
  auto flush = [&]() {
    flushPending();
    if (open != None) w.text("</g>\n");
    open = None;
    w.flushIfLarge();
  };
  auto begin = [&](Kind kind, int cls, float width) {
    if (open == kind && openClass == cls && openWidth == width) return;
    flush();
    open = kind, openClass = cls, openWidth = width;
    if (kind == Triangles) w.print("<g class=\"t f{0:x} s{0:x}\">\n", cls);
    else if (width == 1) w.print("<g class=\"l s{:x}\">\n", cls);
    else w.print("<g class=\"l s{:x}\" stroke-width=\"{}\">\n", cls, num(width));
  };
  auto area2 = [](const Point& a, const Point& b, const Point& c) {
    return (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
  };
  // The quad of `pending` and t when they share an edge and turn the same way (then they lie on
  // either side of it and their union is that quad); false otherwise.
  auto mergeQuad = [&](const std::array<Point, 3>& t) {
    if (pending.size() != 3) return false;
    const int64_t a1 = area2(pending[0], pending[1], pending[2]), a2 = area2(t[0], t[1], t[2]);
    if (a1 == 0 || a2 == 0 || (a1 > 0) != (a2 > 0)) return false;
    for (int e = 0; e < 3; ++e) {  // pending's edge e → e+1, which t must run the other way
      const Point &p = pending[e], &q = pending[(e + 1) % 3];
      for (int k = 0; k < 3; ++k)
        if (t[k] == q && t[(k + 1) % 3] == p) {
          const Point other = t[(k + 2) % 3];
          pending.insert(pending.begin() + e + 1, other);
          return true;
        }
    }
    return false;
  };

  for (size_t view = 0; view < page.pictures.size(); ++view) {
    const Picture& pic = page.pictures[view];
    const Geometry& g = *pic.g;
    if (page.multiView)
      w.print("<svg id=\"view{0}\" x=\"{1}\" y=\"{2}\" width=\"{3}\" height=\"{4}\" overflow=\"hidden\">\n"
              "<rect x=\"0\" y=\"0\" width=\"{3}\" height=\"{4}\" fill=\"{5}\"/>\n<g xml:space=\"preserve\">\n",
              view, pic.x, pic.y, pic.width, pic.height, Hex{cx.color(0)});
    else
      w.print("<g id=\"plant\" xml:space=\"preserve\">\n");
    for (const Item& it : pic.items) {
      const Rgba col = itemColor(pic, it);
      const int cls = colorClass(col);
      switch (it.kind) {
        case Item::Triangle: {
          const uint32_t* i = &g.indices[3 * it.index];
          const glm::vec3 &a = pic.win[i[0]], &b = pic.win[i[1]], &c = pic.win[i[2]];
          if (col[3] < 1) {
            flush();
            w.print("<path class=\"f{:x}\" fill-opacity=\"{}\" d=\"M{} {} {} {} {} {}z\"/>\n", cls, num3(col[3]),
                    gridNumber(a.x), gridNumber(a.y), gridNumber(b.x), gridNumber(b.y), gridNumber(c.x), gridNumber(c.y));
            break;
          }
          begin(Triangles, cls, 0);
          const std::array<Point, 3> t{Point{onGrid(a.x), onGrid(a.y)}, Point{onGrid(b.x), onGrid(b.y)},
                                       Point{onGrid(c.x), onGrid(c.y)}};
          if (mergeQuad(t)) {
            flushPending();
          } else {
            flushPending();
            pending.assign(t.begin(), t.end());
          }
          break;
        }
        case Item::Line: {
          const Segment& s = g.segments[it.index];
          const glm::vec3 &a = pic.segmentEnds[2 * it.index], &b = pic.segmentEnds[2 * it.index + 1];
          if (col[3] < 1) {
            flush();
            w.print("<path class=\"l s{:x}\" stroke-width=\"{}\" stroke-opacity=\"{}\" d=\"M{} {} {} {}\"/>\n", cls,
                    num(s.width), num3(col[3]), gridNumber(a.x), gridNumber(a.y), gridNumber(b.x), gridNumber(b.y));
            break;
          }
          begin(Lines, cls, (float)num(s.width).v);
          const Point ends[2] = {{onGrid(a.x), onGrid(a.y)}, {onGrid(b.x), onGrid(b.y)}};
          writePath(ends, 2, false);
          break;
        }
        case Item::Disc:
        case Item::Ring: {
          flush();
          const Picture::Circle& c = pic.circles[it.index];
          if (it.kind == Item::Disc)
            w.print("<circle class=\"f{:x}\" cx=\"{}\" cy=\"{}\" r=\"{}\"/>\n", cls, gridNumber(c.x), gridNumber(c.y), num(c.r));
          else
            w.print("<circle class=\"s{:x}\" fill=\"none\" stroke-width=\"{}\" cx=\"{}\" cy=\"{}\" r=\"{}\"/>\n", cls, num(c.w),
                    gridNumber(c.x), gridNumber(c.y), num(c.r));
          break;
        }
        case Item::Text: {
          flush();
          const Label& l = g.labels[it.index];
          const glm::vec3& p = pic.labelAt[it.index];
          // The renderer's placement: left end at the anchor, baseline 2 px below it.
          w.print("<text class=\"f{:x}\" x=\"{}\" y=\"{}\">{}</text>\n", cls, gridNumber(p.x), gridNumber(p.y + 2),
                  xmlEscape(text::cleanUtf8(l.text, true)));
          break;
        }
      }
    }
    flush();
    w.text(page.multiView ? "</g>\n</svg>\n" : "</g>\n");
  }
  w.text("</svg>\n");
  return w.close();
}

// ---------------------------------------------------------------------------------------------
// PostScript: lpfg's layout — the picture scaled to fit 8 × 10 inches (576 × 720 pt) with an
// 18 pt margin, clipped, background filled with colour 0, `%%BoundingBox` around it. EPS: the
// picture at 1 pt per pixel, bounding box 0 0 width height. Labels are filled glyph outlines, as
// in PDF: the standard fonts' encodings have no room for most of Unicode, and outlines need no
// font in the file or the printer.

llvm::Error writePostScript(const Context& cx, bool eps) {
  const Page page = drawPage(cx);
  const float W = (float)page.width, H = (float)page.height;
  float s, ox, oy, wx, wy;
  int x1, y1, x2, y2;
  if (eps) {
    s = 1, ox = 0, oy = 0, wx = W, wy = H;
    x1 = 0, y1 = 0, x2 = page.width, y2 = page.height;
  } else {
    s = std::min(576.0f / W, 720.0f / H);
    wx = W * s, wy = H * s;
    x1 = (int)std::floor((576 - wx) / 2 + 18);
    y1 = (int)std::floor((720 - wy) / 2 + 18);
    x2 = (int)std::floor(x1 + wx);
    y2 = (int)std::floor(y1 + wy);
    ox = (float)x1, oy = (float)y1;
  }
  const Picture* placed = nullptr;  // the view being drawn: its window coordinates on the page
  auto X = [&](float x) { return num(ox + (float(placed->x) + x) * s); };
  auto Y = [&](float y) { return num(oy + (H - float(placed->y) - y) * s); };
  auto rgb = [&](const Rgba& c) { return fmt::format("{} {} {}", num3(c[0]), num3(c[1]), num3(c[2])); };

  FileWriter w;
  if (auto e = w.open(cx.path)) return e;
  w.text(eps ? "%!PS-Adobe-3.0 EPSF-3.0\n" : "%!PS-Adobe-3.0\n");
  w.print("%%Creator: lcjit\n%%BoundingBox: {} {} {} {}\n", x1, y1, x2, y2);
  if (eps) w.print("%%HiResBoundingBox: 0 0 {} {}\n", num(W), num(H));
  w.print("%%Pages: 1\n%%EndComments\n%%BeginProlog\n");
  w.print("/Tw {} def\n", num3(0.5f * s));
  w.print("% r g b x3 y3 x2 y2 x1 y1 T: filled triangle (outlined by Tw against seams)\n");
  w.print("/T {{ newpath moveto lineto lineto closepath setrgbcolor gsave fill grestore Tw setlinewidth stroke }} bind def\n");
  w.print("% r g b width x2 y2 x1 y1 L: line\n");
  w.print("/L {{ newpath moveto lineto setlinewidth setrgbcolor stroke }} bind def\n");
  w.print("% r g b x y radius D: disc\n/D {{ newpath 0 360 arc setrgbcolor fill }} bind def\n");
  w.print("% r g b width x y radius R: ring\n/R {{ newpath 0 360 arc setlinewidth setrgbcolor stroke }} bind def\n");
  w.print("% labels: glyph outlines (m l c h: moveto lineto curveto closepath)\n");
  w.print("/m /moveto load def /l /lineto load def /c /curveto load def /h /closepath load def\n");
  w.print("%%EndProlog\n%%Page: 1 1\n");
  w.print("{} setlinecap 1 setlinejoin\n", std::clamp(cx.view.postscriptLinecap, 0, 2));
  w.print("newpath {} {} moveto 0 {} rlineto {} 0 rlineto 0 {} rlineto closepath clip\n", x1, y1, num(wy), num(wx),
          num(-wy));
  w.print("{} setrgbcolor fill\n", rgb(page.multiView ? page.border : cx.color(0)));
  LabelGlyphs labels(cx.view);

  for (const Picture& pic : page.pictures) {
    placed = &pic;
    const Geometry& g = *pic.g;
    if (page.multiView)  // the view's rectangle, clipped, in the background colour
      w.print("gsave newpath {} {} moveto {} 0 rlineto 0 {} rlineto {} 0 rlineto closepath clip {} setrgbcolor fill\n",
              X(0), Y(float(pic.height)), num(float(pic.width) * s), num(float(pic.height) * s),
              num(-float(pic.width) * s), rgb(cx.color(0)));
    for (const Item& it : pic.items) {
      switch (it.kind) {
        case Item::Triangle: {
          const uint32_t* i = &g.indices[3 * it.index];
          const glm::vec3 &a = pic.win[i[0]], &b = pic.win[i[1]], &c = pic.win[i[2]];
          w.print("{} {} {} {} {} {} {} T\n", rgb(pic.triangleColor[it.index]), X(c.x), Y(c.y), X(b.x), Y(b.y), X(a.x),
                  Y(a.y));
          break;
        }
        case Item::Line: {
          const Segment& sg = g.segments[it.index];
          const glm::vec3 &a = pic.segmentEnds[2 * it.index], &b = pic.segmentEnds[2 * it.index + 1];
          w.print("{} {} {} {} {} {} L\n", rgb(cx.color(sg.color)), num(sg.width * s), X(b.x), Y(b.y), X(a.x), Y(a.y));
          break;
        }
        case Item::Disc:
        case Item::Ring: {
          const Picture::Circle& c = pic.circles[it.index];
          const std::string col = rgb(cx.color(g.discs[it.index].color));
          if (it.kind == Item::Disc) w.print("{} {} {} {} D\n", col, X(c.x), Y(c.y), num(c.r * s));
          else w.print("{} {} {} {} {} R\n", col, num(c.w * s), X(c.x), Y(c.y), num(c.r * s));
          break;
        }
        case Item::Text: {
          const Label& l = g.labels[it.index];
          const glm::vec3& p = pic.labelAt[it.index];
          w.print("% label: {}\n{} setrgbcolor\n", commentText(l.text), rgb(cx.textColor(l.color)));
          auto at = [&](float x, float y) { return fmt::format("{} {}", X(x), Y(y)); };
          labels.forEach(l, p, [&](const text::GlyphOutline& o, float x, float y) {
            w.text("newpath ");
            outlinePath(o, x, y, [&](const std::string& op) { w.text(op); }, at);
            w.text("fill\n");
          });
          break;
        }
      }
    }
    if (page.multiView) w.text("grestore\n");
  }
  w.print("showpage\n%%Trailer\n%%EOF\n");
  return w.close();
}

// PDF 1.4: the same 2D drawing as SVG/PostScript, one page of W × H points (1 pt per pixel), one
// uncompressed content stream, labels as filled glyph outlines (any script, no font to embed; the
// text itself is in a comment before them). Built in memory for the xref offsets.
llvm::Error writePdf(const Context& cx) {
  const Page page = drawPage(cx);
  const float H = (float)page.height;
  const Picture* placed = nullptr;  // the view being drawn: its window coordinates on the page
  auto X = [&](float x) { return num(float(placed->x) + x); };
  auto Y = [&](float y) { return num(H - float(placed->y) - y); };
  auto rgb = [&](const Rgba& c) { return fmt::format("{} {} {}", num3(c[0]), num3(c[1]), num3(c[2])); };
  LabelGlyphs labels(cx.view);
  fmt::memory_buffer content;
  auto out = [&](std::string_view f, const auto&... args) { fmt::format_to(fmt::appender(content), fmt::runtime(f), args...); };
  out("1 J 1 j {} rg 0 0 {} {} re f\n", rgb(page.multiView ? page.border : cx.color(0)), page.width, page.height);
  // A circle as four Bézier quarter arcs (k = 0.5523 of the radius for the control points).
  auto circle = [&](float cx0, float cy0, float r) {
    const float k = 0.5523f * r;
    out("{} {} m {} {} {} {} {} {} c {} {} {} {} {} {} c {} {} {} {} {} {} c {} {} {} {} {} {} c h\n", num(cx0 + r), num(cy0),
        num(cx0 + r), num(cy0 + k), num(cx0 + k), num(cy0 + r), num(cx0), num(cy0 + r), num(cx0 - k), num(cy0 + r),
        num(cx0 - r), num(cy0 + k), num(cx0 - r), num(cy0), num(cx0 - r), num(cy0 - k), num(cx0 - k), num(cy0 - r),
        num(cx0), num(cy0 - r), num(cx0 + k), num(cy0 - r), num(cx0 + r), num(cy0 - k), num(cx0 + r), num(cy0));
  };
  for (const Picture& pic : page.pictures) {
    placed = &pic;
    const Geometry& g = *pic.g;
    if (page.multiView) {  // the view's rectangle, clipped, in the background colour
      const std::string rect = fmt::format("{} {} {} {} re", pic.x, page.height - pic.y - pic.height, pic.width, pic.height);
      out("q {} W n {} rg {} f\n", rect, rgb(cx.color(0)), rect);
    }
    for (const Item& it : pic.items) {
      switch (it.kind) {
        case Item::Triangle: {
          const uint32_t* i = &g.indices[3 * it.index];
          const glm::vec3 &a = pic.win[i[0]], &b = pic.win[i[1]], &c = pic.win[i[2]];
          const std::string col = rgb(pic.triangleColor[it.index]);
          // Filled and outlined by half a point in its own colour against seams, as in PostScript.
          out("{} rg {} RG 0.5 w {} {} m {} {} l {} {} l h B\n", col, col, X(a.x), Y(a.y), X(b.x), Y(b.y), X(c.x), Y(c.y));
          break;
        }
        case Item::Line: {
          const Segment& sg = g.segments[it.index];
          const glm::vec3 &a = pic.segmentEnds[2 * it.index], &b = pic.segmentEnds[2 * it.index + 1];
          out("{} RG {} w {} {} m {} {} l S\n", rgb(cx.color(sg.color)), num(sg.width), X(a.x), Y(a.y), X(b.x), Y(b.y));
          break;
        }
        case Item::Disc:
        case Item::Ring: {
          const Picture::Circle& c = pic.circles[it.index];
          const std::string col = rgb(cx.color(g.discs[it.index].color));
          if (it.kind == Item::Disc) {
            out("{} rg ", col);
            circle(float(pic.x) + c.x, H - float(pic.y) - c.y, c.r);
            out("f\n");
          } else {
            out("{} RG {} w ", col, num(c.w));
            circle(float(pic.x) + c.x, H - float(pic.y) - c.y, c.r);
            out("S\n");
          }
          break;
        }
        case Item::Text: {
          const Label& l = g.labels[it.index];
          const glm::vec3& p = pic.labelAt[it.index];
          out("% label: {}\n{} rg\n", commentText(l.text), rgb(cx.textColor(l.color)));
          auto at = [&](float x, float y) { return fmt::format("{} {}", X(x), Y(y)); };
          labels.forEach(l, p, [&](const text::GlyphOutline& o, float x, float y) {
            outlinePath(o, x, y, [&](const std::string& op) { content.append(op.data(), op.data() + op.size()); }, at);
            out("f\n");
          });
          break;
        }
      }
    }
    if (page.multiView) out("Q\n");
  }
  std::string pdf = "%PDF-1.4\n";
  std::vector<size_t> offsets;
  auto object = [&](const std::string& body) {
    offsets.push_back(pdf.size());
    pdf += fmt::format("{} 0 obj\n{}\nendobj\n", offsets.size(), body);
  };
  object("<< /Type /Catalog /Pages 2 0 R >>");
  object("<< /Type /Pages /Kids [3 0 R] /Count 1 >>");
  object(fmt::format("<< /Type /Page /Parent 2 0 R /MediaBox [0 0 {} {}] /Contents 4 0 R /Resources << >> >>",
                     page.width, page.height));
  object(fmt::format("<< /Length {} >>\nstream\n{}endstream", content.size(), fmt::to_string(content)));
  size_t xref = pdf.size();
  pdf += fmt::format("xref\n0 {}\n0000000000 65535 f \n", offsets.size() + 1);
  for (size_t o : offsets) pdf += fmt::format("{:010d} 00000 n \n", o);
  pdf += fmt::format("trailer\n<< /Size {} /Root 1 0 R >>\nstartxref\n{}\n%%EOF\n", offsets.size() + 1, xref);
  FileWriter w;
  if (auto e = w.open(cx.path, true)) return e;
  w.text(pdf);
  return w.close();
}

}  // namespace lcjit::runtime::exporting
