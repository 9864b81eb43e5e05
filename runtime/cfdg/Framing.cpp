// A finished expansion framed in a picture (Expander.h): its fit to the picture's size, the
// shapes big enough to be drawn, colour as RGB, the -V picture (SVG), and variation codes.
#include "runtime/cfdg/Expander.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "runtime/cfdg/Paths.h"
#include "runtime/cfdg/Tiling.h"

namespace lcjit::runtime::cfdg {

// ---------------------------------------------------------------------------------------------
// Framing and the -V picture
// ---------------------------------------------------------------------------------------------

Framing frame(const Expansion& e, const ExpandOptions& o, const Bounds* fitTo) {
  const Bounds& bounds = fitTo ? *fitTo : e.bounds;
  const PictureSettings& p = e.picture;
  Framing f;
  f.width = o.width;
  f.height = o.height;
  // A tiled or sized picture took the frame's shape at the start; a frieze takes it now, from its
  // final bounds. Their fits are exact (no change of parity to keep the picture centred).
  const bool exact = p.tiled || p.sized || p.frieze;
  if (p.tiled || p.sized) f.width = p.width, f.height = p.height;
  if (p.frieze && bounds.valid() && !o.animation) {
    Fit once = fitBounds(bounds, f.width, f.height, p.borderX, p.borderY, true);
    f.width = once.width, f.height = once.height;
  }
  f.fit = fitBounds(bounds, f.width, f.height, p.borderX, p.borderY, exact);
  f.offsetX = double((f.width - f.fit.width) / 2);
  f.offsetY = double((f.height - f.fit.height) / 2);
  f.toPixels = f.fit.toBlock;
  f.toPixels.multiply(Affine::translation(f.offsetX, f.offsetY));
  if (p.tiled || p.frieze) frameLattice(f, p);
  return f;
}

bool drawn(const FinishedShape& s, const Framing& f, const ExpandOptions& o) {
  if (f.times && !(*f.times)[size_t(s.order - 1)].overlaps(f.window))
    return false;
  if (s.shape == 3)
    return true;
  double minSize = o.minimumSize <= 0 ? 0.3 : o.minimumSize;
  double a = s.boxArea * (f.fit.scale * f.fit.scale);
  return std::isfinite(a) && a >= minSize * minSize;
}

void rgbOf(const double hsba[4], double rgba[4]) {
  double h = hsba[0], s = hsba[1], v = hsba[2];
  double q = h / 60.0, whole, frac = std::modf(q, &whole);
  for (int tries = 0; tries < 2 && (whole <= -0.1 || whole >= 5.1 || frac < 0.0); ++tries) {
    q = std::fmod(q, 6.0);
    if (q < 0.0) q += 6.0;
    frac = std::modf(q, &whole);
  }
  int hextant = int(whole + 0.5);
  double p = v * (1 - s), qq = v * (1 - s * frac), t = v * (1 - s * (1 - frac));
  double r = 0, g = 0, b = 0;
  switch (hextant) {
    case 0: r = v, g = t, b = p; break;
    case 1: r = qq, g = v, b = p; break;
    case 2: r = p, g = v, b = t; break;
    case 3: r = p, g = qq, b = v; break;
    case 4: r = t, g = p, b = v; break;
    default: r = v, g = p, b = qq; break;
  }
  rgba[0] = r, rgba[1] = g, rgba[2] = b, rgba[3] = hsba[3];
}

namespace {

// One shape of the -V picture, with its matrix into SVG's pixels. Its colour is rounded as the
// picture's depth rounds it (16 bits: the fill shows the high byte).
void svgShape(std::string& out, const FinishedShape& s, const double* rgba, const Affine& m, bool depth16,
              int& precision) {
  char line[512];
  const double top = depth16 ? 65535.0 : 255.0;
  auto level = [&](double v) { return unsigned(v * top + 0.5); };
  auto byte = [&](double v) { return depth16 ? level(v) >> 8 : level(v); };
  char fill[64];
  std::snprintf(fill, sizeof fill, "#%02x%02x%02x", byte(rgba[0]), byte(rgba[1]), byte(rgba[2]));
  std::string opacity;
  if (level(rgba[3]) != unsigned(top)) {
    char a[64];
    std::snprintf(a, sizeof a, " fill-opacity=\"%.*g\"", precision, level(rgba[3]) / top);
    opacity = a;
  }
  const char* element = s.shape == 0   ? "<circle r=\"0.5\""
                        : s.shape == 1 ? "<rect x=\"-0.5\" y=\"-0.5\" width=\"1\" height=\"1\""
                                       : "<use xlink:href=\"#TRIANGLE\"";
  std::snprintf(line, sizeof line,
                "  %s\n        stroke=\"none\" fill=\"%s\"%s fill-rule=\"nonzero\"\n"
                "        transform=\"matrix(%.8g %.8g %.8g %.8g %.8g %.8g)\"/>\n",
                element, fill, opacity.c_str(), m.sx, m.shy, m.shx, m.sy, m.tx, m.ty);
  out += line;
  precision = 8;  // cfdg's stream keeps the precision its first transform set
}

}  // namespace

std::string svgOf(const Expansion& e, const Framing& f, const ExpandOptions& o) {
  std::string out;
  char line[512];
  std::snprintf(line, sizeof line,
                "<?xml version=\"1.0\" standalone=\"no\"?>\n<svg width=\"%dpx\" height=\"%dpx\" version=\"1.1\"\n"
                "     xmlns=\"http://www.w3.org/2000/svg\" xmlns:xlink=\"http://www.w3.org/1999/xlink\">\n"
                "  <defs>\n    <polygon id=\"TRIANGLE\" points=\"0,0.57735 -0.5,-0.288675 0.5,-0.288675\"/>\n  </defs>\n",
                f.width, f.height);
  out += line;
  // SVG's y axis points down: the picture is flipped about its height, then the fitted block
  // placed in it.
  Affine toSvg{1, 0, 0, -1, 0, double(f.height)};
  toSvg.multiply(Affine::translation((f.width - f.fit.width) / 2.0, (f.height - f.fit.height) / 2.0));
  std::unique_ptr<PathEngine> paths;
  int nextPathId = 1;
  int precision = 6;  // cfdg's stream: 6 significant digits until the first transform is written
  for (const FinishedShape& s : e.shapes) {
    if (s.shape == kPathShape && drawn(s, f, o)) {
      if (!paths) paths = std::make_unique<PathEngine>(*e.design);
      out += paths->svg(e.paths[size_t(s.path)], e, f, copyOffsets(e, f, s), toSvg, nextPathId, precision);
      continue;
    }
    if (s.shape == 3 || !drawn(s, f, o))
      continue;
    const double* rgba = e.colours[s.colour].data();
    forEachCopy(e, f, s, toSvg, [&](const Affine& m) { svgShape(out, s, rgba, m, e.picture.depth16, precision); });
  }
  out += "</svg>\n";
  return out;
}

uint64_t variationOf(const std::string& code) {
  size_t i = 0;
  while (i < code.size() && code[i] == ' ') ++i;
  if (i == code.size() || !std::isalnum(static_cast<unsigned char>(code[i])))
    return 0;
  if (std::isdigit(static_cast<unsigned char>(code[i])))
    return std::strtoull(code.c_str() + i, nullptr, 0);
  uint64_t value = 0, base = 0, power = 1;
  size_t length = 0;
  for (; i < code.size() && std::isalpha(static_cast<unsigned char>(code[i])); ++i, ++length)
    value = value * 26 + uint64_t(std::toupper(static_cast<unsigned char>(code[i])) - 'A');
  for (size_t k = 1; k < length; ++k) base += (power *= 26);
  return value + base + 1;
}

std::string variationName(uint64_t v) {
  std::string name;
  // Bijective base 26: A = 1 … Z = 26, AA = 27.
  while (v > 0) {
    --v;
    name.insert(name.begin(), char('A' + v % 26));
    v /= 26;
  }
  return name;
}
}  // namespace lcjit::runtime::cfdg
