// The 2D picture: SVG and PostScript/EPS. Everything is projected with the renderer's framing
// (frameView / projectToWindow) and drawn back to front (painter's algorithm, by mean depth), in
// flat palette colours like lpfg's PostScript output.
#include <algorithm>
#include <cmath>

#include "runtime/export/ExportCommon.h"
#include "runtime/export/ExportFormats.h"

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

struct Picture {
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

Picture draw(const Context& cx) {
  Picture pic;
  const CameraMatrices& cam = cx.camera();
  pic.width = cam.width;
  pic.height = cam.height;
  const Geometry& g = cx.geometry;
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

std::string psEscape(std::string_view s) {
  std::string out;
  for (char c : s) {
    unsigned char u = (unsigned char)c;
    if (c == '(' || c == ')' || c == '\\') {
      out += '\\';
      out += c;
    } else if (u < 0x20 || u >= 0x7f) {
      out += fmt::format("\\{:03o}", u);
    } else {
      out += c;
    }
  }
  return out;
}

// A PostScript standard font for the view file's `winfont:` (lpfg's labels use it too).
std::string psFontName(const ViewSettings& v) {
  std::string family = v.winFont;
  std::string lower;
  for (char c : family) lower += (char)std::tolower((unsigned char)c);
  bool bold = v.winFontBold(), italic = v.winFontItalic;
  std::string base, slant = "Oblique";
  if (lower.find("times") != std::string::npos || lower.find("serif") == 0) base = "Times", slant = "Italic";
  else if (lower.find("courier") != std::string::npos || lower.find("mono") != std::string::npos) base = "Courier";
  else base = "Helvetica";
  if (base == "Times" && !bold && !italic) return "Times-Roman";
  if (!bold && !italic) return base;
  return base + "-" + (bold ? "Bold" : "") + (italic ? slant : "");
}

}  // namespace

// ---------------------------------------------------------------------------------------------

llvm::Error writeSvg(const Context& cx) {
  Picture pic = draw(cx);
  const Geometry& g = cx.geometry;
  FileWriter w;
  if (auto e = w.open(cx.path)) return e;
  w.print("<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"no\"?>\n<!-- written by lcjit -->\n");
  w.print("<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"{0}\" height=\"{1}\" viewBox=\"0 0 {0} {1}\">\n",
          pic.width, pic.height);
  // Polygons get a hairline of their own colour so anti-aliasing leaves no seams between them.
  w.print("<style>polygon{{stroke-width:0.5px;stroke-linejoin:round}} line{{stroke-linecap:butt}}</style>\n");
  w.print("<rect id=\"background\" x=\"0\" y=\"0\" width=\"{}\" height=\"{}\" fill=\"{}\"/>\n", pic.width, pic.height,
          Hex{cx.color(0)});
  const std::string font = xmlEscape(cx.view.winFont);
  w.print("<g id=\"plant\">\n");
  for (const Item& it : pic.items) {
    switch (it.kind) {
      case Item::Triangle: {
        const uint32_t* i = &g.indices[3 * it.index];
        const glm::vec3 &a = pic.win[i[0]], &b = pic.win[i[1]], &c = pic.win[i[2]];
        const Rgba& col = pic.triangleColor[it.index];
        w.print("<polygon points=\"{},{} {},{} {},{}\" fill=\"{}\"", num(a.x), num(a.y), num(b.x), num(b.y), num(c.x),
                num(c.y), Hex{col});
        if (col[3] < 1) w.print(" fill-opacity=\"{}\" stroke=\"none\"/>\n", num3(col[3]));
        else w.print(" stroke=\"{}\"/>\n", Hex{col});
        break;
      }
      case Item::Line: {
        const Segment& s = g.segments[it.index];
        const glm::vec3 &a = pic.segmentEnds[2 * it.index], &b = pic.segmentEnds[2 * it.index + 1];
        const Rgba& col = cx.color(s.color);
        w.print("<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"{}\" stroke-width=\"{}\"", num(a.x), num(a.y),
                num(b.x), num(b.y), Hex{col}, num(s.width));
        if (col[3] < 1) w.print(" stroke-opacity=\"{}\"", num3(col[3]));
        w.text("/>\n");
        break;
      }
      case Item::Disc:
      case Item::Ring: {
        const Picture::Circle& c = pic.circles[it.index];
        const Rgba& col = cx.color(g.discs[it.index].color);
        if (it.kind == Item::Disc)
          w.print("<circle cx=\"{}\" cy=\"{}\" r=\"{}\" fill=\"{}\"/>\n", num(c.x), num(c.y), num(c.r), Hex{col});
        else
          w.print("<circle cx=\"{}\" cy=\"{}\" r=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"{}\"/>\n", num(c.x),
                  num(c.y), num(c.r), Hex{col}, num(c.w));
        break;
      }
      case Item::Text: {
        const Label& l = g.labels[it.index];
        const glm::vec3& p = pic.labelAt[it.index];
        w.print("<text x=\"{}\" y=\"{}\" fill=\"{}\" font-family=\"{}\" font-size=\"{}\"{}{} xml:space=\"preserve\">{}</text>\n",
                num(p.x), num(p.y), Hex{cx.palette.textColor(l.color)}, font, cx.view.winFontSize,
                cx.view.winFontBold() ? " font-weight=\"bold\"" : "", cx.view.winFontItalic ? " font-style=\"italic\"" : "",
                xmlEscape(l.text));
        break;
      }
    }
  }
  w.print("</g>\n</svg>\n");
  return w.close();
}

// ---------------------------------------------------------------------------------------------
// PostScript: lpfg's layout — the picture scaled to fit 8 × 10 inches (576 × 720 pt) with an
// 18 pt margin, clipped, background filled with colour 0, `%%BoundingBox` around it. EPS: the
// picture at 1 pt per pixel, bounding box 0 0 width height.

llvm::Error writePostScript(const Context& cx, bool eps) {
  Picture pic = draw(cx);
  const Geometry& g = cx.geometry;
  const float W = (float)pic.width, H = (float)pic.height;
  float s, ox, oy, wx, wy;
  int x1, y1, x2, y2;
  if (eps) {
    s = 1, ox = 0, oy = 0, wx = W, wy = H;
    x1 = 0, y1 = 0, x2 = pic.width, y2 = pic.height;
  } else {
    s = std::min(576.0f / W, 720.0f / H);
    wx = W * s, wy = H * s;
    x1 = (int)std::floor((576 - wx) / 2 + 18);
    y1 = (int)std::floor((720 - wy) / 2 + 18);
    x2 = (int)std::floor(x1 + wx);
    y2 = (int)std::floor(y1 + wy);
    ox = (float)x1, oy = (float)y1;
  }
  auto X = [&](float x) { return num(ox + x * s); };
  auto Y = [&](float y) { return num(oy + (H - y) * s); };
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
  w.print("%%EndProlog\n%%Page: 1 1\n");
  w.print("{} setlinecap 1 setlinejoin\n", std::clamp(cx.view.postscriptLinecap, 0, 2));
  w.print("newpath {} {} moveto 0 {} rlineto {} 0 rlineto 0 {} rlineto closepath clip\n", x1, y1, num(wy), num(wx),
          num(-wy));
  w.print("{} setrgbcolor fill\n", rgb(cx.color(0)));
  if (!g.labels.empty())
    w.print("/{} findfont {} scalefont setfont\n", psFontName(cx.view), num(cx.view.winFontSize * s));

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
        w.print("{} setrgbcolor {} {} moveto ({}) show\n", rgb(cx.palette.textColor(l.color)), X(p.x), Y(p.y), psEscape(l.text));
        break;
      }
    }
  }
  w.print("showpage\n%%Trailer\n%%EOF\n");
  return w.close();
}

// PDF 1.4: the same 2D drawing as SVG/PostScript, one page of W × H points (1 pt per pixel), one
// uncompressed content stream, labels in the standard Helvetica. Built in memory for the xref
// offsets.
llvm::Error writePdf(const Context& cx) {
  Picture pic = draw(cx);
  const Geometry& g = cx.geometry;
  const float H = (float)pic.height;
  auto X = [&](float x) { return num(x); };
  auto Y = [&](float y) { return num(H - y); };
  auto rgb = [&](const Rgba& c) { return fmt::format("{} {} {}", num3(c[0]), num3(c[1]), num3(c[2])); };
  fmt::memory_buffer content;
  auto out = [&](std::string_view f, const auto&... args) { fmt::format_to(fmt::appender(content), fmt::runtime(f), args...); };
  out("1 J 1 j {} rg 0 0 {} {} re f\n", rgb(cx.color(0)), pic.width, pic.height);
  // A circle as four Bézier quarter arcs (k = 0.5523 of the radius for the control points).
  auto circle = [&](float cx0, float cy0, float r) {
    const float k = 0.5523f * r;
    out("{} {} m {} {} {} {} {} {} c {} {} {} {} {} {} c {} {} {} {} {} {} c {} {} {} {} {} {} c h\n", num(cx0 + r), num(cy0),
        num(cx0 + r), num(cy0 + k), num(cx0 + k), num(cy0 + r), num(cx0), num(cy0 + r), num(cx0 - k), num(cy0 + r),
        num(cx0 - r), num(cy0 + k), num(cx0 - r), num(cy0), num(cx0 - r), num(cy0 - k), num(cx0 - k), num(cy0 - r),
        num(cx0), num(cy0 - r), num(cx0 + k), num(cy0 - r), num(cx0 + r), num(cy0 - k), num(cx0 + r), num(cy0));
  };
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
          circle(c.x, H - c.y, c.r);
          out("f\n");
        } else {
          out("{} RG {} w ", col, num(c.w));
          circle(c.x, H - c.y, c.r);
          out("S\n");
        }
        break;
      }
      case Item::Text: {
        const Label& l = g.labels[it.index];
        const glm::vec3& p = pic.labelAt[it.index];
        out("BT /F1 {} Tf {} rg {} {} Td ({}) Tj ET\n", num(cx.view.winFontSize), rgb(cx.palette.textColor(l.color)),
            X(p.x), Y(p.y), psEscape(l.text));
        break;
      }
    }
  }
  std::string pdf = "%PDF-1.4\n";
  std::vector<size_t> offsets;
  auto object = [&](const std::string& body) {
    offsets.push_back(pdf.size());
    pdf += fmt::format("{} 0 obj\n{}\nendobj\n", offsets.size(), body);
  };
  object("<< /Type /Catalog /Pages 2 0 R >>");
  object("<< /Type /Pages /Kids [3 0 R] /Count 1 >>");
  object(fmt::format("<< /Type /Page /Parent 2 0 R /MediaBox [0 0 {} {}] /Contents 4 0 R "
                     "/Resources << /Font << /F1 5 0 R >> >> >>",
                     pic.width, pic.height));
  object(fmt::format("<< /Length {} >>\nstream\n{}endstream", content.size(), fmt::to_string(content)));
  object("<< /Type /Font /Subtype /Type1 /BaseFont /Helvetica >>");
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
