// A design's picture as a vector page (VectorPage.h). One painter (Picture.h's ShapePainter)
// writes the page's drawing operators; PDF and PostScript differ only in their spelling and in
// what wraps them (PDF's objects and cross-reference table, PostScript's DSC header).
#include "runtime/cfdg/VectorPage.h"

#include <cmath>
#include <cstdio>
#include <map>
#include <vector>

#include "runtime/cfdg/Picture.h"

namespace lcjit::runtime::cfdg {
namespace {

// The operators of the two languages, by what they do.
struct Spelling {
  const char *moveTo, *lineTo, *curveTo, *close, *fill, *evenOddFill, *stroke, *save, *restore;
};
constexpr Spelling kPdf{"m", "l", "c", "h", "f", "f*", "S", "q", "Q"};
constexpr Spelling kPostScript{"moveto", "lineto", "curveto", "closepath", "fill", "eofill", "stroke", "gsave", "grestore"};

class PageWriter final : public ShapePainter {
 public:
  PageWriter(PageFormat format, int width, int height)
      : format_(format), s_(format == PageFormat::Pdf ? kPdf : kPostScript), width_(width), height_(height) {}

  void background(const Rgba& c) {
    if (c.a <= 0) return;  // a transparent background: the page's own
    colour(c, false);
    rectangle(0, 0, width_, height_);
    op(s_.fill);
  }

  void draw(const CanvasShape& shape) override {
    if (shape.primitive == Primitive::Fill) {  // the whole picture, in the shape's colour
      op(s_.save);
      colour(shape.colour, false);
      rectangle(0, 0, width_, height_);
      op(s_.fill);
      op(s_.restore);
      return;
    }
    op(s_.save);
    transform(shape.toPixels);
    colour(shape.colour, false);
    if (shape.primitive == Primitive::Square) {
      rectangle(-0.5, -0.5, 1, 1);
    } else if (shape.primitive == Primitive::Triangle) {
      // Context Free's unit triangle: centred on its centroid, side 1.
      point(0, 0.57735026918962573, s_.moveTo);
      point(-0.5, -0.28867513459481287, s_.lineTo);
      point(0.5, -0.28867513459481287, s_.lineTo);
      op(s_.close);
    } else {
      circle();
    }
    op(s_.fill);
    op(s_.restore);
  }

  void drawPath(const std::vector<PathVertex>& outline, const PathStyle& style, const Affine& toPixels,
                const Rgba& colour, int) override {
    op(s_.save);
    // A stroke of CF::IsoWidth is drawn on the outline in pixels, its width scaled by the
    // transform's mean scale; any other in the path's own units, transformed (so a non-uniform
    // transform stretches the width, as AGG strokes it).
    const bool inPixels = style.stroke && style.isoWidth;
    if (!inPixels) transform(toPixels);
    this->colour(colour, style.stroke);
    outlinePath(outline, inPixels ? &toPixels : nullptr);
    if (!style.stroke) {
      op(style.evenOdd ? s_.evenOddFill : s_.fill);
    } else {
      const double width = inPixels ? style.width * std::sqrt(std::fabs(toPixels.determinant())) : style.width;
      // AGG's joins (miter 0, round 2, bevel 3) and caps (butt 0, square 1, round 2) in the
      // page's numbering (joins: miter 0, round 1, bevel 2; caps: butt 0, round 1, square 2).
      const int join = style.join == 2 ? 1 : style.join == 3 ? 2 : 0;
      const int cap = style.cap == 1 ? 2 : style.cap == 2 ? 1 : 0;
      char line[160];
      if (format_ == PageFormat::Pdf)
        std::snprintf(line, sizeof line, "%.6g w %d j %d J %.6g M\n", width, join, cap, style.miterLimit);
      else
        std::snprintf(line, sizeof line, "%.6g setlinewidth %d setlinejoin %d setlinecap %.6g setmiterlimit\n", width,
                      join, cap, style.miterLimit);
      text_ += line;
      op(s_.stroke);
    }
    op(s_.restore);
  }

  // The finished file.
  std::string page() const {
    return format_ == PageFormat::Pdf ? pdf() : postscript();
  }

 private:
  void op(const char* name) {
    text_ += name;
    text_ += '\n';
  }
  void number(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.8g ", std::fabs(v) < 1e-12 ? 0.0 : v);
    text_ += b;
  }
  void point(double x, double y, const char* how) {
    number(x);
    number(y);
    op(how);
  }
  void rectangle(double x, double y, double w, double h) {
    point(x, y, s_.moveTo);
    point(x + w, y, s_.lineTo);
    point(x + w, y + h, s_.lineTo);
    point(x, y + h, s_.lineTo);
    op(s_.close);
  }
  void circle() {
    // Radius 0.5 as four cubic arcs (the control points 0.5·4/3·(√2 − 1) along the tangents).
    const double r = 0.5, k = r * 0.55228474983079339;
    point(r, 0, s_.moveTo);
    curve(r, k, k, r, 0, r);
    curve(-k, r, -r, k, -r, 0);
    curve(-r, -k, -k, -r, 0, -r);
    curve(k, -r, r, -k, r, 0);
    op(s_.close);
  }
  void curve(double x1, double y1, double x2, double y2, double x, double y) {
    number(x1), number(y1), number(x2), number(y2), number(x), number(y);
    op(s_.curveTo);
  }
  void transform(const Affine& a) {
    if (format_ == PageFormat::Pdf) {
      number(a.sx), number(a.shy), number(a.shx), number(a.sy), number(a.tx), number(a.ty);
      op("cm");
    } else {
      text_ += "[";
      number(a.sx), number(a.shy), number(a.shx), number(a.sy), number(a.tx), number(a.ty);
      text_ += "] concat\n";
    }
  }
  void colour(const Rgba& c, bool stroke) {
    auto clamp = [](double v) { return v < 0 ? 0.0 : v > 1 ? 1.0 : v; };
    number(clamp(c.r)), number(clamp(c.g)), number(clamp(c.b));
    op(format_ == PageFormat::PostScript ? "setrgbcolor" : stroke ? "RG" : "rg");
    if (format_ != PageFormat::Pdf) return;
    // Alpha through a graphics state of the page's resources, one per alpha used.
    const int alpha = int(std::lround(clamp(c.a) * 1000));
    auto [it, added] = alphas_.try_emplace(alpha, int(alphas_.size()));
    (void)added;
    text_ += "/A" + std::to_string(it->second) + " gs\n";
  }
  // A path command's outline: AGG's commands as the page's (a quadratic curve as the cubic that
  // draws it), through `toPixels` when given.
  void outlinePath(const std::vector<PathVertex>& outline, const Affine* toPixels) {
    double cx = 0, cy = 0, startX = 0, startY = 0;
    auto at = [&](const PathVertex& v) {
      double x = v.x, y = v.y;
      if (toPixels) toPixels->apply(x, y);
      return std::pair(x, y);
    };
    for (size_t i = 0; i < outline.size(); ++i) {
      const PathVertex& v = outline[i];
      const unsigned command = v.command & 0x0F;
      if (command == kMoveTo) {
        std::tie(cx, cy) = at(v);
        startX = cx, startY = cy;
        point(cx, cy, s_.moveTo);
      } else if (command == kLineTo) {
        std::tie(cx, cy) = at(v);
        point(cx, cy, s_.lineTo);
      } else if (command == kCurve3 && i + 1 < outline.size()) {
        auto [qx, qy] = at(v);
        auto [x, y] = at(outline[++i]);
        curve(cx + 2.0 / 3.0 * (qx - cx), cy + 2.0 / 3.0 * (qy - cy), x + 2.0 / 3.0 * (qx - x), y + 2.0 / 3.0 * (qy - y), x, y);
        cx = x, cy = y;
      } else if (command == kCurve4 && i + 2 < outline.size()) {
        auto [x1, y1] = at(v);
        auto [x2, y2] = at(outline[++i]);
        auto [x, y] = at(outline[++i]);
        curve(x1, y1, x2, y2, x, y);
        cx = x, cy = y;
      } else if (command == kEndPoly && (v.command & kClose)) {
        op(s_.close);
        cx = startX, cy = startY;
      }
    }
  }

  std::string pdf() const {
    std::string resources = "<< ";
    if (!alphas_.empty()) {
      resources += "/ExtGState << ";
      for (const auto& [alpha, n] : alphas_) {
        char b[80];
        std::snprintf(b, sizeof b, "/A%d << /ca %.3f /CA %.3f >> ", n, alpha / 1000.0, alpha / 1000.0);
        resources += b;
      }
      resources += ">> ";
    }
    resources += ">>";
    std::vector<std::string> objects = {
        "<< /Type /Catalog /Pages 2 0 R >>",
        "<< /Type /Pages /Kids [3 0 R] /Count 1 >>",
        "<< /Type /Page /Parent 2 0 R /MediaBox [0 0 " + std::to_string(width_) + " " + std::to_string(height_) +
            "] /Contents 4 0 R /Resources " + resources + " >>",
        "<< /Length " + std::to_string(text_.size()) + " >>\nstream\n" + text_ + "endstream",
    };
    std::string out = "%PDF-1.4\n";
    std::vector<size_t> offsets;
    for (size_t i = 0; i < objects.size(); ++i) {
      offsets.push_back(out.size());
      out += std::to_string(i + 1) + " 0 obj\n" + objects[i] + "\nendobj\n";
    }
    const size_t xref = out.size();
    out += "xref\n0 " + std::to_string(objects.size() + 1) + "\n0000000000 65535 f \n";
    for (size_t o : offsets) {
      char b[24];
      std::snprintf(b, sizeof b, "%010zu 00000 n \n", o);
      out += b;
    }
    out += "trailer\n<< /Size " + std::to_string(objects.size() + 1) + " /Root 1 0 R >>\nstartxref\n" +
           std::to_string(xref) + "\n%%EOF\n";
    return out;
  }

  std::string postscript() const {
    const std::string size = std::to_string(width_) + " " + std::to_string(height_);
    return "%!PS-Adobe-3.0 EPSF-3.0\n%%Creator: lcjit\n%%BoundingBox: 0 0 " + size + "\n%%Pages: 1\n%%EndComments\n" +
           "%%Page: 1 1\n" + text_ + "showpage\n%%EOF\n";
  }

  PageFormat format_;
  const Spelling& s_;
  int width_, height_;
  std::string text_;
  std::map<int, int> alphas_;  // alpha × 1000 → its graphics state's number
};

}  // namespace

std::string vectorPage(const __cf_Design& design, const Expansion& e, const Framing& f, const ExpandOptions& o,
                       PageFormat format) {
  PageWriter page(format, f.width, f.height);
  page.background(deviceColour(e.background));
  paintShapes(design, e, f, o, page);
  return page.page();
}

}  // namespace lcjit::runtime::cfdg
